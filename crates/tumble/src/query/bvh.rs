//! The queries' acceleration structure: a bounding volume hierarchy over the bodies' tight
//! boxes (no margin), built from the world's current poses on the first query after a change
//! and dropped by every call that moves, adds or removes a body (`QueryCache::invalidate`).
//!
//! Built top down: each node's bodies are split at the median centre along the axis where the
//! centres spread most, down to [`LEAF_SIZE`] bodies a leaf. Nodes are stored in depth-first
//! order, so a node's first child is the next node and only the second's index is kept.

use std::sync::OnceLock;

use tumble_geometry::{Aabb, Cuboid, Point3, Pose, Real, Vec3};
use tumble_solver::BodyKind;

use crate::{BodyHandle, Error};

/// Most bodies in one leaf: a leaf's boxes are tested one by one, cheaper than more nodes.
pub(crate) const LEAF_SIZE: usize = 4;

/// One body as the queries see it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    pub handle: BodyHandle,
    /// Its index in the world's dense arrays when the tree was built.
    pub dense: usize,
    pub kind: BodyKind,
    pub shape: Cuboid,
    pub pose: Pose,
    pub aabb: Aabb,
}

/// A node: its box, and either a range of entries (a leaf, `count > 0`) or its second child.
#[derive(Clone, Copy, Debug)]
struct Node {
    aabb: Aabb,
    /// First entry of a leaf, or the index of the second child of an inner node.
    index: u32,
    /// Entries of a leaf; 0 for an inner node.
    count: u32,
}

/// The tree: entries reordered so that each leaf's are contiguous.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    entries: Vec<Entry>,
    nodes: Vec<Node>,
}

impl Bvh {
    /// The tree over `entries`.
    pub(crate) fn build(mut entries: Vec<Entry>) -> Self {
        let mut nodes = Vec::with_capacity(2 * entries.len().div_ceil(LEAF_SIZE));
        if !entries.is_empty() {
            let n = entries.len();
            build_node(&mut entries, 0, n, &mut nodes);
        }
        Self { entries, nodes }
    }

    /// Visits every entry whose box, grown by `grow` on each side, the segment
    /// `origin + t dir`, `t` in `[0, *max_toi]`, reaches, nearer nodes first. `visit` may
    /// shorten `*max_toi` (a closest-hit search), which prunes the nodes beyond it.
    pub(crate) fn along_ray<E>(
        &self,
        origin: &Point3,
        dir: &Vec3,
        grow: &Vec3,
        max_toi: &mut Real,
        mut visit: impl FnMut(&Entry, &mut Real) -> Result<(), E>,
    ) -> Result<(), E> {
        let entry_time = |aabb: &Aabb, max: Real| aabb.grown(grow).cast_ray(origin, dir, max);
        let Some(root) = self.nodes.first() else {
            return Ok(());
        };
        let mut stack: Vec<(usize, Real)> = Vec::new();
        if let Some(t) = entry_time(&root.aabb, *max_toi) {
            stack.push((0, t));
        }
        while let Some((i, t)) = stack.pop() {
            // `>` and not `>=`: a body at exactly the best time may still win a tie.
            if t > *max_toi {
                continue;
            }
            let node = self.nodes[i];
            if node.count > 0 {
                let start = node.index as usize;
                for e in &self.entries[start..start + node.count as usize] {
                    if entry_time(&e.aabb, *max_toi).is_some() {
                        visit(e, max_toi)?;
                    }
                }
                continue;
            }
            let (a, b) = (i + 1, node.index as usize);
            let ta = entry_time(&self.nodes[a].aabb, *max_toi);
            let tb = entry_time(&self.nodes[b].aabb, *max_toi);
            // The nearer child last, so it is popped first.
            match (ta, tb) {
                (Some(ta), Some(tb)) if ta <= tb => stack.extend([(b, tb), (a, ta)]),
                (Some(ta), Some(tb)) => stack.extend([(a, ta), (b, tb)]),
                (Some(ta), None) => stack.push((a, ta)),
                (None, Some(tb)) => stack.push((b, tb)),
                (None, None) => {}
            }
        }
        Ok(())
    }

    /// Visits every entry whose box intersects `aabb` (closed boxes).
    pub(crate) fn overlapping<E>(
        &self,
        aabb: &Aabb,
        mut visit: impl FnMut(&Entry) -> Result<(), E>,
    ) -> Result<(), E> {
        if self.nodes.is_empty() {
            return Ok(());
        }
        let mut stack = vec![0];
        while let Some(i) = stack.pop() {
            let node = self.nodes[i];
            if !node.aabb.intersects(aabb) {
                continue;
            }
            if node.count > 0 {
                let start = node.index as usize;
                for e in &self.entries[start..start + node.count as usize] {
                    if e.aabb.intersects(aabb) {
                        visit(e)?;
                    }
                }
            } else {
                stack.extend([node.index as usize, i + 1]);
            }
        }
        Ok(())
    }

    /// Every entry, in the tree's order (the linear reference path).
    #[cfg(test)]
    pub(crate) fn entries(&self) -> &[Entry] {
        &self.entries
    }
}

/// Builds the node of `entries[start..end]` and its subtree; returns its index.
fn build_node(entries: &mut [Entry], start: usize, end: usize, nodes: &mut Vec<Node>) -> usize {
    let slice = &mut entries[start..end];
    let aabb = slice[1..]
        .iter()
        .fold(slice[0].aabb, |acc, e| acc.merged(&e.aabb));
    let me = nodes.len();
    if slice.len() <= LEAF_SIZE {
        nodes.push(Node {
            aabb,
            index: start as u32,
            count: slice.len() as u32,
        });
        return me;
    }
    let first = slice[0].aabb.center();
    let (lo, hi) = slice.iter().fold((first, first), |(lo, hi), e| {
        let c = e.aabb.center();
        (lo.inf(&c), hi.sup(&c))
    });
    let spread = hi - lo;
    let axis = spread.imax();
    let mid = slice.len() / 2;
    slice.select_nth_unstable_by(mid, |a, b| {
        a.aabb.center()[axis].total_cmp(&b.aabb.center()[axis])
    });
    nodes.push(Node {
        aabb,
        index: 0,
        count: 0,
    });
    build_node(entries, start, start + mid, nodes);
    let second = build_node(entries, start + mid, end, nodes);
    nodes[me].index = second as u32;
    me
}

/// The tree of the world's current poses, built on demand. Getters take `&self`, so it
/// lives in a `OnceLock`; the calls that change the bodies take `&mut self` and drop it.
#[derive(Debug, Default)]
pub(crate) struct QueryCache {
    tree: OnceLock<Bvh>,
    /// Whether a body was added, removed or moved by the caller since the last step (or
    /// since the world was made or restored): the GPU step's buffers then lag the host.
    edited: bool,
}

impl QueryCache {
    /// The tree, built by `build` when there is none yet. A failed build keeps nothing.
    pub(crate) fn get_or_build(
        &self,
        build: impl FnOnce() -> Result<Bvh, Error>,
    ) -> Result<&Bvh, Error> {
        if let Some(tree) = self.tree.get() {
            return Ok(tree);
        }
        let tree = build()?;
        Ok(self.tree.get_or_init(|| tree))
    }

    /// Forgets the tree: the poses, the bodies or their number changed.
    pub(crate) fn invalidate(&mut self) {
        self.tree.take();
        self.edited = true;
    }

    /// A step ran: the poses changed, and every earlier edit reached the step.
    pub(crate) fn stepped(&mut self) {
        self.tree.take();
        self.edited = false;
    }

    /// Whether bodies were added, removed or moved by the caller since the last step.
    #[cfg_attr(not(feature = "gpu"), allow(dead_code))]
    pub(crate) fn edited_since_step(&self) -> bool {
        self.edited
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(i: usize, c: Vec3) -> Entry {
        let shape = Cuboid::new(Vec3::repeat(0.25));
        let pose = Pose::translation(c.x, c.y, c.z);
        Entry {
            handle: BodyHandle::from_bits(i as u64),
            dense: i,
            kind: BodyKind::Dynamic,
            shape,
            pose,
            aabb: shape.aabb(&pose, 0.0),
        }
    }

    /// A grid of 10 x 10 x 10 small boxes 1 m apart.
    fn grid() -> Bvh {
        let entries = (0..1000)
            .map(|i| {
                let c = Vec3::new((i % 10) as Real, ((i / 10) % 10) as Real, (i / 100) as Real);
                entry(i, c)
            })
            .collect();
        Bvh::build(entries)
    }

    #[test]
    fn every_entry_sits_in_one_leaf_below_boxes_that_hold_it() {
        let tree = grid();
        let mut seen = vec![0; 1000];
        for n in &tree.nodes {
            if n.count > 0 {
                assert!(n.count as usize <= LEAF_SIZE);
                for e in &tree.entries[n.index as usize..(n.index + n.count) as usize] {
                    seen[e.dense] += 1;
                    assert!(n.aabb.merged(&e.aabb) == n.aabb);
                }
            }
        }
        assert!(seen.iter().all(|&k| k == 1));
        assert_eq!(tree.entries().len(), 1000);
    }

    /// The dense indices of the tree's entries that `keep` accepts, sorted: what a traversal
    /// must visit.
    fn scan(tree: &Bvh, keep: impl Fn(&Aabb) -> bool) -> Vec<usize> {
        let mut found: Vec<usize> = tree
            .entries()
            .iter()
            .filter(|e| keep(&e.aabb))
            .map(|e| e.dense)
            .collect();
        found.sort_unstable();
        found
    }

    #[test]
    fn traversals_visit_exactly_what_a_scan_finds() {
        let tree = grid();
        let query = Aabb::new(Point3::new(2.1, 3.5, -1.0), Point3::new(4.0, 3.8, 9.5));
        let mut found: Vec<usize> = Vec::new();
        tree.overlapping::<()>(&query, |e| {
            found.push(e.dense);
            Ok(())
        })
        .unwrap();
        found.sort_unstable();
        assert_eq!(found, scan(&tree, |b| b.intersects(&query)));
        assert!(!found.is_empty());
        // A diagonal ray: every box its segment reaches, and no other.
        let (o, d) = (Point3::new(-1.0, -0.9, -1.1), Vec3::new(1.0, 1.0, 1.0));
        let mut max = 20.0;
        let mut along: Vec<usize> = Vec::new();
        tree.along_ray::<()>(&o, &d, &Vec3::zeros(), &mut max, |e, _| {
            along.push(e.dense);
            Ok(())
        })
        .unwrap();
        along.sort_unstable();
        assert_eq!(along, scan(&tree, |b| b.cast_ray(&o, &d, 20.0).is_some()));
        assert!(along.len() >= 10, "{along:?}");
    }

    #[test]
    fn an_empty_tree_visits_nothing() {
        let tree = Bvh::build(Vec::new());
        let mut max = 1.0;
        let mut n = 0;
        tree.along_ray::<()>(
            &Point3::origin(),
            &Vec3::x(),
            &Vec3::zeros(),
            &mut max,
            |_, _| {
                n += 1;
                Ok(())
            },
        )
        .unwrap();
        let all = Aabb::new(Point3::new(-1.0, -1.0, -1.0), Point3::new(1.0, 1.0, 1.0));
        tree.overlapping::<()>(&all, |_| {
            n += 1;
            Ok(())
        })
        .unwrap();
        assert_eq!(n, 0);
    }
}
