//! The label-propagation form of the sleep stage, the one the GPU runs (its kernels' CPU
//! twin): the same state (an island label and a rest time per body, a wake flag per label)
//! and one method per kernel, in the order a step records them. Where [`SleepState`] finds
//! islands with union-find on the gathered bodies, this finds them by a bounded number of
//! label-propagation rounds ([`island_search`]) on every body in place. Apart from the
//! rest-time test, whose speeds may round differently in the last bit on the GPU, every result
//! is integer and equals the kernels' exactly.
//!
//! [`SleepState`]: super::SleepState

use tumble_geometry::{Aabb, Vec3};

use super::{AWAKE, TIME_TO_SLEEP, is_moving_kinematic, is_resting};
use crate::BodyKind;

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

/// The label-propagation sleep state of a world.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SleepLabels {
    /// Each body's island label, [`AWAKE`] for an awake body.
    pub island: Vec<u32>,
    /// Each body's rest time, s.
    pub rest_time: Vec<f32>,
    /// Wake flags by island label.
    pub wake: Vec<bool>,
}

impl SleepLabels {
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
        let moving_kinematic =
            |i: usize| is_moving_kinematic(kinds[i], &velocities[i].0, &velocities[i].1);
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
            .filter(|&k| is_moving_kinematic(kinds[k], &velocities[k].0, &velocities[k].1))
            .collect();
        for (i, aabb) in aabbs.iter().enumerate() {
            let label = self.island[i];
            if label != AWAKE && moving.iter().any(|&k| aabb.intersects(&aabbs[k])) {
                self.wake[label as usize] = true;
            }
        }
    }

    /// The island search (`rounds` rounds), `island_rest` and `fall_asleep`: islands of
    /// linkable bodies whose shortest rest time reached [`TIME_TO_SLEEP`] fall asleep under
    /// their label (nothing does when the search did not finish). Returns the bodies that fell
    /// asleep (the kernel zeroes their velocities and makes them fixed and static).
    pub fn fall_asleep(
        &mut self,
        links: &[SleepLink],
        kinds: &[BodyKind],
        rounds: u32,
    ) -> Vec<usize> {
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
        let search = island_search(&linkable, &pairs, rounds);
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

/// The result of an island search.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IslandSearch {
    /// Each body's label after the last round (a body index of its island).
    pub labels: Vec<u32>,
    /// True when no link joins two labels: each island is labelled with its smallest body.
    pub finished: bool,
}

/// The island search by label propagation: `rounds` rounds over `links` (pairs of body
/// indices; a link counts when both its bodies are `linkable`) in which, for each link whose
/// two labels differ, the larger label is hooked onto the smaller, then every label is
/// replaced by the label it points at; then the check that no link still joins two labels.
/// The GPU's `hook_labels`, `jump_labels` and `check_labels` compute these labels bit for bit.
pub fn island_search(linkable: &[bool], links: &[(u32, u32)], rounds: u32) -> IslandSearch {
    let n = linkable.len();
    let counts = |&(a, b): &(u32, u32)| linkable[a as usize] && linkable[b as usize];
    let mut labels: Vec<u32> = (0..n as u32).collect();
    for _ in 0..rounds {
        let mut next = labels.clone();
        for &(a, b) in links.iter().filter(|l| counts(l)) {
            let (la, lb) = (labels[a as usize], labels[b as usize]);
            if la != lb {
                let slot = &mut next[la.max(lb) as usize];
                *slot = (*slot).min(la.min(lb));
            }
        }
        labels = (0..n).map(|i| next[next[i] as usize]).collect();
    }
    let finished = links
        .iter()
        .filter(|l| counts(l))
        .all(|&(a, b)| labels[a as usize] == labels[b as usize]);
    IslandSearch { labels, finished }
}
