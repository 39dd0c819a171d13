//! Sleep thresholds shared by every backend: the CPU step's islands and the GPU's sleep
//! kernels read the same values, so a scene falls asleep after the same number of steps on
//! both. The values are Box2D's (`b2_timeToSleep`, `b2_linearSleepTolerance`,
//! `b2_angularSleepTolerance` in Box2D v2.4's `b2_settings.h`).

use std::collections::HashSet;

use tumble_broad::motion_aabb;
use tumble_geometry::{Real, Vec3};

use crate::{Body, BodyKind, BodyState, Contact, Islands, PairKey, finalize_bodies};

pub mod labels;

/// Box2D's `b2_timeToSleep`: an island sleeps after half a second at rest.
pub const TIME_TO_SLEEP: Real = 0.5;

/// Box2D's `b2_linearSleepTolerance`: below 5 cm/s a body counts as resting.
pub const LINEAR_SLEEP_TOLERANCE: Real = 0.05;

/// Box2D's `b2_angularSleepTolerance`: below 2 degrees per second a body counts as resting.
pub const ANGULAR_SLEEP_TOLERANCE: Real = 2.0 / 180.0 * std::f32::consts::PI;

/// True when a body moving at `linear_speed` and `angular_speed` (m/s, rad/s) counts as resting:
/// strictly below both tolerances, the test the CPU step and the GPU kernels both make.
pub fn is_resting(linear_speed: Real, angular_speed: Real) -> bool {
    linear_speed < LINEAR_SLEEP_TOLERANCE && angular_speed < ANGULAR_SLEEP_TOLERANCE
}

/// Island label of an awake body, on every backend (a sleeping body holds its island's
/// label; the GPU's labels are body indices, below any body count it allows).
pub const AWAKE: u32 = u32::MAX;

/// True for a kinematic body that moves (any nonzero velocity): what it touches or reaches
/// stays or wakes up, on the CPU step and in the GPU's sleep kernels.
pub fn is_moving_kinematic(kind: BodyKind, linear: &Vec3, angular: &Vec3) -> bool {
    kind == BodyKind::Kinematic && (*linear != Vec3::zeros() || *angular != Vec3::zeros())
}

/// The sleep state of a world on the CPU: per body (dense order, parallel to the body arrays)
/// its rest time and sleeping island, and the manifolds of the sleeping islands.
///
/// An island (dynamic bodies touching through dynamic bodies, see [`Islands`]) whose bodies
/// have all stayed slow for [`TIME_TO_SLEEP`] falls asleep. A sleeping island is out of the
/// narrow phase and the solver, and pairs between sleeping and immovable bodies are never
/// formed; it wakes when an awake body touches it (a manifold with one of its bodies,
/// speculative points included), when a moving kinematic body's box reaches it, or when its
/// owner wakes one of its bodies.
///
/// While some bodies sleep, the step runs on a [`Gathered`] copy: the awake bodies, then the
/// sleeping ones as fixed obstacles. An awake body that reaches a sleeping one meets it as
/// fixed for that one step and wakes its island for the next (Box2D does the same: a touch
/// wakes the island, which rejoins the solver on the following step).
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SleepState {
    /// Time each body has stayed below the sleep tolerances, s.
    rest_time: Vec<Real>,
    /// The sleeping island of each body, or [`AWAKE`].
    island: Vec<u32>,
    /// Label for the next island to fall asleep.
    next_island: u32,
    /// Bodies asleep.
    asleep: usize,
    /// The manifolds of sleeping islands and their pair keys (stable body ids), kept for
    /// contact reports and warm starting. Their body indices are those of the step they fell
    /// asleep in: [`SleepState::sleeping_contacts`] renumbers them.
    contacts: Vec<(Contact, PairKey)>,
}

/// A step's bodies while some sleep: the awake bodies in dense order, then the sleeping ones
/// made fixed (no mass, no motion), so that the stages see sleepers as obstacles.
#[derive(Clone, Debug, Default)]
pub struct Gathered {
    /// The dense index of each gathered body.
    pub order: Vec<usize>,
    /// Bodies `0..awake` of the gathered arrays are the awake ones.
    pub awake: usize,
    /// The gathered bodies.
    pub bodies: Vec<Body>,
    /// The gathered states (default for the sleepers).
    pub states: Vec<BodyState>,
    /// The gathered index of each dense body.
    position: Vec<u32>,
}

impl Gathered {
    /// True when some awake body is dynamic or kinematic (otherwise nothing can move or
    /// touch, and the step is empty).
    pub fn any_moving(&self) -> bool {
        self.bodies[..self.awake]
            .iter()
            .any(|b| b.kind != BodyKind::Fixed)
    }

    /// The gathered index of the body at dense index `d`.
    pub fn position(&self, d: usize) -> u32 {
        self.position[d]
    }

    /// Renumbers `contacts` from gathered to dense body indices.
    pub fn to_dense(&self, contacts: &mut [Contact]) {
        for c in contacts {
            c.body_a = self.order[c.body_a as usize] as u32;
            c.body_b = self.order[c.body_b as usize] as u32;
        }
    }

    /// The dense indices of the sleeping bodies that `contacts` (gathered indices) reach.
    pub fn touched_sleepers(&self, contacts: &[Contact]) -> Vec<usize> {
        let mut out = Vec::new();
        for c in contacts {
            for g in [c.body_a as usize, c.body_b as usize] {
                if g >= self.awake {
                    out.push(self.order[g]);
                }
            }
        }
        out
    }

    /// The dense indices of the sleeping bodies whose AABB (grown as by stage 1 with `margin`
    /// and `dt`) a moving kinematic body's AABB reaches. Kinematic bodies are immovable to
    /// contacts, so their pairs with sleepers never reach the narrow phase: this is how a
    /// moving kinematic body wakes what it reaches.
    pub fn kinematic_reach(&self, margin: Real, dt: Real) -> Vec<usize> {
        let aabb = |g: usize| {
            let (b, s) = (&self.bodies[g], &self.states[g]);
            motion_aabb(
                &b.shape,
                &b.pose,
                &s.linear_velocity,
                &s.angular_velocity,
                margin,
                dt,
            )
        };
        let sleepers: Vec<_> = (self.awake..self.bodies.len()).map(aabb).collect();
        let mut out = Vec::new();
        for (g, b) in self.bodies[..self.awake].iter().enumerate() {
            let s = &self.states[g];
            if is_moving_kinematic(b.kind, &s.linear_velocity, &s.angular_velocity) {
                let mine = aabb(g);
                for (k, other) in sleepers.iter().enumerate() {
                    if mine.intersects(other) {
                        out.push(self.order[self.awake + k]);
                    }
                }
            }
        }
        out
    }

    /// Finalizes the awake bodies' poses ([`finalize_bodies`]) and writes them and their
    /// states back to the dense arrays.
    pub fn finish_into(&mut self, bodies: &mut [Body], states: &mut [BodyState]) {
        finalize_bodies(
            &mut self.bodies[..self.awake],
            &mut self.states[..self.awake],
        );
        for (g, &d) in self.order[..self.awake].iter().enumerate() {
            bodies[d].pose = self.bodies[g].pose;
            states[d] = self.states[g];
        }
    }
}

impl SleepState {
    /// A body appended to the world: awake, not resting.
    pub fn push(&mut self) {
        self.rest_time.push(0.0);
        self.island.push(AWAKE);
    }

    /// The body at `d` is removed by `swap_remove`: its island wakes first (it loses a body).
    pub fn swap_remove(&mut self, d: usize) {
        self.wake(d);
        self.rest_time.swap_remove(d);
        self.island.swap_remove(d);
    }

    /// Checks that the state fits a world of `bodies` bodies (one rest time and one island
    /// per body, the asleep count matching the islands, finite non-negative rest times, kept
    /// manifolds of at most `MAX_MANIFOLD_POINTS` points): the check a state read from outside
    /// (a saved world) must pass before a step uses it. The error says what is wrong.
    pub fn check(&self, bodies: usize) -> Result<(), String> {
        if self.rest_time.len() != bodies || self.island.len() != bodies {
            return Err(format!(
                "{} rest times and {} islands for {bodies} bodies",
                self.rest_time.len(),
                self.island.len()
            ));
        }
        let asleep = self.island.iter().filter(|&&i| i != AWAKE).count();
        if asleep != self.asleep {
            return Err(format!(
                "asleep count {} but {asleep} bodies in sleeping islands",
                self.asleep
            ));
        }
        if let Some(t) = self.rest_time.iter().find(|t| !t.is_finite() || **t < 0.0) {
            return Err(format!("rest time {t}"));
        }
        let max_points = tumble_geometry::MAX_MANIFOLD_POINTS;
        if let Some((c, _)) = self
            .contacts
            .iter()
            .find(|(c, _)| c.manifold.len as usize > max_points)
        {
            return Err(format!("kept manifold of {} points", c.manifold.len));
        }
        Ok(())
    }

    /// True when the body at `d` sleeps.
    pub fn is_asleep(&self, d: usize) -> bool {
        self.island.get(d).is_some_and(|&i| i != AWAKE)
    }

    /// Bodies asleep.
    pub fn asleep_count(&self) -> usize {
        self.asleep
    }

    /// How long the body at `d` has rested, s (0 for an unknown index).
    pub fn rest_time(&self, d: usize) -> Real {
        self.rest_time.get(d).copied().unwrap_or(0.0)
    }

    /// Wakes the island of the body at `d` (nothing when it is awake) and resets its rest time.
    pub fn wake(&mut self, d: usize) {
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

    /// The pair keys of the sleeping islands' manifolds.
    pub fn sleeping_keys(&self) -> impl Iterator<Item = PairKey> + '_ {
        self.contacts.iter().map(|(_, k)| *k)
    }

    /// Before a step: drops the kept manifolds of islands that woke (they rejoin the narrow
    /// phase through the contact cache). `dense` maps a body id of a pair key to its dense
    /// index (`None` for a removed body).
    pub fn drop_woken_contacts(&mut self, dense: impl Fn(u64) -> Option<usize>) {
        let island = &self.island;
        let asleep = |id: u64| dense(id).is_some_and(|d| island[d] != AWAKE);
        self.contacts.retain(|(_, (a, b))| asleep(*a) || asleep(*b));
    }

    /// The sleeping islands' manifolds and keys, renumbered to the current dense indices
    /// (`dense` as for [`SleepState::drop_woken_contacts`]; pairs with a removed body are left
    /// out).
    pub fn sleeping_contacts<'a>(
        &'a self,
        dense: impl Fn(u64) -> Option<usize> + 'a,
    ) -> impl Iterator<Item = (Contact, PairKey)> + 'a {
        self.contacts.iter().filter_map(move |(c, key)| {
            let (a, b) = (dense(key.0)?, dense(key.1)?);
            Some((
                Contact {
                    body_a: a as u32,
                    body_b: b as u32,
                    ..*c
                },
                *key,
            ))
        })
    }

    /// The step's bodies with the sleepers moved behind the awake ones and made fixed.
    pub fn gather(&self, bodies: &[Body], states: &[BodyState]) -> Gathered {
        let awake: Vec<usize> = (0..bodies.len()).filter(|&d| !self.is_asleep(d)).collect();
        let n_awake = awake.len();
        let mut order = awake;
        order.extend((0..bodies.len()).filter(|&d| self.is_asleep(d)));
        let mut position = vec![0; bodies.len()];
        for (g, &d) in order.iter().enumerate() {
            position[d] = g as u32;
        }
        let mut gathered_bodies: Vec<Body> = order.iter().map(|&d| bodies[d]).collect();
        let mut gathered_states: Vec<BodyState> = order.iter().map(|&d| states[d]).collect();
        for b in &mut gathered_bodies[n_awake..] {
            b.kind = BodyKind::Fixed;
            b.inverse_mass = 0.0;
            b.inverse_inertia_local = Vec3::zeros();
        }
        for s in &mut gathered_states[n_awake..] {
            *s = BodyState::default();
        }
        Gathered {
            order,
            awake: n_awake,
            bodies: gathered_bodies,
            states: gathered_states,
            position,
        }
    }

    /// After a step: rest timers, islands of the awake bodies, and the islands that fall
    /// asleep (their bodies stop: zero velocities in `states`). `contacts` are the step's
    /// manifolds (dense indices) and `keys` their pair keys; the manifolds of islands that
    /// fall asleep are kept. `kinematic` is the kinematic effect: with it, a body touching a
    /// moving kinematic body stays awake.
    pub fn update(
        &mut self,
        bodies: &[Body],
        states: &mut [BodyState],
        contacts: &[Contact],
        keys: &[PairKey],
        dt: Real,
        kinematic: bool,
    ) {
        for (d, (body, state)) in bodies.iter().zip(states.iter()).enumerate() {
            let resting = is_resting(state.linear_velocity.norm(), state.angular_velocity.norm());
            self.rest_time[d] = match body.kind {
                BodyKind::Dynamic if resting => self.rest_time[d] + dt,
                _ => 0.0,
            };
        }
        // A body carried or pushed by a moving kinematic body stays awake.
        if kinematic {
            let moving = |i: usize| {
                let s = &states[i];
                is_moving_kinematic(bodies[i].kind, &s.linear_velocity, &s.angular_velocity)
            };
            for c in contacts {
                let (a, b) = (c.body_a as usize, c.body_b as usize);
                if moving(a) || moving(b) {
                    self.rest_time[a] = 0.0;
                    self.rest_time[b] = 0.0;
                }
            }
        }
        let awake_dynamic: Vec<bool> = bodies
            .iter()
            .zip(&self.island)
            .map(|(b, &i)| b.is_dynamic() && i == AWAKE)
            .collect();
        // Every manifold links, speculative ones too, as a manifold with a sleeping body wakes
        // it: were the two rules different, two neighbours a few millimetres apart would wake
        // each other in turn forever (Box2D v3 links on the same condition it wakes on).
        let links = contacts.iter().map(|c| (c.body_a, c.body_b));
        let islands = Islands::build(&awake_dynamic, links);
        // The shortest rest of each island (indexed by its label, a body index).
        let mut shortest = vec![Real::INFINITY; bodies.len()];
        for (d, &label) in islands.label.iter().enumerate() {
            if awake_dynamic[d] {
                let s = &mut shortest[label as usize];
                *s = s.min(self.rest_time[d]);
            }
        }
        let mut any_asleep = false;
        for (d, (&label, &awake)) in islands.label.iter().zip(&awake_dynamic).enumerate() {
            if awake && shortest[label as usize] >= TIME_TO_SLEEP {
                // Wrapping, the label could only meet AWAKE after four billion bodies fell
                // asleep; it is moved off it all the same.
                let id = self.next_island.wrapping_add(label);
                self.island[d] = if id == AWAKE { 0 } else { id };
                states[d].linear_velocity = Vec3::zeros();
                states[d].angular_velocity = Vec3::zeros();
                self.asleep += 1;
                any_asleep = true;
            }
        }
        if !any_asleep {
            return;
        }
        // Labels are body indices, so offsetting by the body count keeps them unique.
        self.next_island = self.next_island.wrapping_add(bodies.len() as u32);
        let kept: HashSet<PairKey> = self.contacts.iter().map(|(_, k)| *k).collect();
        for (c, key) in contacts.iter().zip(keys) {
            let (a, b) = (c.body_a as usize, c.body_b as usize);
            let involved = self.island[a] != AWAKE || self.island[b] != AWAKE;
            if involved && !kept.contains(key) {
                self.contacts.push((*c, *key));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Material;
    use tumble_geometry::{Manifold, Pose};

    fn cube(kind: BodyKind, y: Real) -> Body {
        crate::tests::body(
            kind,
            Vec3::repeat(0.5),
            Pose::translation(0.0, y, 0.0),
            1.0,
            Material::default(),
        )
    }

    /// Floor 0, cubes 1 and 2 stacked on it, cube 3 alone.
    fn scene() -> (Vec<Body>, Vec<BodyState>, Vec<Contact>, Vec<PairKey>) {
        let bodies = vec![
            cube(BodyKind::Fixed, -0.5),
            cube(BodyKind::Dynamic, 0.5),
            cube(BodyKind::Dynamic, 1.5),
            cube(BodyKind::Dynamic, 5.0),
        ];
        let states = vec![BodyState::default(); 4];
        let contacts = vec![
            Contact::new(0, 1, Manifold::default()),
            Contact::new(1, 2, Manifold::default()),
        ];
        let keys = vec![(10, 11), (11, 12)];
        (bodies, states, contacts, keys)
    }

    fn sleep_of(n: usize) -> SleepState {
        let mut s = SleepState::default();
        for _ in 0..n {
            s.push();
        }
        s
    }

    #[test]
    fn an_island_sleeps_after_time_to_sleep_at_rest_and_keeps_its_contacts() {
        let (bodies, mut states, contacts, keys) = scene();
        // Cube 3 drifts just above the tolerance: it stays awake.
        states[3].linear_velocity = Vec3::new(LINEAR_SLEEP_TOLERANCE, 0.0, 0.0);
        let mut sleep = sleep_of(4);
        // A step of 1/8 s: four steps at rest make TIME_TO_SLEEP exactly.
        let dt = 0.125;
        for step in 1..=3 {
            sleep.update(&bodies, &mut states, &contacts, &keys, dt, false);
            assert_eq!(sleep.asleep_count(), 0, "step {step}");
        }
        assert_eq!(sleep.rest_time(1), 0.375);
        sleep.update(&bodies, &mut states, &contacts, &keys, dt, false);
        assert_eq!(sleep.asleep_count(), 2);
        assert!(sleep.is_asleep(1) && sleep.is_asleep(2));
        assert!(!sleep.is_asleep(0) && !sleep.is_asleep(3));
        assert_eq!(sleep.rest_time(0), 0.0);
        assert_eq!(sleep.rest_time(3), 0.0);
        assert_eq!(states[3].linear_velocity.x, LINEAR_SLEEP_TOLERANCE);
        let kept: Vec<PairKey> = sleep.sleeping_keys().collect();
        assert_eq!(kept, vec![(10, 11), (11, 12)]);
        // Waking one body wakes its whole island and resets the timers.
        sleep.wake(2);
        assert_eq!(sleep.asleep_count(), 0);
        assert_eq!(sleep.rest_time(1), 0.0);
    }

    #[test]
    fn a_moving_kinematic_contact_keeps_its_bodies_awake() {
        let (mut bodies, mut states, contacts, keys) = scene();
        bodies[0].kind = BodyKind::Kinematic;
        states[0].linear_velocity = Vec3::new(0.0, 0.0, 1.0);
        let mut sleep = sleep_of(4);
        for _ in 0..20 {
            sleep.update(&bodies, &mut states, &contacts, &keys, 0.1, true);
        }
        assert!(!sleep.is_asleep(1));
        // Only cube 1 touches the platform; cube 2 rests, but its island holds cube 1.
        assert!(!sleep.is_asleep(2));
        assert!(sleep.is_asleep(3));
        assert_eq!(sleep.rest_time(1), 0.0);
    }

    #[test]
    fn the_gathered_step_puts_sleepers_last_as_fixed_and_maps_back() {
        let (bodies, mut states, contacts, keys) = scene();
        states[3].linear_velocity = Vec3::new(1.0, 0.0, 0.0);
        let mut sleep = sleep_of(4);
        for _ in 0..6 {
            sleep.update(&bodies, &mut states, &contacts, &keys, 0.1, false);
        }
        assert_eq!(sleep.asleep_count(), 2);
        let g = sleep.gather(&bodies, &states);
        assert_eq!(g.order, vec![0, 3, 1, 2]);
        assert_eq!(g.awake, 2);
        assert!(g.any_moving());
        assert_eq!((g.position(1), g.position(3)), (2, 1));
        assert!(
            g.bodies[2..]
                .iter()
                .all(|b| b.kind == BodyKind::Fixed && b.inverse_mass == 0.0)
        );
        assert_eq!(g.states[1].linear_velocity.x, 1.0);
        // Cube 3 (gathered 1) touches sleeping cube 2 (gathered 3): it reaches cube 2's island.
        let mut touching = vec![Contact::new(1, 3, Manifold::default())];
        assert_eq!(g.touched_sleepers(&touching), vec![2]);
        g.to_dense(&mut touching);
        assert_eq!((touching[0].body_a, touching[0].body_b), (3, 2));
        // The kept contacts come back renumbered; a removed body drops its pairs.
        let dense = |id: u64| (id != 12).then(|| (id - 10) as usize);
        let back: Vec<_> = sleep.sleeping_contacts(dense).collect();
        assert_eq!(back.len(), 1);
        assert_eq!((back[0].0.body_a, back[0].0.body_b), (0, 1));
        // Once the island wakes, its kept contacts are dropped before the next step.
        sleep.wake(1);
        sleep.drop_woken_contacts(|id| Some((id - 10) as usize));
        assert_eq!(sleep.sleeping_keys().count(), 0);
    }

    #[test]
    fn a_moving_kinematic_box_reaches_the_sleepers_it_overlaps() {
        let (mut bodies, mut states, contacts, keys) = scene();
        let mut sleep = sleep_of(4);
        for _ in 0..6 {
            sleep.update(&bodies, &mut states, &contacts, &keys, 0.1, false);
        }
        assert_eq!(sleep.asleep_count(), 3);
        // A kinematic box beside cube 2 and above cube 1, moving: its grown AABB (x from 0.43
        // to 1.52, y from 1.23 to 2.27) reaches cube 2's (x up to 0.52, y from 0.98) only.
        let mut platform = cube(BodyKind::Kinematic, 1.5);
        platform.pose = Pose::translation(1.0, 1.75, 0.0);
        bodies.push(platform);
        states.push(BodyState::default());
        sleep.push();
        // Still, it reaches nothing.
        let still = sleep.gather(&bodies, &states);
        assert!(still.any_moving());
        assert!(still.kinematic_reach(0.02, 0.1).is_empty());
        states[4].linear_velocity = Vec3::new(-0.5, 0.0, 0.0);
        let g = sleep.gather(&bodies, &states);
        assert_eq!(g.kinematic_reach(0.02, 0.1), vec![2]);
    }
}
