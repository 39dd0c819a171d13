//! The CPU twin of the sleep stage: the same state (an island label and a rest time per
//! body, a wake flag per label) and one method per kernel, in the order a step records them.
//! Apart from the rest-time test, whose speeds may round differently in the last bit on the
//! GPU, every result is integer and equals the kernels' exactly.

use tumble_geometry::{Aabb, Vec3};
use tumble_solver::{BodyKind, TIME_TO_SLEEP, is_resting};

use super::constants::{AWAKE, ISLAND_ROUNDS};
use super::islands::island_search_cpu;

/// A manifold as the sleep stage sees it: its two bodies, and whether it has points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SleepLink {
    /// Body A.
    pub a: u32,
    /// Body B.
    pub b: u32,
    /// True when the manifold has points (speculative ones included).
    pub touching: bool,
}

/// The sleep state of a world on the CPU.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SleepCpu {
    /// Each body's island label, [`AWAKE`] for an awake body.
    pub island: Vec<u32>,
    /// Each body's rest time, s.
    pub rest_time: Vec<f32>,
    /// Wake flags by island label.
    pub wake: Vec<bool>,
}

impl SleepCpu {
    /// `n` awake bodies that have not rested.
    pub fn new(n: usize) -> Self {
        Self {
            island: vec![AWAKE; n],
            rest_time: vec![0.0; n],
            wake: vec![false; n],
        }
    }

    /// `wake_bodies`: the queued bodies restart their rest time and flag their islands.
    pub fn wake_bodies(&mut self, queued: &[u32]) {
        for &body in queued {
            self.rest_time[body as usize] = 0.0;
            let label = self.island[body as usize];
            if label != AWAKE {
                self.wake[label as usize] = true;
            }
        }
    }

    /// `wake_islands`: every body of a flagged island wakes; the flags clear. Returns the
    /// bodies woken (the kernel restores their solver data and shapes).
    pub fn wake_islands(&mut self) -> Vec<usize> {
        let mut woken = Vec::new();
        for i in 0..self.island.len() {
            let label = self.island[i];
            if label != AWAKE && self.wake[label as usize] {
                self.island[i] = AWAKE;
                self.rest_time[i] = 0.0;
                woken.push(i);
            }
        }
        self.wake.iter_mut().for_each(|w| *w = false);
        woken
    }

    /// `update_rest`: awake dynamic bodies below both tolerances rest `dt` longer, others
    /// start over; sleeping bodies keep theirs. `velocities` are (linear, angular).
    pub fn update_rest(&mut self, kinds: &[BodyKind], velocities: &[(Vec3, Vec3)], dt: f32) {
        for (i, (kind, (v, w))) in kinds.iter().zip(velocities).enumerate() {
            if *kind != BodyKind::Dynamic {
                self.rest_time[i] = 0.0;
            } else if self.island[i] == AWAKE {
                self.rest_time[i] = if is_resting(v.norm(), w.norm()) {
                    self.rest_time[i] + dt
                } else {
                    0.0
                };
            }
        }
    }

    /// `touch_sleepers`: manifolds with points flag the sleeping islands they reach, and a
    /// moving kinematic body's manifolds stop both bodies' rest.
    pub fn touch_sleepers(
        &mut self,
        links: &[SleepLink],
        kinds: &[BodyKind],
        velocities: &[(Vec3, Vec3)],
    ) {
        let moving_kinematic = |i: usize| {
            kinds[i] == BodyKind::Kinematic
                && (velocities[i].0 != Vec3::zeros() || velocities[i].1 != Vec3::zeros())
        };
        for link in links.iter().filter(|l| l.touching) {
            let (a, b) = (link.a as usize, link.b as usize);
            for i in [a, b] {
                if self.island[i] != AWAKE {
                    self.wake[self.island[i] as usize] = true;
                }
            }
            if moving_kinematic(a) || moving_kinematic(b) {
                self.rest_time[a] = 0.0;
                self.rest_time[b] = 0.0;
            }
        }
    }

    /// `kinematic_wake`: a sleeping body whose AABB overlaps that of a moving kinematic body
    /// flags its island.
    pub fn kinematic_wake(
        &mut self,
        kinds: &[BodyKind],
        velocities: &[(Vec3, Vec3)],
        aabbs: &[Aabb],
    ) {
        let moving: Vec<usize> = (0..kinds.len())
            .filter(|&k| {
                kinds[k] == BodyKind::Kinematic
                    && (velocities[k].0 != Vec3::zeros() || velocities[k].1 != Vec3::zeros())
            })
            .collect();
        for (i, aabb) in aabbs.iter().enumerate() {
            let label = self.island[i];
            if label != AWAKE && moving.iter().any(|&k| aabb.intersects(&aabbs[k])) {
                self.wake[label as usize] = true;
            }
        }
    }

    /// The island search, `island_rest` and `fall_asleep`: islands of linkable bodies whose
    /// shortest rest time reached [`TIME_TO_SLEEP`] fall asleep under their label (nothing
    /// does when the search did not finish). Returns the bodies that fell asleep (the kernel
    /// zeroes their velocities and makes them fixed and static).
    pub fn fall_asleep(&mut self, links: &[SleepLink], kinds: &[BodyKind]) -> Vec<usize> {
        let linkable: Vec<bool> = kinds
            .iter()
            .zip(&self.island)
            .map(|(k, &label)| *k == BodyKind::Dynamic && label == AWAKE)
            .collect();
        let pairs: Vec<(u32, u32)> = links
            .iter()
            .filter(|l| l.touching)
            .map(|l| (l.a, l.b))
            .collect();
        // plan_search: with no body rested long enough, no island can sleep, and the GPU
        // skips the search.
        let ready = (0..linkable.len()).any(|i| linkable[i] && self.rest_time[i] >= TIME_TO_SLEEP);
        if !ready {
            return Vec::new();
        }
        let search = island_search_cpu(&linkable, &pairs, ISLAND_ROUNDS);
        if !search.finished {
            return Vec::new();
        }
        let mut shortest = vec![f32::INFINITY; linkable.len()];
        for (i, &label) in search.labels.iter().enumerate() {
            if linkable[i] {
                let s = &mut shortest[label as usize];
                *s = s.min(self.rest_time[i]);
            }
        }
        let mut asleep = Vec::new();
        for (i, &label) in search.labels.iter().enumerate() {
            if linkable[i] && shortest[label as usize] >= TIME_TO_SLEEP {
                self.island[i] = label;
                asleep.push(i);
            }
        }
        asleep
    }
}
