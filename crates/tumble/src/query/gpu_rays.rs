//! [`World::cast_rays_gpu`]: a batch of rays cast on the GPU, in one dispatch, against the
//! `Backend::Gpu` world's own pose and shape buffers.

use tumble_geometry::{Point3, Real, Vec3};

use super::{RayHit, input};
use crate::{Backend, Error, World};

/// A ray `origin + t dir` of a batch ([`World::cast_rays_gpu`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Point3,
    /// Its direction: any length but zero; times of impact are in its units.
    pub dir: Vec3,
}

impl Ray {
    /// The ray from `origin` along `dir`.
    pub fn new(origin: Point3, dir: Vec3) -> Self {
        Self { origin, dir }
    }
}

/// What the GPU batch needs besides `Backend::Gpu`.
#[cfg(feature = "gpu")]
const EXPECTED_GPU_STATE: &str = "a world stepped since its last add_body, remove_body, \
    set_pose or restore (the GPU buffers receive those with the next step)";

impl World {
    /// The first body hit by each ray of `rays`, `t` in `[0, max_toi]`, cast on the GPU:
    /// one dispatch for the whole batch, one thread per ray testing every body's box in the
    /// step's own pose and shape buffers (nothing about the bodies is uploaded or read back;
    /// only the rays go up and one hit per ray comes back). The answers are
    /// [`World::cast_ray`]'s with [`crate::QueryFilter::default`]: the same slab test and
    /// conventions (`toi` in units of `dir`, a ray starting inside a body hits it at 0 with a
    /// zero normal), and of two bodies hit at the same `toi` the one first in
    /// [`World::handles`]. Both sides compute in `f32`, the GPU possibly fusing a multiply
    /// and an add where the CPU rounds twice, so a `toi` may differ from the CPU's in its
    /// last bits. The test of every body makes a batch cost rays times bodies box tests,
    /// spread over the GPU's threads.
    ///
    /// Errs, leaving the world unchanged:
    /// - on a ray whose origin or direction [`World::cast_ray`] refuses (field `origin` or
    ///   `dir`, the value naming the ray's index) and a negative or NaN `max_toi`;
    /// - on a backend other than `Backend::Gpu` (field `backend`: use [`World::cast_ray`]),
    ///   and in a build without the crate's `gpu` feature;
    /// - when the GPU buffers lag the world: bodies added, removed or moved (`set_pose`) since
    ///   the last step, or no step yet (field `world`: step first).
    pub fn cast_rays_gpu(&self, rays: &[Ray], max_toi: Real) -> Result<Vec<Option<RayHit>>, Error> {
        for (i, ray) in rays.iter().enumerate() {
            let indexed = |e: Error| match e {
                Error::InvalidValue {
                    field,
                    value,
                    expected,
                } => Error::InvalidValue {
                    field,
                    value: format!("{value} (rays[{i}])"),
                    expected,
                },
                other => other,
            };
            input::position("origin", &ray.origin).map_err(indexed)?;
            input::direction("dir", &ray.dir).map_err(indexed)?;
        }
        input::reach("max_toi", max_toi)?;
        if self.config.backend != Backend::Gpu {
            return Err(Error::InvalidValue {
                field: "backend",
                value: format!("{:?}", self.config.backend),
                expected: "Backend::Gpu (the other backends answer World::cast_ray)",
            });
        }
        self.cast_on_device(rays, max_toi)
    }

    #[cfg(feature = "gpu")]
    fn cast_on_device(&self, rays: &[Ray], max_toi: Real) -> Result<Vec<Option<RayHit>>, Error> {
        use tumble_gpu::kernels::cast_rays::{GpuRay, cast_rays};
        if self.body_count() == 0 {
            return Ok(vec![None; rays.len()]);
        }
        let lagging = |value: String| Error::InvalidValue {
            field: "world",
            value,
            expected: EXPECTED_GPU_STATE,
        };
        if self.query.edited_since_step() {
            return Err(lagging(
                "bodies added, removed or moved since the last step".into(),
            ));
        }
        let Some((ctx, draw)) = self.backend.draw_buffers() else {
            return Err(lagging("no step has put the bodies on the GPU yet".into()));
        };
        if draw.body_count as usize != self.body_count() {
            return Err(lagging(format!(
                "{} bodies on the GPU, {} in the world",
                draw.body_count,
                self.body_count()
            )));
        }
        let batch: Vec<GpuRay> = rays
            .iter()
            .map(|r| GpuRay::new(&r.origin, &r.dir))
            .collect();
        let hits = cast_rays(
            &ctx,
            &draw.poses,
            &draw.shapes,
            draw.body_count,
            &batch,
            max_toi,
        )
        .map_err(|e| crate::backend::unavailable(Backend::Gpu, e))?;
        let handles = self.handles();
        Ok(rays
            .iter()
            .zip(hits)
            .map(|(ray, hit)| {
                let (body, toi, normal) = hit.found()?;
                Some(RayHit {
                    body: handles[body as usize],
                    toi,
                    point: ray.origin + ray.dir * toi,
                    normal,
                })
            })
            .collect())
    }

    #[cfg(not(feature = "gpu"))]
    fn cast_on_device(&self, rays: &[Ray], max_toi: Real) -> Result<Vec<Option<RayHit>>, Error> {
        let _ = (rays, max_toi);
        Err(Error::BackendUnavailable {
            backend: Backend::Gpu,
            reason: "the tumble crate was built without its `gpu` feature".into(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BodyDesc, WorldConfig};

    /// The checks that need no GPU: each ray as `cast_ray` checks it (the error naming the
    /// ray's index), `max_toi`, and the backend, in every build.
    #[test]
    fn the_gpu_ray_batch_checks_its_rays_and_needs_the_gpu_backend() {
        let mut world = World::new(WorldConfig {
            backend: Backend::Cpu,
            ..Default::default()
        })
        .unwrap();
        world.add_body(BodyDesc::dynamic()).unwrap();
        world.step().unwrap();
        let down = Ray::new(Point3::new(0.0, 5.0, 0.0), -Vec3::y());
        let e = world.cast_rays_gpu(&[down], 10.0).unwrap_err();
        assert_eq!(e.field(), Some("backend"), "{e}");
        let zero = Ray::new(Point3::origin(), Vec3::zeros());
        let e = world.cast_rays_gpu(&[down, zero], 10.0).unwrap_err();
        assert_eq!(e.field(), Some("dir"));
        assert!(e.to_string().contains("rays[1]"), "{e}");
        let far = Ray::new(Point3::new(1e9, 0.0, 0.0), Vec3::x());
        let e = world.cast_rays_gpu(&[far], 10.0).unwrap_err();
        assert_eq!(e.field(), Some("origin"));
        let e = world.cast_rays_gpu(&[down], Real::NAN).unwrap_err();
        assert_eq!(e.field(), Some("max_toi"));
    }
}
