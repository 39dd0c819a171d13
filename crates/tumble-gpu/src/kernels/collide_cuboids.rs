//! `collide_cuboids`: the box-box narrow phase, one manifold per candidate pair.

use tumble_geometry::{Cuboid, FeatureKind, Manifold, Vec3};

use crate::constants::{MANIFOLD_EDGE, MANIFOLD_FACE_A, MANIFOLD_FACE_B};
use crate::kernel::kernel;
use crate::kernels::update_aabbs::pose_from_gpu;
use crate::layout::{GpuPose, GpuShape, GpuVelocity};

kernel! {
    /// Buffers of [`COLLIDE_CUBOIDS`].
    pub struct CollideCuboidsArgs {
        /// [`crate::layout::NarrowParams`].
        params,
        /// This step's pair `WorkList`.
        work,
        /// Sorted pairs, first bodies.
        pair_a,
        /// Sorted pairs, second bodies.
        pair_b,
        /// `array<GpuPose>`.
        poses,
        /// `array<GpuVelocity>` (for the speculative margin).
        velocities,
        /// `array<GpuShape>`.
        shapes,
        /// From `match_pairs`.
        previous_index,
        /// Last step's manifolds (for the reference-face hysteresis).
        previous_manifolds,
        /// Output manifolds, one per pair.
        manifolds,
        /// Output points, `MAX_MANIFOLD_POINTS` per pair.
        contacts,
    }
    /// The kernel: one thread per pair.
    pub static COLLIDE_CUBOIDS = "collide_cuboids.wgsl";
}

/// `GpuManifold::kind` of a CPU feature kind.
pub fn kind_code(kind: FeatureKind) -> u32 {
    match kind {
        FeatureKind::FaceA => MANIFOLD_FACE_A,
        FeatureKind::FaceB => MANIFOLD_FACE_B,
        FeatureKind::Edge => MANIFOLD_EDGE,
    }
}

/// The CPU feature kind of a `GpuManifold::kind` code.
pub fn kind_from_code(code: u32) -> FeatureKind {
    match code {
        MANIFOLD_FACE_A => FeatureKind::FaceA,
        MANIFOLD_FACE_B => FeatureKind::FaceB,
        _ => FeatureKind::Edge,
    }
}

fn vec3(v: &[f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

/// The speculative margin of a pair: `margin` plus how far the two boxes can close in one
/// step (relative speed plus each spin's rim speed, times `dt`), the rule of the CPU world.
pub fn pair_margin(
    velocities: &[GpuVelocity],
    shapes: &[GpuShape],
    a: usize,
    b: usize,
    margin: f32,
    dt: f32,
) -> f32 {
    let half = |i: usize| Vec3::new(shapes[i].hx, shapes[i].hy, shapes[i].hz);
    let (va, vb) = (&velocities[a], &velocities[b]);
    let closing = (vec3(&vb.linear) - vec3(&va.linear)).norm()
        + vec3(&va.angular).norm() * half(a).norm()
        + vec3(&vb.angular).norm() * half(b).norm();
    margin + closing * dt
}

/// The CPU twin of [`COLLIDE_CUBOIDS`] for one pair: `tumble_narrow::collide_cuboids_cached`
/// with the pair's margin and last step's `(kind, feature)`.
pub fn collide_pair_cpu(
    poses: &[GpuPose],
    velocities: &[GpuVelocity],
    shapes: &[GpuShape],
    (a, b): (u32, u32),
    previous: Option<(FeatureKind, u32)>,
    margin: f32,
    dt: f32,
) -> Option<Manifold> {
    let (a, b) = (a as usize, b as usize);
    let cuboid = |i: usize| Cuboid::new(Vec3::new(shapes[i].hx, shapes[i].hy, shapes[i].hz));
    tumble_narrow::collide_cuboids_cached(
        &cuboid(a),
        &pose_from_gpu(&poses[a]),
        &cuboid(b),
        &pose_from_gpu(&poses[b]),
        pair_margin(velocities, shapes, a, b, margin, dt),
        previous,
    )
}
