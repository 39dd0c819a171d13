//! The CPU time of the step's broad phase (`tumble_broad::BroadPhase`) per call, on the
//! scenes of `benches/benches/broad_phase.rs`: the resting pyramid of 50 (the floor flagged
//! immovable) and 100,000 random boxes. On a shared machine wall time counts the waits for a
//! core; this counts only the time this thread ran (the first field of
//! `/proc/thread-self/schedstat`, Linux), so it is a second view beside criterion's.
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin broad_cpu_time -- [CALLS] [pyramid|random]
//! ```
//!
//! Prints per scene: boxes, pairs, an FNV-1a hash of the pair list (the same list gives the
//! same hash, to compare two builds), the mean CPU time per call over `CALLS` calls (default
//! 200) after 5 warm-up calls, and the median and minimum wall time per call. The CPU time is
//! read once around the whole loop: the kernel updates it at scheduler ticks (a few ms), too
//! coarse for one call, exact enough over a loop of a second or more. A scene name runs that
//! scene only (for `perf record`).

use std::time::Instant;

use tumble_broad::BroadPhase;
use tumble_geometry::Aabb;
use tumble_scenes::pyramid;
use tumble_tests::scene_support::{resting_aabbs, sparse_boxes};

/// The CPU time this thread has run, in nanoseconds (`None` off Linux).
fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// FNV-1a over the pairs' indices, little-endian.
fn hash(pairs: &[(u32, u32)]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325_u64;
    for &(i, j) in pairs {
        for b in i.to_le_bytes().into_iter().chain(j.to_le_bytes()) {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn measure(name: &str, boxes: &[Aabb], flags: &[bool], calls: usize) {
    let mut grid = BroadPhase::new();
    let mut pairs = Vec::new();
    for _ in 0..5 {
        grid.find_pairs_filtered(boxes, flags, &mut pairs).unwrap();
    }
    let mut wall = Vec::new();
    let c0 = thread_cpu_ns();
    for _ in 0..calls {
        let w0 = Instant::now();
        grid.find_pairs_filtered(boxes, flags, &mut pairs).unwrap();
        wall.push(w0.elapsed().as_secs_f64() * 1e3);
    }
    let cpu_text = match (c0, thread_cpu_ns()) {
        (Some(c0), Some(c1)) if calls > 0 => {
            format!("mean {:.3} ms", (c1 - c0) as f64 * 1e-6 / calls as f64)
        }
        _ => "n/a".to_string(),
    };
    let wall_min = wall.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "{name}: {} boxes, {} pairs, hash {:016x}; cpu {cpu_text}; wall median {:.3} ms, min {:.3} ms",
        boxes.len(),
        pairs.len(),
        hash(&pairs),
        median(&mut wall),
        wall_min,
    );
}

fn main() {
    let calls: usize = std::env::args()
        .nth(1)
        .map(|a| match a.parse() {
            Ok(calls) if calls > 0 => calls,
            _ => panic!("CALLS must be a positive whole number, not {a:?}"),
        })
        .unwrap_or(200);
    let only = std::env::args().nth(2);
    let runs = |scene: &str| only.as_deref().is_none_or(|o| o == scene);
    if runs("pyramid") {
        let (boxes, flags) = resting_aabbs(&pyramid(50));
        measure("resting pyramid of 50", &boxes, &flags, calls);
    }
    if runs("random") {
        let n = 100_000;
        // As the bench's `random_boxes`: 0.3 boxes per cubic meter, seeded by the count.
        let boxes = sparse_boxes(n, (n as f32 / 0.3).cbrt(), n as u64);
        measure("100,000 random boxes", &boxes, &vec![false; n], calls);
    }
}
