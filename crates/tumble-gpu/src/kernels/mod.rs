//! The kernels of the collision stages, one module per kernel: its spec, its typed buffer
//! arguments; the CPU twins are the layer crates' stages, fed by the conversions below.

use tumble_geometry::{Aabb, Cuboid, FeatureKind, Manifold, Point3, Vec3};
use tumble_narrow::BoxMotion;

use crate::layout::{GpuAabb, GpuPose, GpuShape, GpuVelocity};

pub mod carry_impulses;
pub mod cast_rays;
pub mod check_motion;
pub mod choose_axis;
pub mod collide_cuboids;
pub mod compact_touching;
pub mod contact_events;
pub mod contact_summary;
pub mod forget_pairs;
pub mod gather_sweep_boxes;
pub mod match_pairs;
pub mod plan_dispatch;
pub mod radix_sort;
pub mod rank_sort;
pub mod recycle;
pub mod remap_pairs;
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

/// The host form of a GPU AABB.
pub fn aabb_from_gpu(b: &GpuAabb) -> Aabb {
    Aabb::new(
        Point3::new(b.min[0], b.min[1], b.min[2]),
        Point3::new(b.max[0], b.max[1], b.max[2]),
    )
}

/// The narrow-phase stage's pair test on GPU body arrays, what `collide_cuboids` computes for
/// pair `(a, b)`: `tumble_narrow::collide_cuboids_cached` at the pair's margin
/// (`tumble_narrow::pair_margin`) with last step's `(kind, feature)`.
pub fn collide_gpu_pair(
    poses: &[GpuPose],
    velocities: &[GpuVelocity],
    shapes: &[GpuShape],
    (a, b): (u32, u32),
    previous: Option<(FeatureKind, u32)>,
    margin: f32,
    dt: f32,
) -> Option<Manifold> {
    use crate::solver::convert::pose_from_gpu;
    let margin = gpu_pair_margin(velocities, shapes, (a, b), margin, dt);
    let (a, b) = (a as usize, b as usize);
    tumble_narrow::collide_cuboids_cached(
        &cuboid_from_gpu(&shapes[a]),
        &pose_from_gpu(&poses[a]),
        &cuboid_from_gpu(&shapes[b]),
        &pose_from_gpu(&poses[b]),
        margin,
        previous,
    )
}

/// The speculative margin `collide_cuboids` gives pair `(a, b)`: `tumble_narrow::pair_margin`
/// on the GPU body arrays, from the base `margin` and step `dt`.
pub fn gpu_pair_margin(
    velocities: &[GpuVelocity],
    shapes: &[GpuShape],
    (a, b): (u32, u32),
    margin: f32,
    dt: f32,
) -> f32 {
    let (a, b) = (a as usize, b as usize);
    tumble_narrow::pair_margin(
        &box_motion(&shapes[a], &velocities[a]),
        &box_motion(&shapes[b], &velocities[b]),
        margin,
        dt,
    )
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
