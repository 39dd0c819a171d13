//! `update_aabbs`: poses -> world AABBs grown by the speculative margin and swept by the
//! motion over the next step.

use tumble_geometry::{Aabb, Cuboid, Point3, Pose, Rot, Vec3};

use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::{GpuAabb, GpuPose, GpuShape, GpuVelocity};
use crate::shader::{Binding, ShaderSource, common, wgsl_file};

/// The kernel: one thread per body.
pub static UPDATE_AABBS: KernelSpec = KernelSpec {
    name: "update_aabbs",
    source: ShaderSource {
        common: &[
            common::CONSTANTS,
            common::INDEXING,
            common::LAYOUT,
            common::QUAT,
        ],
        kernel: wgsl_file!("update_aabbs.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`UPDATE_AABBS`].
pub struct UpdateAabbsArgs<'a> {
    /// [`crate::layout::UpdateAabbsParams`].
    pub params: &'a wgpu::Buffer,
    /// `array<GpuPose>`, one per body.
    pub poses: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`, one per body.
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuShape>`, one per body.
    pub shapes: &'a wgpu::Buffer,
    /// Output `array<GpuAabb>`, one per body.
    pub aabbs: &'a wgpu::Buffer,
}

impl KernelArgs for UpdateAabbsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.poses,
            self.velocities,
            self.shapes,
            self.aabbs,
        ]
    }
}

/// The host form of a GPU pose.
pub fn pose_from_gpu(p: &GpuPose) -> Pose {
    let [x, y, z, _] = p.position;
    let [i, j, k, w] = p.rotation;
    Pose::from_parts(
        tumble_geometry::nalgebra::Translation3::new(x, y, z),
        Rot::new_unchecked(tumble_geometry::nalgebra::Quaternion::new(w, i, j, k)),
    )
}

/// The CPU twin of [`UPDATE_AABBS`]: [`Aabb::from_cuboid`] grown by the margin, plus the
/// rotation bound `|w| |h| dt` on every side and the linear sweep `v dt` on its side.
pub fn update_aabbs_cpu(
    poses: &[GpuPose],
    velocities: &[GpuVelocity],
    shapes: &[GpuShape],
    margin: f32,
    dt: f32,
) -> Vec<GpuAabb> {
    poses
        .iter()
        .zip(velocities)
        .zip(shapes)
        .map(|((p, v), s)| {
            let h = Vec3::new(s.hx, s.hy, s.hz);
            let w = Vec3::new(v.angular[0], v.angular[1], v.angular[2]);
            let spin = w.norm() * h.norm() * dt;
            let tight = Aabb::from_cuboid(&Cuboid::new(h), &pose_from_gpu(p), margin + spin);
            let travel = Vec3::new(v.linear[0], v.linear[1], v.linear[2]) * dt;
            let lo: Point3 = tight.min + travel.inf(&Vec3::zeros());
            let hi: Point3 = tight.max + travel.sup(&Vec3::zeros());
            GpuAabb {
                min: [lo.x, lo.y, lo.z, 0.0],
                max: [hi.x, hi.y, hi.z, 0.0],
            }
        })
        .collect()
}
