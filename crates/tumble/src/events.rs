//! Contact events: which body pairs started and stopped touching in the last step.
//!
//! A pair touches in a step when its manifold has a point that overlapped at the start of the
//! step (depth > 0) or that pushed during it (a positive normal impulse: a speculative point
//! that caught an approaching body), the test of [`crate::World::contact_pairs`] and of
//! `tumble_solver::Contact::is_touching`. A speculative point that stayed apart and pushed
//! nothing does not count, on every backend. A sleeping island's kept manifolds count as
//! touching, so a pair does not end by falling asleep.
//!
//! With events on ([`crate::World::set_contact_events`]), each step compares its touching
//! pairs with the last step's: a pair that touches now and did not then gets a
//! [`ContactEventKind::Begin`], one that touched then and does not now (its bodies parted, or
//! one of them was removed since) an [`ContactEventKind::End`]. Events and touching pairs are
//! sorted by body pair (the smaller handle first), so their order does not depend on the
//! backend or on the order the narrow phase found the pairs in.
//!
//! Off (the default) nothing is computed and nothing is read back.

use tumble_geometry::{Point3, Real, Vec3};
use tumble_solver::Contact;

use crate::BodyHandle;

/// Whether a pair started or stopped touching.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ContactEventKind {
    /// The pair touches in this step and did not in the previous one.
    Begin,
    /// The pair touched in the previous step and does not in this one (or one of its bodies
    /// was removed in between).
    End,
}

/// A pair of bodies touching in the last step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TouchingPair {
    /// The body with the smaller handle.
    pub body_a: BodyHandle,
    /// The body with the larger handle.
    pub body_b: BodyHandle,
    /// The manifold's normal impulse over the step, summed over its points, N s (at rest,
    /// about the weight the pair carries times the step).
    pub normal_impulse: Real,
    /// A representative contact point, world space: the points' mean weighted by their
    /// normal impulses, or their plain mean when none pushed.
    pub point: Point3,
}

/// A pair that started or stopped touching in the last step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactEvent {
    /// Begin or end.
    pub kind: ContactEventKind,
    /// The body with the smaller handle.
    pub body_a: BodyHandle,
    /// The body with the larger handle (possibly removed, for an end).
    pub body_b: BodyHandle,
    /// Begin: the pair's normal impulse in this step, N s. End: its impulse in the last step
    /// it touched.
    pub normal_impulse: Real,
    /// Begin: the contact point of this step. End: the point of the last step it touched.
    pub point: Point3,
}

/// The events' state of a world: on or off, last step's touching pairs, this step's events.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct EventState {
    /// Whether steps compute events.
    pub enabled: bool,
    /// The touching pairs of the last step, sorted by pair.
    pub touching: Vec<TouchingPair>,
    /// The events of the last step, sorted by pair.
    pub events: Vec<ContactEvent>,
    /// Whether `touching` is the step before's (events were on for it), so that a backend's
    /// own comparison of the two steps can stand for the host's.
    pub continuous: bool,
}

impl EventState {
    /// Turns events on or off. Off forgets the touching pairs, so turning them on again
    /// begins every pair touching at the next step.
    pub(crate) fn set_enabled(&mut self, on: bool) {
        if !on {
            self.touching.clear();
            self.events.clear();
            self.continuous = false;
        }
        self.enabled = on;
    }

    /// After a step: `touching` (sorted by pair) replaces last step's pairs; the events are
    /// `events` when the backend compared the steps and the host's list is the step before's,
    /// else the host's comparison ([`EventState::advance`]).
    pub(crate) fn update(
        &mut self,
        touching: Vec<TouchingPair>,
        events: Option<Vec<ContactEvent>>,
    ) {
        match events {
            Some(events) if self.continuous => {
                self.events = events;
                self.touching = touching;
            }
            _ => self.advance(touching),
        }
        self.continuous = true;
    }

    /// After a step: `touching` (sorted by pair, one entry per pair) replaces last step's
    /// pairs, and the events are the difference.
    pub(crate) fn advance(&mut self, touching: Vec<TouchingPair>) {
        self.events.clear();
        let (old, new) = (&self.touching, &touching);
        let (mut i, mut j) = (0, 0);
        let event = |kind, p: &TouchingPair| ContactEvent {
            kind,
            body_a: p.body_a,
            body_b: p.body_b,
            normal_impulse: p.normal_impulse,
            point: p.point,
        };
        while i < old.len() || j < new.len() {
            let order = match (old.get(i), new.get(j)) {
                (Some(o), Some(n)) => pair_of(o).cmp(&pair_of(n)),
                (Some(_), None) => std::cmp::Ordering::Less,
                _ => std::cmp::Ordering::Greater,
            };
            match order {
                std::cmp::Ordering::Less => {
                    self.events.push(event(ContactEventKind::End, &old[i]));
                    i += 1;
                }
                std::cmp::Ordering::Greater => {
                    self.events.push(event(ContactEventKind::Begin, &new[j]));
                    j += 1;
                }
                std::cmp::Ordering::Equal => {
                    i += 1;
                    j += 1;
                }
            }
        }
        self.touching = touching;
    }
}

fn pair_of(p: &TouchingPair) -> (BodyHandle, BodyHandle) {
    (p.body_a, p.body_b)
}

/// The touching pair of manifold `c` between bodies `a` and `b`, or `None` when it does not
/// touch.
pub(crate) fn touching_pair(c: &Contact, a: BodyHandle, b: BodyHandle) -> Option<TouchingPair> {
    if !c.is_touching() {
        return None;
    }
    let n = c.manifold.len as usize;
    let points = c.manifold.points();
    let impulses = &c.total_normal_impulse[..n];
    let impulse: Real = impulses.iter().sum();
    let pushed: Real = impulses.iter().map(|j| j.max(0.0)).sum();
    let point = if pushed > 0.0 {
        let sum = points
            .iter()
            .zip(impulses)
            .fold(Vec3::zeros(), |s, (p, j)| {
                s + p.position.coords * j.max(0.0)
            });
        Point3::from(sum / pushed)
    } else {
        let sum = points
            .iter()
            .fold(Vec3::zeros(), |s, p| s + p.position.coords);
        Point3::from(sum / n.max(1) as Real)
    };
    let (body_a, body_b) = if a <= b { (a, b) } else { (b, a) };
    Some(TouchingPair {
        body_a,
        body_b,
        normal_impulse: impulse,
        point,
    })
}

/// The touching pairs of `contacts` (with the handles of their bodies), sorted by pair.
pub(crate) fn touching_pairs(
    contacts: &[Contact],
    handles: &[(BodyHandle, BodyHandle)],
) -> Vec<TouchingPair> {
    let mut out: Vec<TouchingPair> = contacts
        .iter()
        .zip(handles)
        .filter_map(|(c, &(a, b))| touching_pair(c, a, b))
        .collect();
    out.sort_unstable_by_key(pair_of);
    out.dedup_by_key(|p| pair_of(p));
    out
}
