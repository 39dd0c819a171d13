//! Sleep: an island (dynamic bodies touching through dynamic bodies, see
//! [`tumble_solver::Islands`]) whose bodies have all stayed slow for [`TIME_TO_SLEEP`] leaves
//! the step. A sleeping island is out of the narrow phase and the solver, and pairs between
//! sleeping and fixed bodies are never formed; it wakes when an awake body touches it (a
//! manifold with one of its bodies, speculative points included), when a moving kinematic body's box reaches it, or when the
//! user sets a pose or a velocity, applies an impulse, or removes one of its bodies.
//!
//! While some bodies sleep, the step runs on a gathered copy: the awake bodies, then the
//! sleeping ones as fixed obstacles. An awake body that reaches a sleeping one meets it as
//! fixed for that one step and wakes its island for the next (Box2D does the same: a touch
//! wakes the island, which rejoins the solver on the following step).
//!
//! On `Backend::Gpu` the islands are found and put to sleep on the GPU (`tumble_gpu::sleep`,
//! label propagation instead of union-find, the same thresholds); `is_sleeping` and
//! `sleeping_count` read its flags back lazily like any other result. `Backend::Hybrid` steps
//! every body, and its bodies never sleep.

use std::collections::HashSet;

use tumble_broad::SweepAndPrune;
use tumble_geometry::{Aabb, Real, Vec3};
use tumble_solver::{Body, BodyKind, BodyState, Contact, Effects, Islands, PairKey};

use crate::{BodyHandle, Error, StepStats, World, stages};

pub use tumble_solver::{ANGULAR_SLEEP_TOLERANCE, LINEAR_SLEEP_TOLERANCE, TIME_TO_SLEEP};

/// Island label of an awake body.
const AWAKE: u32 = u32::MAX;

/// Per-body sleep data (dense order, parallel to the world's body arrays) and the contacts of
/// the sleeping islands.
#[derive(Clone, Debug, Default)]
pub(crate) struct SleepState {
    /// Time each body has stayed below the sleep tolerances, s.
    rest_time: Vec<Real>,
    /// The sleeping island of each body, or [`AWAKE`].
    island: Vec<u32>,
    /// Label for the next island to fall asleep.
    next_island: u32,
    /// Bodies asleep.
    asleep: usize,
    /// The manifolds of sleeping islands, kept for contact reports and warm starting.
    pub(crate) contacts: Vec<(Contact, PairKey, (BodyHandle, BodyHandle))>,
    /// The broad phase's buffers for the gathered step.
    sap: SweepAndPrune,
}

impl SleepState {
    /// A body appended to the world: awake, not resting.
    pub(crate) fn push(&mut self) {
        self.rest_time.push(0.0);
        self.island.push(AWAKE);
    }

    /// The body at `d` is removed by `swap_remove`: its island wakes first (it loses a body).
    pub(crate) fn swap_remove(&mut self, d: usize) {
        self.wake(d);
        self.rest_time.swap_remove(d);
        self.island.swap_remove(d);
    }

    /// True when the body at `d` sleeps.
    pub(crate) fn is_asleep(&self, d: usize) -> bool {
        self.island.get(d).is_some_and(|&i| i != AWAKE)
    }

    /// Wakes the island of the body at `d` (nothing when it is awake) and resets its rest time.
    pub(crate) fn wake(&mut self, d: usize) {
        let Some(&label) = self.island.get(d) else {
            return;
        };
        self.rest_time[d] = 0.0;
        if label == AWAKE {
            return;
        }
        for (island, rest) in self.island.iter_mut().zip(&mut self.rest_time) {
            if *island == label {
                *island = AWAKE;
                *rest = 0.0;
                self.asleep -= 1;
            }
        }
    }
}

impl World {
    /// True when the body sleeps (it is out of the step until something wakes its island).
    pub fn is_sleeping(&self, h: BodyHandle) -> Result<bool, Error> {
        let d = self.handles.dense(h)?;
        match self.gpu_sleeping()? {
            Some(flags) => Ok(flags[d]),
            None => Ok(self.sleep.is_asleep(d)),
        }
    }

    /// Bodies asleep.
    pub fn sleeping_count(&self) -> usize {
        match self.gpu_sleeping() {
            Ok(Some(flags)) => flags.iter().filter(|&&s| s).count(),
            // A failed read reports its error from the next step.
            Err(_) => 0,
            Ok(None) => self.sleep.asleep,
        }
    }

    /// Wakes the body's island (a no-op for an awake body).
    pub fn wake_up(&mut self, h: BodyHandle) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        self.wake_on_gpu(d)?;
        self.sleep.wake(d);
        Ok(())
    }

    /// After a step: rest timers, islands of the awake bodies, and the islands that fall asleep.
    pub(crate) fn update_sleep(&mut self, effects: &Effects) {
        let dt = self.config.dt;
        let sleep = &mut self.sleep;
        for (d, (body, state)) in self.bodies.iter().zip(&self.states).enumerate() {
            let resting = state.linear_velocity.norm() < LINEAR_SLEEP_TOLERANCE
                && state.angular_velocity.norm() < ANGULAR_SLEEP_TOLERANCE;
            sleep.rest_time[d] = match body.kind {
                BodyKind::Dynamic if resting => sleep.rest_time[d] + dt,
                _ => 0.0,
            };
        }
        // A body carried or pushed by a moving kinematic body stays awake.
        if effects.kinematic {
            for c in &self.contacts {
                let (a, b) = (c.body_a as usize, c.body_b as usize);
                let moving = |i: usize| {
                    self.bodies[i].kind == BodyKind::Kinematic
                        && (self.states[i].linear_velocity != Vec3::zeros()
                            || self.states[i].angular_velocity != Vec3::zeros())
                };
                if moving(a) || moving(b) {
                    sleep.rest_time[a] = 0.0;
                    sleep.rest_time[b] = 0.0;
                }
            }
        }
        let awake_dynamic: Vec<bool> = self
            .bodies
            .iter()
            .zip(&sleep.island)
            .map(|(b, &i)| b.is_dynamic() && i == AWAKE)
            .collect();
        // Every manifold links, speculative ones too, as a manifold with a sleeping body wakes
        // it: were the two rules different, two neighbours a few millimetres apart would wake
        // each other in turn forever (Box2D v3 links on the same condition it wakes on).
        let links = self.contacts.iter().map(|c| (c.body_a, c.body_b));
        let islands = Islands::build(&awake_dynamic, links);
        // The shortest rest of each island (indexed by its label, a body index).
        let mut shortest = vec![Real::INFINITY; self.bodies.len()];
        for (d, &label) in islands.label.iter().enumerate() {
            if awake_dynamic[d] {
                let s = &mut shortest[label as usize];
                *s = s.min(sleep.rest_time[d]);
            }
        }
        let mut any_asleep = false;
        for (d, (&label, &awake)) in islands.label.iter().zip(&awake_dynamic).enumerate() {
            if awake && shortest[label as usize] >= TIME_TO_SLEEP {
                // Wrapping, the label could only meet AWAKE after four billion bodies fell
                // asleep; it is moved off it all the same.
                let id = sleep.next_island.wrapping_add(label);
                sleep.island[d] = if id == AWAKE { 0 } else { id };
                self.states[d].linear_velocity = Vec3::zeros();
                self.states[d].angular_velocity = Vec3::zeros();
                sleep.asleep += 1;
                any_asleep = true;
            }
        }
        if !any_asleep {
            return;
        }
        // Labels are body indices, so offsetting by the body count keeps them unique.
        sleep.next_island = sleep.next_island.wrapping_add(self.bodies.len() as u32);
        let handles = self.handles.handles();
        let kept: HashSet<(BodyHandle, BodyHandle)> =
            sleep.contacts.iter().map(|(_, _, h)| *h).collect();
        for (c, &(ha, hb)) in self.contacts.iter().zip(&self.contact_handles) {
            let (a, b) = (c.body_a as usize, c.body_b as usize);
            let involved = sleep.island[a] != AWAKE || sleep.island[b] != AWAKE;
            if involved && !kept.contains(&(ha, hb)) {
                let key = (handles[a].to_bits(), handles[b].to_bits());
                sleep.contacts.push((*c, key, (ha, hb)));
            }
        }
    }

    /// The step while some bodies sleep (returns `None` when none does, for the full step).
    pub(crate) fn step_with_sleepers(&mut self, effects: &Effects) -> Option<StepStats> {
        if !effects.sleep || self.sleep.asleep == 0 {
            return None;
        }
        let dt = self.config.dt;
        // Sleeping contacts whose islands woke rejoin the narrow phase through the cache.
        let island = &self.sleep.island;
        let handles_map = &self.handles;
        self.sleep.contacts.retain(|(_, _, (a, b))| {
            let asleep = |h: &BodyHandle| handles_map.dense(*h).is_ok_and(|d| island[d] != AWAKE);
            asleep(a) || asleep(b)
        });
        // Gathered order: awake bodies first (as they are), sleeping ones after, as fixed.
        let awake: Vec<usize> = (0..self.bodies.len())
            .filter(|&d| !self.sleep.is_asleep(d))
            .collect();
        let moving = awake
            .iter()
            .any(|&d| self.bodies[d].kind != BodyKind::Fixed);
        if !moving {
            // Nothing can move or touch: the step is empty.
            self.keep_only_sleeping_contacts();
            return Some(StepStats {
                bodies: self.bodies.len(),
                ..Default::default()
            });
        }
        let sleeping: Vec<usize> = (0..self.bodies.len())
            .filter(|&d| self.sleep.is_asleep(d))
            .collect();
        let order: Vec<usize> = awake.iter().chain(&sleeping).copied().collect();
        let mut bodies: Vec<Body> = order.iter().map(|&d| self.bodies[d]).collect();
        let mut states: Vec<BodyState> = order.iter().map(|&d| self.states[d]).collect();
        for b in &mut bodies[awake.len()..] {
            b.kind = BodyKind::Fixed;
            b.inverse_mass = 0.0;
            b.inverse_inertia_local = Vec3::zeros();
        }
        for s in &mut states[awake.len()..] {
            *s = BodyState::default();
        }
        let aabbs: Vec<Aabb> = stages::update_aabbs(&bodies, &states, self.config.margin, dt);
        // Kinematic bodies are immovable to contacts, so their pairs with sleeping bodies are
        // filtered out of the broad phase; a moving kinematic box reaching one wakes it here.
        let mut to_wake: Vec<usize> = Vec::new();
        if effects.kinematic {
            for (g, b) in bodies[..awake.len()].iter().enumerate() {
                let s = &states[g];
                let moves =
                    s.linear_velocity != Vec3::zeros() || s.angular_velocity != Vec3::zeros();
                if b.kind == BodyKind::Kinematic && moves {
                    for (k, aabb) in aabbs[awake.len()..].iter().enumerate() {
                        if aabbs[g].intersects(aabb) {
                            to_wake.push(sleeping[k]);
                        }
                    }
                }
            }
        }
        let pairs = stages::broad_phase(&mut self.sleep.sap, &aabbs, &bodies);
        let all_ids = self.handles.handles();
        let ids: Vec<u64> = order.iter().map(|&d| all_ids[d].to_bits()).collect();
        let narrow = stages::narrow_phase(
            &bodies,
            &states,
            &pairs,
            &ids,
            &self.cache,
            self.config.margin,
            dt,
        );
        let (mut contacts, mut keys) = (narrow.contacts, narrow.keys);
        for c in &contacts {
            for g in [c.body_a as usize, c.body_b as usize] {
                if g >= awake.len() {
                    to_wake.push(order[g]);
                }
            }
        }
        let coloring = stages::color(
            &contacts,
            &bodies,
            self.config.solver.order,
            &self.config.gravity,
        );
        let solved = stages::solve_with_effects(
            &bodies,
            &mut states,
            &mut contacts,
            &coloring,
            &self.config.solver,
            dt,
            &self.config.gravity,
            effects,
        );
        // Back to dense indices, then the sleeping islands' manifolds, which stay in the
        // cache for when they wake.
        for c in &mut contacts {
            c.body_a = order[c.body_a as usize] as u32;
            c.body_b = order[c.body_b as usize] as u32;
        }
        let mut handles = Vec::with_capacity(contacts.len() + self.sleep.contacts.len());
        handles.extend(
            contacts
                .iter()
                .map(|c| (all_ids[c.body_a as usize], all_ids[c.body_b as usize])),
        );
        for (c, key, (ha, hb)) in &self.sleep.contacts {
            let (Ok(a), Ok(b)) = (self.handles.dense(*ha), self.handles.dense(*hb)) else {
                continue;
            };
            contacts.push(Contact {
                body_a: a as u32,
                body_b: b as u32,
                ..*c
            });
            keys.push(*key);
            handles.push((*ha, *hb));
        }
        self.cache.store(&keys, &contacts, &self.bodies);
        tumble_solver::finalize_bodies(&mut bodies[..awake.len()], &mut states[..awake.len()]);
        for (g, &d) in awake.iter().enumerate() {
            self.bodies[d].pose = bodies[g].pose;
            self.states[d] = states[g];
        }
        let stats = StepStats {
            bodies: self.bodies.len(),
            pairs: pairs.len(),
            manifolds: contacts.len(),
            contact_points: solved.points,
            colors: coloring.used_colors(),
            parallel_colors: solved.parallel_batches,
            max_penetration: contacts
                .iter()
                .map(|c| c.manifold.max_depth())
                .fold(0.0, Real::max),
            ..Default::default()
        };
        self.contacts = contacts;
        self.contact_handles = handles;
        for d in to_wake {
            self.sleep.wake(d);
        }
        self.update_sleep(effects);
        Some(stats)
    }

    /// Last step's contacts become those of the sleeping islands only.
    fn keep_only_sleeping_contacts(&mut self) {
        let mut contacts = Vec::new();
        let mut handles = Vec::new();
        for (c, _, (ha, hb)) in &self.sleep.contacts {
            if let (Ok(a), Ok(b)) = (self.handles.dense(*ha), self.handles.dense(*hb)) {
                contacts.push(Contact {
                    body_a: a as u32,
                    body_b: b as u32,
                    ..*c
                });
                handles.push((*ha, *hb));
            }
        }
        self.contacts = contacts;
        self.contact_handles = handles;
    }
}
