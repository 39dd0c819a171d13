//! The kernels of the collision stages, one module per kernel: its spec, its typed buffer
//! arguments, and its CPU twin.

pub mod carry_impulses;
pub mod choose_axis;
pub mod collide_cuboids;
pub mod compact_touching;
pub mod gather_sweep_boxes;
pub mod match_pairs;
pub mod plan_dispatch;
pub mod radix_sort;
pub mod sweep_pairs;
pub mod update_aabbs;
pub mod write_sort_keys;

use crate::kernel::KernelSpec;

/// Every kernel spec of this module, for validation and layout checks.
pub fn all() -> Vec<&'static KernelSpec> {
    vec![
        &update_aabbs::UPDATE_AABBS,
        &choose_axis::CHOOSE_AXIS,
        &write_sort_keys::WRITE_SORT_KEYS,
        &radix_sort::RADIX_HISTOGRAM,
        &radix_sort::RADIX_SCAN,
        &radix_sort::RADIX_SCATTER,
        &gather_sweep_boxes::GATHER_SWEEP_BOXES,
        &sweep_pairs::SWEEP_PAIRS,
        &sweep_pairs::LONG_PAIRS,
        &plan_dispatch::PLAN_DISPATCH,
        &match_pairs::MATCH_PAIRS,
        &collide_cuboids::COLLIDE_CUBOIDS,
        &carry_impulses::CARRY_IMPULSES,
        &compact_touching::COUNT_TOUCHING,
        &compact_touching::SCAN_TOUCHING,
        &compact_touching::WRITE_TOUCHING,
        &compact_touching::SCATTER_IMPULSES,
    ]
}
