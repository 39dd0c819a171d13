//! Graph coloring of constraints: no two constraints of one color share a dynamic body, so
//! the constraints of a color can be solved at the same time.
//!
//! Contract (shared with the GPU twin):
//! - input: per constraint its two body indices, and per body whether it is dynamic; fixed and
//!   kinematic bodies are never written by the solver, so they do not count;
//! - output: per constraint a color in `0..GRAPH_COLOR_COUNT`, or [`OVERFLOW_COLOR`] when every
//!   color already holds one of its dynamic bodies; overflow constraints are solved one after
//!   another after the colors;
//! - the CPU assignment is greedy in constraint order (lowest free color), so it is
//!   deterministic; any assignment that passes [`validate_coloring`] solves correctly.

use std::collections::HashMap;

use crate::{Body, Contact, InvalidParameter};

/// Number of graph colors. Box2D v3 uses 24 (`B2_GRAPH_COLOR_COUNT`): enough for dense piles,
/// where a box has at most about a dozen neighbours, while a body touching more than this
/// many others (a crowded floor is fixed, so it does not count) spills into the overflow set.
/// At most 32, so a body's used colors fit one `u32` mask.
pub const GRAPH_COLOR_COUNT: usize = 24;

/// The color of a constraint left to the sequential overflow set.
pub const OVERFLOW_COLOR: u32 = GRAPH_COLOR_COUNT as u32;

const _: () = assert!(GRAPH_COLOR_COUNT <= 32, "a body's color mask is one u32");

/// Color and proposal of a constraint not decided yet (parallel rounds, [`color_in_rounds`]).
pub const NO_COLOR: u32 = u32::MAX;

/// The color of a manifold without points (a candidate pair not in contact): it is no
/// constraint, sorts after the overflow set and lies in no color's range.
pub const EMPTY_COLOR: u32 = OVERFLOW_COLOR + 1;

/// Coloring rounds of [`color_in_rounds`] (the GPU's on every path); constraints still
/// undecided after them overflow. Every round decides at least the undecided constraint of
/// highest priority. Around a dynamic body touching many others (a star) every round decides
/// one of its constraints, so it fills its 24 colors in 24 rounds and overflows on the 25th;
/// the 8 rounds on top absorb chains of lost claims in dense piles. After the seeded first
/// round a settled scene has almost nothing left to decide, and the GPU's finishing kernel
/// stops at the first empty round.
pub const COLOR_ROUNDS: u32 = GRAPH_COLOR_COUNT as u32 + 8;

/// The result of coloring: a color per constraint and the constraints grouped by color.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Coloring {
    /// Color of each constraint, `0..GRAPH_COLOR_COUNT` or [`OVERFLOW_COLOR`].
    pub colors: Vec<u32>,
    /// Constraint indices grouped by color (ascending color, overflow last), ascending within
    /// a color.
    pub order: Vec<u32>,
    /// `order[offsets[c]..offsets[c + 1]]` holds color `c`; `c = OVERFLOW_COLOR` is the
    /// overflow set. Length `GRAPH_COLOR_COUNT + 2`.
    pub offsets: Vec<u32>,
}

impl Default for Coloring {
    /// The coloring of no constraints.
    fn default() -> Self {
        Self::from_colors(Vec::new())
    }
}

impl Coloring {
    /// The constraints of color `c` (`OVERFLOW_COLOR` for the overflow set).
    pub fn color(&self, c: u32) -> &[u32] {
        let (s, e) = (
            self.offsets[c as usize] as usize,
            self.offsets[c as usize + 1] as usize,
        );
        &self.order[s..e]
    }

    /// How many colors hold at least one constraint.
    pub fn used_colors(&self) -> usize {
        (0..GRAPH_COLOR_COUNT as u32)
            .filter(|&c| !self.color(c).is_empty())
            .count()
    }

    /// How many constraints fell into the overflow set.
    pub fn overflow_count(&self) -> usize {
        self.color(OVERFLOW_COLOR).len()
    }

    /// Groups `colors` into `order` and `offsets` (a counting sort, stable).
    pub fn from_colors(colors: Vec<u32>) -> Self {
        let mut offsets = vec![0u32; GRAPH_COLOR_COUNT + 2];
        for &c in &colors {
            offsets[c as usize + 1] += 1;
        }
        for c in 1..offsets.len() {
            offsets[c] += offsets[c - 1];
        }
        let mut next = offsets.clone();
        let mut order = vec![0u32; colors.len()];
        for (i, &c) in colors.iter().enumerate() {
            order[next[c as usize] as usize] = i as u32;
            next[c as usize] += 1;
        }
        Self {
            colors,
            order,
            offsets,
        }
    }
}

/// Colors constraints greedily in order: each takes the lowest color in which neither of its
/// dynamic bodies appears yet, or [`OVERFLOW_COLOR`].
///
/// `pairs[i]` are constraint `i`'s body indices; `dynamic[b]` says whether body `b` counts.
pub fn color_constraints(pairs: &[(u32, u32)], dynamic: &[bool]) -> Coloring {
    color_constraints_in_order(pairs, dynamic, 0..pairs.len())
}

/// Colors `contacts` over `bodies` greedily in manifold order: [`color_constraints`] on
/// their body pairs, with the bodies that [`Body::is_dynamic`] counting.
pub fn color_contacts(contacts: &[Contact], bodies: &[Body]) -> Coloring {
    let pairs: Vec<(u32, u32)> = contacts.iter().map(|c| (c.body_a, c.body_b)).collect();
    let dynamic: Vec<bool> = bodies.iter().map(Body::is_dynamic).collect();
    color_constraints(&pairs, &dynamic)
}

/// Colors constraints greedily, visiting them in `visit` order (a permutation of
/// `0..pairs.len()`): each takes the lowest color in which neither of its dynamic bodies
/// appears yet, or [`OVERFLOW_COLOR`]. The constraints visited first mostly get the low
/// colors, which the solver visits first in each pass.
pub fn color_constraints_in_order(
    pairs: &[(u32, u32)],
    dynamic: &[bool],
    visit: impl IntoIterator<Item = usize>,
) -> Coloring {
    let visits: Vec<(usize, (u32, u32))> = visit.into_iter().map(|i| (i, pairs[i])).collect();
    color_visits(&visits, dynamic, pairs.len())
}

/// [`color_constraints_in_order`] on `count` constraints given as `(constraint, its body
/// pair)` in visiting order (each constraint at most once; those never visited overflow).
pub(crate) fn color_visits(
    visits: &[(usize, (u32, u32))],
    dynamic: &[bool],
    count: usize,
) -> Coloring {
    // Bit c of used[b]: body b already has a constraint of color c.
    let mut used = vec![0u32; dynamic.len()];
    let all = if GRAPH_COLOR_COUNT == 32 {
        u32::MAX
    } else {
        (1u32 << GRAPH_COLOR_COUNT) - 1
    };
    let mut colors = vec![OVERFLOW_COLOR; count];
    for &(i, (a, b)) in visits {
        let (da, db) = (dynamic[a as usize], dynamic[b as usize]);
        let mut taken = 0u32;
        if da {
            taken |= used[a as usize];
        }
        if db {
            taken |= used[b as usize];
        }
        let free = !taken & all;
        if free == 0 {
            continue;
        }
        let c = free.trailing_zeros();
        if da {
            used[a as usize] |= 1 << c;
        }
        if db {
            used[b as usize] |= 1 << c;
        }
        colors[i] = c;
    }
    Coloring::from_colors(colors)
}

/// Why a coloring is invalid.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ColoringError {
    /// The color list and the constraint list differ in length.
    #[error("{colors} colors for {constraints} constraints")]
    LengthMismatch {
        /// Number of colors given.
        colors: usize,
        /// Number of constraints.
        constraints: usize,
    },
    /// A color outside `0..GRAPH_COLOR_COUNT` that is not the overflow color.
    #[error("constraint {constraint} has color {color}")]
    ColorOutOfRange {
        /// The constraint.
        constraint: usize,
        /// Its color.
        color: u32,
    },
    /// Two constraints of one color share a dynamic body.
    #[error("constraints {first} and {second} share dynamic body {body} in color {color}")]
    SharedBody {
        /// The earlier constraint.
        first: usize,
        /// The later constraint.
        second: usize,
        /// The shared body.
        body: u32,
        /// The color.
        color: u32,
    },
    /// A body index beyond the body list.
    #[error(transparent)]
    BadBody(#[from] InvalidParameter),
}

/// Checks that no two constraints of one color share a dynamic body and that every color is
/// in range. Overflow constraints may share anything.
pub fn validate_coloring(
    pairs: &[(u32, u32)],
    dynamic: &[bool],
    colors: &[u32],
) -> Result<(), ColoringError> {
    if pairs.len() != colors.len() {
        return Err(ColoringError::LengthMismatch {
            colors: colors.len(),
            constraints: pairs.len(),
        });
    }
    // owner[(body, color)] = the constraint that holds the body in that color.
    let mut owner = std::collections::HashMap::new();
    for (i, (&(a, b), &c)) in pairs.iter().zip(colors).enumerate() {
        if c == OVERFLOW_COLOR {
            continue;
        }
        if c as usize >= GRAPH_COLOR_COUNT {
            return Err(ColoringError::ColorOutOfRange {
                constraint: i,
                color: c,
            });
        }
        for body in [a, b] {
            let is_dynamic = *dynamic.get(body as usize).ok_or_else(|| {
                InvalidParameter::new("body index", body, "an index below the body count")
            })?;
            if !is_dynamic {
                continue;
            }
            if let Some(&first) = owner.get(&(body, c)) {
                if first != i {
                    return Err(ColoringError::SharedBody {
                        first,
                        second: i,
                        body,
                        color: c,
                    });
                }
            } else {
                owner.insert((body, c), i);
            }
        }
    }
    Ok(())
}

/// Wellons' "lowbias32" hash, the same bijection as `hash_u32` in `coloring.wgsl`.
pub fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Constraint `i`'s priority in the rounds (distinct and nonzero).
pub fn color_priority(i: u32) -> u32 {
    hash_u32(i + 1)
}

/// One manifold as the coloring sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ColorCandidate {
    /// Its two bodies.
    pub bodies: (u32, u32),
    /// False for a candidate pair not in contact (no points): it gets [`EMPTY_COLOR`].
    pub touching: bool,
    /// Last step's color of the pair, proposed in round 0 when free.
    pub seed: Option<u32>,
}

/// Graph coloring in parallel rounds, the algorithm the GPU runs on every path (the CPU step's
/// default is the greedy top-down [`crate::stages::color`]; this is the GPU's CPU twin):
/// [`COLOR_ROUNDS`] rounds in which every undecided constraint proposes its lowest free color
/// (round 0: last step's color when still free) and keeps it when it holds the highest
/// [`color_priority`] among the proposals for that color on each of its dynamic bodies; the
/// constraints still undecided go to [`OVERFLOW_COLOR`]. `dynamic[b]` says whether body `b`
/// counts.
pub fn color_in_rounds(candidates: &[ColorCandidate], dynamic: &[bool]) -> Vec<u32> {
    let all = if GRAPH_COLOR_COUNT >= 32 {
        u32::MAX
    } else {
        (1u32 << GRAPH_COLOR_COUNT) - 1
    };
    let mut colors = vec![NO_COLOR; candidates.len()];
    let mut used = vec![0u32; dynamic.len()];
    let mut undecided = Vec::with_capacity(candidates.len());
    for (i, c) in candidates.iter().enumerate() {
        if c.touching {
            undecided.push(i);
        } else {
            colors[i] = EMPTY_COLOR;
        }
    }
    for round in 0..COLOR_ROUNDS {
        if undecided.is_empty() {
            break;
        }
        // Proposals, and the highest priority claiming each (body, color).
        let mut proposals = Vec::with_capacity(undecided.len());
        let mut claims: HashMap<(u32, u32), u32> = HashMap::new();
        for &i in &undecided {
            let (a, b) = candidates[i].bodies;
            let (da, db) = (dynamic[a as usize], dynamic[b as usize]);
            let taken =
                if da { used[a as usize] } else { 0 } | if db { used[b as usize] } else { 0 };
            let free = !taken & all;
            if free == 0 {
                colors[i] = OVERFLOW_COLOR;
                continue;
            }
            let mut color = free.trailing_zeros();
            if round == 0
                && let Some(seed) = candidates[i].seed
                && seed < OVERFLOW_COLOR
                && (free >> seed) & 1 != 0
            {
                color = seed;
            }
            proposals.push((i, color));
            for (body, counts) in [(a, da), (b, db)] {
                if counts {
                    let claim = claims.entry((body, color)).or_insert(0);
                    *claim = (*claim).max(color_priority(i as u32));
                }
            }
        }
        let mut next = Vec::new();
        for (i, color) in proposals {
            let (a, b) = candidates[i].bodies;
            let priority = color_priority(i as u32);
            let holds = |body: u32| !dynamic[body as usize] || claims[&(body, color)] == priority;
            if holds(a) && holds(b) {
                colors[i] = color;
                for body in [a, b] {
                    if dynamic[body as usize] {
                        used[body as usize] |= 1 << color;
                    }
                }
            } else {
                next.push(i);
            }
        }
        undecided = next;
    }
    for i in undecided {
        colors[i] = OVERFLOW_COLOR;
    }
    colors
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_graph(rng: &mut ChaCha8Rng, bodies: u32, edges: usize) -> Vec<(u32, u32)> {
        (0..edges)
            .map(|_| {
                let a = rng.random_range(0..bodies);
                let mut b = rng.random_range(0..bodies);
                while b == a {
                    b = rng.random_range(0..bodies);
                }
                (a.min(b), a.max(b))
            })
            .collect()
    }

    #[test]
    fn greedy_coloring_of_random_graphs_is_valid() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for trial in 0..50 {
            let bodies = rng.random_range(2..400);
            let edges = rng.random_range(0..2000);
            let pairs = random_graph(&mut rng, bodies, edges);
            // A fifth of the bodies are fixed or kinematic.
            let dynamic: Vec<bool> = (0..bodies).map(|_| rng.random_bool(0.8)).collect();
            let coloring = color_constraints(&pairs, &dynamic);
            validate_coloring(&pairs, &dynamic, &coloring.colors)
                .unwrap_or_else(|e| panic!("trial {trial}: {e}"));
            // order is a permutation grouped by color.
            let mut seen = coloring.order.clone();
            seen.sort_unstable();
            assert!(seen.iter().enumerate().all(|(i, &c)| c as usize == i));
            for c in 0..=OVERFLOW_COLOR {
                assert!(
                    coloring
                        .color(c)
                        .iter()
                        .all(|&i| coloring.colors[i as usize] == c)
                );
            }
        }
    }

    #[test]
    fn a_body_touching_a_hundred_others_fills_every_color_then_overflows() {
        // Body 0 is dynamic and touches 100 dynamic bodies: each color can hold it once.
        let pairs: Vec<(u32, u32)> = (1..=100).map(|i| (0, i)).collect();
        let dynamic = vec![true; 101];
        let coloring = color_constraints(&pairs, &dynamic);
        validate_coloring(&pairs, &dynamic, &coloring.colors).unwrap();
        assert_eq!(coloring.used_colors(), GRAPH_COLOR_COUNT);
        assert_eq!(coloring.overflow_count(), 100 - GRAPH_COLOR_COUNT);

        // The same star around a fixed body needs one color: fixed bodies do not count.
        let mut fixed_hub = dynamic.clone();
        fixed_hub[0] = false;
        let coloring = color_constraints(&pairs, &fixed_hub);
        validate_coloring(&pairs, &fixed_hub, &coloring.colors).unwrap();
        assert_eq!(coloring.used_colors(), 1);
        assert_eq!(coloring.overflow_count(), 0);
    }

    #[test]
    fn validation_catches_a_shared_dynamic_body() {
        let pairs = [(0, 1), (1, 2), (2, 3)];
        let dynamic = [true, true, true, false];
        assert!(matches!(
            validate_coloring(&pairs, &dynamic, &[0, 0, 1]),
            Err(ColoringError::SharedBody { body: 1, .. })
        ));
        // Bodies 0 and 3 do not meet, so (0, 1) and (2, 3) may share a color; (1, 2) and
        // (2, 3) may not, because of body 2.
        assert!(validate_coloring(&pairs, &dynamic, &[0, 1, 0]).is_ok());
        assert!(validate_coloring(&pairs, &dynamic, &[0, 1, 1]).is_err());
        assert!(matches!(
            validate_coloring(&pairs, &dynamic, &[0, 99, 1]),
            Err(ColoringError::ColorOutOfRange { .. })
        ));
        // Overflow may share anything.
        assert!(validate_coloring(&pairs, &dynamic, &[OVERFLOW_COLOR; 3]).is_ok());
    }

    #[test]
    fn rounds_give_a_valid_coloring_keep_free_seeds_and_skip_empty_pairs() {
        // A star of 30 dynamic bodies around body 0, plus a chain on a fixed floor (body 31).
        let mut pairs: Vec<(u32, u32)> = (1..31).map(|i| (0, i)).collect();
        pairs.extend((1..30).map(|i| (i, i + 1)));
        pairs.extend((1..31).map(|i| (i, 31)));
        let mut dynamic = vec![true; 31];
        dynamic.push(false);
        let mut candidates: Vec<ColorCandidate> = pairs
            .iter()
            .map(|&bodies| ColorCandidate {
                bodies,
                touching: true,
                seed: None,
            })
            .collect();
        candidates.push(ColorCandidate {
            bodies: (2, 5),
            touching: false,
            seed: None,
        });
        let colors = color_in_rounds(&candidates, &dynamic);
        assert_eq!(colors[pairs.len()], EMPTY_COLOR);
        validate_coloring(&pairs, &dynamic, &colors[..pairs.len()]).unwrap();
        // The star's centre holds only 24 colors: the rest of its constraints overflow.
        let overflow = colors[..30]
            .iter()
            .filter(|&&c| c == OVERFLOW_COLOR)
            .count();
        assert_eq!(overflow, 30 - GRAPH_COLOR_COUNT);
        // A free seed is taken in round 0.
        let seeded = [ColorCandidate {
            bodies: (0, 1),
            touching: true,
            seed: Some(7),
        }];
        assert_eq!(color_in_rounds(&seeded, &[true, true]), vec![7]);
    }
}
