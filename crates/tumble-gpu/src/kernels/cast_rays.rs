//! `cast_rays`: a batch of rays cast against every body's box in one dispatch, one thread per
//! ray, reading the pose and shape buffers where they already are (a `GpuWorld`'s own, see
//! `GpuWorld::draw_buffers`): nothing about the bodies is uploaded. The CPU twin is
//! `tumble_geometry::Cuboid::cast_ray` over every body, keeping the earliest hit and, of equal
//! times, the body of the lower index ([`cast_rays_cpu`]).

use bytemuck::{Pod, Zeroable};
use tumble_geometry::{Cuboid, Point3, Vec3};
use wgpu::util::DeviceExt;

use crate::buffer_pool::{STORAGE_USAGE, UNIFORM_USAGE};
use crate::error::invalid;
use crate::kernel::{Kernel, KernelSpec};
use crate::layout::{GpuPose, GpuShape, host_structs};
use crate::shader::file;
use crate::solver::convert::pose_from_gpu;
use crate::{GpuContext, GpuError};

/// The kernel: one thread per ray.
pub static CAST_RAYS: KernelSpec = KernelSpec::new(file("cast_rays.wgsl"));

host_structs! {
    /// Every struct of `common/ray_types.wgsl`, for the layout check against naga.
    pub fn ray_struct_layouts();

    /// One ray `origin + t dir`. 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuRay {
            /// Start point (world); `w` unused.
            pub origin: [f32; 4],
            /// Direction, not zero, of any length (the time of impact is in its units); `w`
            /// unused.
            pub dir: [f32; 4],
    }

    /// The closest hit of one ray. 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuRayHit {
            /// The body's outward unit normal at the hit, zero when the ray starts inside it;
            /// `w` unused.
            pub normal: [f32; 4],
            /// Time of impact, in units of the ray's direction.
            pub toi: f32,
            /// Index of the body hit (meaningless when `hit` is 0).
            pub body: u32,
            /// 1 when the ray hit a body, 0 when it hit nothing.
            pub hit: u32,
            pad _pad: u32,
    }

    /// Parameters of `cast_rays`. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct RayCastParams {
            /// Rays in the batch.
            pub rays: u32,
            /// Bodies each ray is tested against: indices `0..bodies` of the pose and shape
            /// arrays.
            pub bodies: u32,
            /// The largest time of impact a hit may have (infinity allowed).
            pub max_toi: f32,
            pad _pad: u32,
    }
}

impl GpuRay {
    /// The ray from `origin` along `dir`.
    pub fn new(origin: &Point3, dir: &Vec3) -> Self {
        Self {
            origin: [origin.x, origin.y, origin.z, 0.0],
            dir: [dir.x, dir.y, dir.z, 0.0],
        }
    }
}

impl GpuRayHit {
    /// `(body, toi, normal)` of a hit, `None` for a miss.
    pub fn found(&self) -> Option<(u32, f32, Vec3)> {
        let [x, y, z, _] = self.normal;
        (self.hit != 0).then_some((self.body, self.toi, Vec3::new(x, y, z)))
    }
}

/// Casts every ray of `rays` against the boxes of bodies `0..body_count` (`poses`: an
/// `array<GpuPose>`, `shapes`: an `array<GpuShape>`, both on `ctx`'s device and holding at
/// least `body_count` records), times of impact in `[0, max_toi]`, in one dispatch after
/// everything already submitted on `ctx`'s queue, and reads the closest hit of each back
/// (blocking, within the context's read timeout). The rays must be finite with nonzero
/// directions and `max_toi` not NaN nor negative: the facade checks them, and this errs on a
/// `max_toi` that is not, or on buffers too small for `body_count`.
pub fn cast_rays(
    ctx: &GpuContext,
    poses: &wgpu::Buffer,
    shapes: &wgpu::Buffer,
    body_count: u32,
    rays: &[GpuRay],
    max_toi: f32,
) -> Result<Vec<GpuRayHit>, GpuError> {
    if max_toi.is_nan() || max_toi < 0.0 {
        return Err(invalid("max_toi", max_toi));
    }
    let records = |size: usize| u64::from(body_count) * size as u64;
    if poses.size() < records(size_of::<GpuPose>()) {
        return Err(invalid(
            "poses",
            format!("{} bytes for {body_count} bodies", poses.size()),
        ));
    }
    if shapes.size() < records(size_of::<GpuShape>()) {
        return Err(invalid(
            "shapes",
            format!("{} bytes for {body_count} bodies", shapes.size()),
        ));
    }
    let count = u32::try_from(rays.len()).map_err(|_| invalid("rays.len()", rays.len()))?;
    if count == 0 {
        return Ok(Vec::new());
    }
    let hit_bytes = u64::from(count) * size_of::<GpuRayHit>() as u64;
    ctx.check_storage_size("ray batch", hit_bytes)?;
    let kernel = Kernel::new(ctx, &CAST_RAYS)?;
    let params = RayCastParams {
        rays: count,
        bodies: body_count,
        max_toi,
        _pad: 0,
    };
    let params = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("cast_rays params"),
            contents: bytemuck::bytes_of(&params),
            usage: UNIFORM_USAGE,
        });
    let ray_buffer = ctx.storage_buffer("cast_rays rays", rays);
    let hits = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("cast_rays hits"),
        size: hit_bytes,
        usage: STORAGE_USAGE,
        mapped_at_creation: false,
    });
    let group = kernel.bind_named(ctx, |name| match name {
        "params" => &params,
        "rays" => &ray_buffer,
        "poses" => poses,
        "shapes" => shapes,
        _ => &hits,
    });
    let mut encoder = ctx.encoder("cast_rays");
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("cast_rays"),
            timestamp_writes: None,
        });
        kernel.dispatch(&mut pass, &group, count);
    }
    ctx.submit(encoder)?;
    ctx.read_buffer(&hits, 0, u64::from(count))
}

/// The CPU twin of [`CAST_RAYS`] on host copies of the buffers: for each ray the earliest hit
/// of `Cuboid::cast_ray` over the bodies in index order, of equal times the lower index.
pub fn cast_rays_cpu(
    poses: &[GpuPose],
    shapes: &[GpuShape],
    rays: &[GpuRay],
    max_toi: f32,
) -> Vec<GpuRayHit> {
    rays.iter()
        .map(|ray| {
            let [ox, oy, oz, _] = ray.origin;
            let [dx, dy, dz, _] = ray.dir;
            let (origin, dir) = (Point3::new(ox, oy, oz), Vec3::new(dx, dy, dz));
            let mut best = GpuRayHit::default();
            for (b, (pose, shape)) in poses.iter().zip(shapes).enumerate() {
                let cuboid = Cuboid::new(Vec3::new(shape.hx, shape.hy, shape.hz));
                let Some(hit) = cuboid.cast_ray(&pose_from_gpu(pose), &origin, &dir, max_toi)
                else {
                    continue;
                };
                if best.hit == 0 || hit.toi < best.toi {
                    let n = hit.normal;
                    best = GpuRayHit {
                        normal: [n.x, n.y, n.z, 0.0],
                        toi: hit.toi,
                        body: b as u32,
                        hit: 1,
                        _pad: 0,
                    };
                }
            }
            best
        })
        .collect()
}
