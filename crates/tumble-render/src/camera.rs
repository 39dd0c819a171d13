//! The camera: look-at and perspective, with wgpu's clip space (depth 0..1), and the same
//! projection on the host for tests and overlays computed there.

use tumble::nalgebra::{Matrix4, Vector4};
use tumble::{Point3, Vec3, World};

/// Direction from the target towards the camera of [`Camera::framing`]: from the front
/// right, above (y is up).
const FRAMING_DIRECTION: [f32; 3] = [0.55, 0.42, 0.72];

/// A perspective camera looking at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Where the camera is.
    pub eye: Point3,
    /// The point at the centre of the picture.
    pub target: Point3,
    /// The world direction that is up in the picture.
    pub up: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Near clipping distance, m.
    pub near: f32,
    /// Far clipping distance, m.
    pub far: f32,
}

impl Camera {
    /// A camera at `eye` looking at `target`, y up, 45 degrees vertical field of view, with
    /// clipping planes from a 50th to 50 times the distance between them.
    pub fn looking_at(eye: Point3, target: Point3) -> Self {
        let d = (eye - target).norm().max(1e-3);
        Self {
            eye,
            target,
            up: Vec3::y(),
            fov_y: 45f32.to_radians(),
            near: d / 50.0,
            far: d * 50.0,
        }
    }

    /// A camera that shows the sphere around `min..max` whole in a picture of `aspect`
    /// (width over height), seen from the front right and above.
    pub fn framing(min: Point3, max: Point3, aspect: f32) -> Self {
        let centre = nalgebra_centre(min, max);
        let radius = ((max - min).norm() * 0.5).max(0.05);
        // The narrower of the two fields of view decides the distance.
        let half_fov_y = 45f32.to_radians() * 0.5;
        let half_fov_x = (half_fov_y.tan() * aspect).atan();
        let half = half_fov_y.min(half_fov_x);
        let distance = radius / half.sin() * 1.02;
        let dir = Vec3::from(FRAMING_DIRECTION).normalize();
        Self::looking_at(centre + dir * distance, centre)
    }

    /// [`Camera::framing`] of the bodies that move (dynamic and kinematic ones), or of every
    /// body when all are fixed. Reads every pose (on `Backend::Gpu`, one readback).
    pub fn frame_world(world: &World, aspect: f32) -> Self {
        let mut moving = (
            Point3::from(Vec3::repeat(f32::MAX)),
            Point3::from(Vec3::repeat(f32::MIN)),
        );
        let mut all = moving;
        let grow = |b: &mut (Point3, Point3), c: Point3, r: f32| {
            b.0 = b.0.inf(&(c - Vec3::repeat(r)));
            b.1 = b.1.sup(&(c + Vec3::repeat(r)));
        };
        for &h in world.handles() {
            let (Ok(pose), Ok(half), Ok(kind)) =
                (world.pose(h), world.half_extents(h), world.kind(h))
            else {
                continue;
            };
            let c = Point3::from(pose.translation.vector);
            let r = half.norm();
            grow(&mut all, c, r);
            if kind != tumble::BodyKind::Fixed {
                grow(&mut moving, c, r);
            }
        }
        let (min, max) = if moving.0.x <= moving.1.x {
            moving
        } else {
            all
        };
        if min.x > max.x {
            return Self::framing(Point3::origin(), Point3::origin(), aspect);
        }
        Self::framing(min, max, aspect)
    }

    /// World to view space (right-handed, the camera looking down -z).
    pub fn view(&self) -> Matrix4<f32> {
        Matrix4::look_at_rh(&self.eye, &self.target, &self.up)
    }

    /// View to clip space for `aspect` (width over height), depth 0 at `near` and 1 at `far`.
    pub fn projection(&self, aspect: f32) -> Matrix4<f32> {
        let f = 1.0 / (self.fov_y * 0.5).tan();
        let (n, fa) = (self.near, self.far);
        let mut m = Matrix4::zeros();
        m[(0, 0)] = f / aspect;
        m[(1, 1)] = f;
        m[(2, 2)] = fa / (n - fa);
        m[(2, 3)] = n * fa / (n - fa);
        m[(3, 2)] = -1.0;
        m
    }

    /// World to clip space for `aspect`.
    pub fn view_projection(&self, aspect: f32) -> Matrix4<f32> {
        self.projection(aspect) * self.view()
    }

    /// Where `point` lands in a `width` x `height` picture, in pixels from the top left
    /// (pixel `(x, y)` covers `x..x + 1`), with its depth (0..1); `None` behind the camera.
    pub fn project(&self, point: Point3, width: u32, height: u32) -> Option<[f32; 3]> {
        let clip = self.view_projection(width as f32 / height as f32)
            * Vector4::new(point.x, point.y, point.z, 1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.xyz() / clip.w;
        Some([
            (ndc.x * 0.5 + 0.5) * width as f32,
            (0.5 - ndc.y * 0.5) * height as f32,
            ndc.z,
        ])
    }

    /// The radius around the target that the picture shows at the target's distance, m.
    pub(crate) fn view_radius(&self, aspect: f32) -> f32 {
        let d = (self.eye - self.target).norm();
        d * (self.fov_y * 0.5).tan() * aspect.max(1.0)
    }
}

fn nalgebra_centre(min: Point3, max: Point3) -> Point3 {
    Point3::from((min.coords + max.coords) * 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_target_projects_to_the_centre_and_the_near_plane_to_depth_zero() {
        let cam = Camera::looking_at(Point3::new(3.0, 2.0, 5.0), Point3::new(0.0, 0.5, 0.0));
        let [x, y, z] = cam.project(cam.target, 200, 100).unwrap();
        assert!(
            (x - 100.0).abs() < 1e-3 && (y - 50.0).abs() < 1e-3,
            "{x} {y}"
        );
        assert!(z > 0.0 && z < 1.0);
        let dir = (cam.target - cam.eye).normalize();
        let [_, _, near] = cam.project(cam.eye + dir * cam.near, 200, 100).unwrap();
        assert!(near.abs() < 1e-4, "{near}");
        assert!(cam.project(cam.eye - dir, 200, 100).is_none());
    }

    #[test]
    fn up_is_up_in_the_picture_and_framing_keeps_the_box_inside() {
        let cam = Camera::framing(
            Point3::new(-1.0, 0.0, -1.0),
            Point3::new(1.0, 2.0, 1.0),
            1.5,
        );
        let above = cam.project(cam.target + Vec3::y(), 300, 200).unwrap();
        assert!(above[1] < 100.0, "{above:?}");
        for corner in [Point3::new(-1.0, 0.0, -1.0), Point3::new(1.0, 2.0, 1.0)] {
            let [x, y, _] = cam.project(corner, 300, 200).unwrap();
            assert!(
                (0.0..300.0).contains(&x) && (0.0..200.0).contains(&y),
                "{x} {y}"
            );
        }
    }
}
