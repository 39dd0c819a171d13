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
