//! `rank_sort`: sorts a short `(key, value)` list in place by key, then value (equal pairs
//! keep their order), by one workgroup in one dispatch. The collision stage uses it instead
//! of the [radix sort](super::radix_sort) for lists of at most [`RANK_SORT_CAPACITY`] items,
//! where it gives the same result: the body sort's values are the bodies' input positions
//! (so the order by key, then value, is the stable order by key), and the pair sort orders
//! `(a, b)`. The radix sort's 24 dispatches of the body sort cost a column of 20 cubes
//! 0.32 ms of its 1.61 ms GPU step on an H200. The CPU twin is [`rank_sort_cpu`].

use crate::WORKGROUP_SIZE;
use crate::kernel::KernelSpec;
use crate::shader::file;

/// Items each thread of the workgroup holds.
pub const RANK_SORT_ITEMS: u32 = 4;

/// The longest list [`RANK_SORT`] sorts: its workgroup holds every key and value (8 KiB at
/// 1,024 items, within the 16 KiB of workgroup memory every WebGPU device has). Each item
/// compares itself with every other, so the work grows with the square of the length; at this
/// length it is 4,096 comparisons a thread.
pub const RANK_SORT_CAPACITY: u32 = RANK_SORT_ITEMS * WORKGROUP_SIZE;

/// Kernel: a single workgroup.
pub static RANK_SORT: KernelSpec = KernelSpec::new(file("rank_sort.wgsl"));

/// The CPU twin of [`RANK_SORT`]: `(key, value)` pairs in key, then value order, equal pairs
/// in input order.
pub fn rank_sort_cpu(keys: &[u32], values: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let mut items: Vec<(u32, u32)> = keys.iter().copied().zip(values.iter().copied()).collect();
    items.sort();
    items.into_iter().unzip()
}

/// Kernel: one workgroup per world, for a step of several worlds none of which has more than
/// [`RANK_SORT_CAPACITY`] bodies. Sorts each world's run of the body sort's `(key, body)`
/// pairs in place, as [`RANK_SORT`] sorts one list: since a key leads with its body's world
/// and each world's bodies are one run of indices, in world order, the result is the radix
/// sort's stable order of the whole list. The collision stage's step of 4,096 columns of 20
/// took 0.235 ms in the radix sort's 24 dispatches over its 86,016 bodies on an H200
/// (docs/benchmarks.md, "Batches of small worlds"). The CPU twin is
/// [`sort_world_bodies_cpu`].
pub static SORT_WORLD_BODIES: KernelSpec = KernelSpec::new(file("sort_world_bodies.wgsl"));

/// Kernels of the pair sort of a step of several worlds, none with more than
/// [`WORLD_PAIR_SORT_MAX_BODIES`] bodies: pairs counted per world, the counts scanned into
/// each world's first slot, the pairs moved into their world's run of a scratch copy, each
/// run rank-sorted by `(a, b)` into the pair list by one workgroup. Four dispatches in place
/// of the radix sort's 30, with its result (the pairs in `(a, b)` order are each world's pairs
/// in that order, world after world). The CPU twin is [`sort_world_pairs_cpu`].
pub static COUNT_WORLD_PAIRS: KernelSpec = KernelSpec::new(file("count_world_pairs.wgsl"));
/// See [`COUNT_WORLD_PAIRS`]; a single workgroup.
pub static SCAN_WORLD_PAIRS: KernelSpec = KernelSpec::new(file("scan_world_pairs.wgsl"));
/// See [`COUNT_WORLD_PAIRS`].
pub static SCATTER_WORLD_PAIRS: KernelSpec = KernelSpec::new(file("scatter_world_pairs.wgsl"));
/// See [`COUNT_WORLD_PAIRS`]; one workgroup per world.
pub static SORT_WORLD_PAIRS: KernelSpec = KernelSpec::new(file("sort_world_pairs.wgsl"));

/// The most bodies a world may have for the pair sort by world: `n (n - 1) / 2`, the most
/// pairs `n` bodies form, must fit one rank sort ([`RANK_SORT_CAPACITY`]).
pub const WORLD_PAIR_SORT_MAX_BODIES: u32 = {
    let mut n = 2;
    while (n + 1) * n / 2 <= RANK_SORT_CAPACITY {
        n += 1;
    }
    n
};

/// The CPU twin of the pair sort by world ([`COUNT_WORLD_PAIRS`] and the three after it):
/// the pairs `(a[k], b[k])` in `(a, b)` order, world by world, `world_of` giving a body's
/// world.
pub fn sort_world_pairs_cpu(
    a: &[u32],
    b: &[u32],
    world_of: impl Fn(u32) -> u32,
) -> (Vec<u32>, Vec<u32>) {
    let mut runs: Vec<Vec<(u32, u32)>> = Vec::new();
    for (&a, &b) in a.iter().zip(b) {
        let w = world_of(a) as usize;
        if runs.len() <= w {
            runs.resize(w + 1, Vec::new());
        }
        runs[w].push((a, b));
    }
    runs.into_iter()
        .flat_map(|mut run| {
            run.sort();
            run
        })
        .unzip()
}

/// The table [`SORT_WORLD_BODIES`] reads for bodies whose worlds are `worlds` (one per body):
/// `starts[w]` is world `w`'s first body and the last entry the body count, so world `w` is
/// `starts[w]..starts[w + 1]` (empty for a world without bodies). `None` when the worlds
/// decrease somewhere, so that some world's bodies are not one run.
pub fn world_body_starts(worlds: impl IntoIterator<Item = u32>) -> Option<Vec<u32>> {
    let mut starts = vec![0];
    let mut n = 0u32;
    for world in worlds {
        // A world without bodies is an empty run.
        while (starts.len() as u32) <= world {
            starts.push(n);
        }
        if world + 1 < starts.len() as u32 {
            return None;
        }
        n += 1;
    }
    starts.push(n);
    Some(starts)
}

/// The CPU twin of [`SORT_WORLD_BODIES`]: each world's run of `(key, value)` pairs sorted by
/// key, then value (`starts` as [`world_body_starts`] gives it).
pub fn sort_world_bodies_cpu(keys: &[u32], values: &[u32], starts: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let (mut sorted_keys, mut sorted_values) = (Vec::new(), Vec::new());
    for w in starts.windows(2) {
        let range = w[0] as usize..w[1] as usize;
        let (k, v) = rank_sort_cpu(&keys[range.clone()], &values[range]);
        sorted_keys.extend(k);
        sorted_values.extend(v);
    }
    (sorted_keys, sorted_values)
}
