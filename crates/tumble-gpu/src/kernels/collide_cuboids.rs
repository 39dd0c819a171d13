//! `collide_cuboids`: the box-box narrow phase, one manifold per candidate pair.

use tumble_geometry::{Cuboid, FeatureKind, Manifold, Vec3};

use crate::constants::{MANIFOLD_EDGE, MANIFOLD_FACE_A, MANIFOLD_FACE_B};
use crate::kernel::{KernelArgs, KernelSpec};
use crate::kernels::update_aabbs::pose_from_gpu;
use crate::layout::{GpuPose, GpuShape, GpuVelocity};
use crate::shader::{Binding, ShaderSource, common, wgsl_file};

/// The kernel: one thread per pair.
pub static COLLIDE_CUBOIDS: KernelSpec = KernelSpec {
    name: "collide_cuboids",
    source: ShaderSource {
        common: common::NARROW_PHASE,
        kernel: wgsl_file!("collide_cuboids.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`COLLIDE_CUBOIDS`].
pub struct CollideCuboidsArgs<'a> {
    /// [`crate::layout::NarrowParams`].
    pub params: &'a wgpu::Buffer,
    /// This step's pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// Sorted pairs, first bodies.
    pub pair_a: &'a wgpu::Buffer,
    /// Sorted pairs, second bodies.
    pub pair_b: &'a wgpu::Buffer,
    /// `array<GpuPose>`.
    pub poses: &'a wgpu::Buffer,
    /// `array<GpuVelocity>` (for the speculative margin).
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuShape>`.
    pub shapes: &'a wgpu::Buffer,
    /// From `match_pairs`.
    pub previous_index: &'a wgpu::Buffer,
    /// Last step's manifolds (for the reference-face hysteresis).
    pub previous_manifolds: &'a wgpu::Buffer,
    /// Output manifolds, one per pair.
    pub manifolds: &'a wgpu::Buffer,
    /// Output points, `MAX_MANIFOLD_POINTS` per pair.
    pub contacts: &'a wgpu::Buffer,
}

impl KernelArgs for CollideCuboidsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.work,
            self.pair_a,
            self.pair_b,
            self.poses,
            self.velocities,
            self.shapes,
            self.previous_index,
            self.previous_manifolds,
            self.manifolds,
            self.contacts,
        ]
    }
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
