//! The kernels of the collision stages, one module per kernel: its spec, its typed buffer
//! arguments; the CPU twins are the layer crates' stages, fed by the conversions below.

use tumble_geometry::{Cuboid, Vec3};
use tumble_narrow::BoxMotion;

use crate::layout::{GpuShape, GpuVelocity};

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

/// The host form of a GPU shape: the cuboid of its half extents.
pub fn cuboid_from_gpu(s: &GpuShape) -> Cuboid {
    Cuboid::new(Vec3::new(s.hx, s.hy, s.hz))
}

/// The host form of a GPU velocity: (linear, angular).
pub fn velocity_from_gpu(v: &GpuVelocity) -> (Vec3, Vec3) {
    let [lx, ly, lz, _] = v.linear;
    let [ax, ay, az, _] = v.angular;
    (Vec3::new(lx, ly, lz), Vec3::new(ax, ay, az))
}

/// What `tumble_narrow::pair_margin` needs of a GPU body.
pub fn box_motion(s: &GpuShape, v: &GpuVelocity) -> BoxMotion {
    let (linear, angular) = velocity_from_gpu(v);
    BoxMotion {
        half_extents: Vec3::new(s.hx, s.hy, s.hz),
        linear,
        angular,
    }
}
