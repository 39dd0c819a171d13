//! Islands: the groups of dynamic bodies that touch, directly or through other dynamic bodies.
//! Fixed and kinematic bodies never join two islands (they are not moved by contacts, so a
//! floor does not tie every box on it into one island).
//!
//! Built by union-find with path halving and union by size, as Box2D v2's island search and
//! rapier's `IslandManager` do the equivalent with a depth-first walk.

/// A partition of bodies into islands.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Islands {
    /// Island of each body: the smallest body index of its island, so labels do not depend on
    /// the order the links were given in. Non-dynamic bodies are islands of their own.
    pub label: Vec<u32>,
}

/// Union-find over body indices.
struct DisjointSets {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl DisjointSets {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    fn find(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            let grandparent = self.parent[self.parent[i as usize] as usize];
            self.parent[i as usize] = grandparent;
            i = grandparent;
        }
        i
    }

    fn union(&mut self, a: u32, b: u32) {
        let (mut ra, mut rb) = (self.find(a), self.find(b));
        if ra == rb {
            return;
        }
        if self.size[ra as usize] < self.size[rb as usize] {
            std::mem::swap(&mut ra, &mut rb);
        }
        self.parent[rb as usize] = ra;
        self.size[ra as usize] += self.size[rb as usize];
    }
}

impl Islands {
    /// The islands of `dynamic.len()` bodies linked by `links` (pairs of body indices); a link
    /// joins two islands only when both its bodies are dynamic.
    pub fn build(dynamic: &[bool], links: impl IntoIterator<Item = (u32, u32)>) -> Self {
        let n = dynamic.len();
        let mut sets = DisjointSets::new(n);
        for (a, b) in links {
            if dynamic[a as usize] && dynamic[b as usize] {
                sets.union(a, b);
            }
        }
        // The smallest index of each set: the first body met in index order names it.
        let mut smallest = vec![u32::MAX; n];
        let mut label = vec![0; n];
        for i in 0..n as u32 {
            let root = sets.find(i) as usize;
            if smallest[root] == u32::MAX {
                smallest[root] = i;
            }
            label[i as usize] = smallest[root];
        }
        Self { label }
    }

    /// True when bodies `a` and `b` are in one island.
    pub fn same(&self, a: usize, b: usize) -> bool {
        self.label[a] == self.label[b]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The reference: repeated relabeling until no link joins two labels.
    fn flood(dynamic: &[bool], links: &[(u32, u32)]) -> Vec<u32> {
        let mut label: Vec<u32> = (0..dynamic.len() as u32).collect();
        loop {
            let mut changed = false;
            for &(a, b) in links {
                let (a, b) = (a as usize, b as usize);
                if dynamic[a] && dynamic[b] && label[a] != label[b] {
                    let m = label[a].min(label[b]);
                    label[a] = m;
                    label[b] = m;
                    changed = true;
                }
            }
            if !changed {
                return label;
            }
        }
    }

    #[test]
    fn a_floor_does_not_join_the_boxes_on_it() {
        // Body 0 is the floor; 1-2 touch, 3 stands alone on the floor.
        let dynamic = [false, true, true, true];
        let islands = Islands::build(&dynamic, [(0, 1), (1, 2), (0, 3)]);
        assert!(islands.same(1, 2));
        assert!(!islands.same(1, 3));
        assert_eq!(islands.label, vec![0, 1, 1, 3]);
    }

    #[test]
    fn union_find_equals_flooding_on_random_graphs() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for _ in 0..50 {
            let n = rng.random_range(1..200u32);
            let dynamic: Vec<bool> = (0..n).map(|_| rng.random_bool(0.8)).collect();
            let links: Vec<(u32, u32)> = (0..rng.random_range(0..2 * n))
                .map(|_| (rng.random_range(0..n), rng.random_range(0..n)))
                .collect();
            let islands = Islands::build(&dynamic, links.iter().copied());
            assert_eq!(islands.label, flood(&dynamic, &links));
        }
    }
}
