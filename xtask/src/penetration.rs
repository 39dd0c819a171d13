//! Penetration measured from poses alone, so that every engine (Tumble on any backend,
//! rapier3d) is judged by the same ruler rather than by its own contact generation.
//!
//! The ruler is the separating-axis depth of `tumble_scenes::cuboid_penetration` (the one the
//! scene checks use): for two boxes the smallest overlap over the 15 SAT axes is exactly the
//! distance one must move to separate them. parry3d's `contact` query was tried first and
//! rejected: for a unit cube resting, barely rotated (2e-5 rad), on a 100 m floor it reported
//! a 2 m overlap.

use tumble::scenes::cuboid_penetration;
use tumble_geometry::{Aabb, Cuboid};

use crate::engine::BodyState;
use crate::scene_info::SceneInfo;

/// Overlap found in one snapshot of a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PenetrationSample {
    /// Deepest overlap of any pair, in meters (0 when nothing overlaps).
    pub max: f32,
    /// Sum of the overlap depths of all touching pairs, in meters.
    pub sum: f64,
    /// Number of touching pairs (SAT overlap >= 0) that involve a dynamic body.
    pub touching: usize,
}

/// Measures every pair of boxes whose bounding boxes overlap, skipping fixed-fixed pairs.
pub fn measure_penetration(scene: &SceneInfo, states: &[BodyState]) -> PenetrationSample {
    let shapes: Vec<Cuboid> = scene
        .bodies
        .iter()
        .map(|b| Cuboid::new(b.half_extents))
        .collect();
    let aabbs: Vec<Aabb> = shapes
        .iter()
        .zip(states)
        .map(|(c, s)| c.aabb(&s.pose, 0.0))
        .collect();

    // Sweep along x: after sorting by the lower x bound, a body can only overlap the ones that
    // start before its upper x bound, which keeps big scenes near O(n log n).
    let mut order: Vec<usize> = (0..aabbs.len()).collect();
    order.sort_by(|&a, &b| aabbs[a].min.x.total_cmp(&aabbs[b].min.x));
    let mut sample = PenetrationSample::default();
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if aabbs[j].min.x > aabbs[i].max.x {
                break;
            }
            if !(scene.bodies[i].dynamic || scene.bodies[j].dynamic)
                || !aabbs[i].intersects(&aabbs[j])
            {
                continue;
            }
            // Boxes with non-finite poses are counted by the NaN metric, not here.
            if !(states[i].is_finite() && states[j].is_finite()) {
                continue;
            }
            let depth =
                cuboid_penetration(&shapes[i], &states[i].pose, &shapes[j], &states[j].pose);
            if depth >= 0.0 {
                sample.max = sample.max.max(depth);
                sample.sum += f64::from(depth);
                sample.touching += 1;
            }
        }
    }
    sample
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_info::BodyInfo;
    use tumble_geometry::{Pose, Rot, Vec3};

    /// Unit cubes at `poses`, dynamic where `dynamic` says, at rest.
    fn scene_of(poses: &[Pose], dynamic: &[bool]) -> (SceneInfo, Vec<BodyState>) {
        let half = Vec3::new(0.5, 0.5, 0.5);
        let bodies = poses
            .iter()
            .zip(dynamic)
            .map(|(p, &d)| BodyInfo::cuboid(d, half, 1.0, *p))
            .collect();
        scene_at_rest("t", bodies, poses)
    }

    /// A scene named `name` of `bodies` under Earth gravity at 60 Hz, each at rest at its pose
    /// in `poses`.
    fn scene_at_rest(
        name: &str,
        bodies: Vec<BodyInfo>,
        poses: &[Pose],
    ) -> (SceneInfo, Vec<BodyState>) {
        let states = poses
            .iter()
            .map(|p| BodyState {
                pose: *p,
                linear_velocity: Vec3::zeros(),
                angular_velocity: Vec3::zeros(),
            })
            .collect();
        let scene = SceneInfo {
            name: name.into(),
            bodies,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: 1.0 / 60.0,
        };
        (scene, states)
    }

    #[test]
    fn overlap_of_two_stacked_cubes_is_measured_exactly() {
        // Unit cubes 0.97 m apart overlap by 3 cm; parry's SAT is exact for boxes, so 1e-5 m
        // is f32 round-off only.
        let (scene, states) = scene_of(
            &[
                Pose::translation(0.0, 0.5, 0.0),
                Pose::translation(0.1, 1.47, 0.0),
            ],
            &[true, true],
        );
        let s = measure_penetration(&scene, &states);
        assert_eq!(s.touching, 1);
        assert!((s.max - 0.03).abs() < 1e-5, "{}", s.max);
        assert!((s.sum - 0.03).abs() < 1e-5, "{}", s.sum);
    }

    #[test]
    fn rotated_corner_overlap_matches_geometry() {
        // A cube turned 45 degrees about z reaches down by sqrt(2)/2 below its centre; centred
        // 1.2 m above a fixed cube's centre it dips 0.5 + 0.7071 - 1.2 = 0.0071 m into it.
        let turned = Pose::from_parts(
            Vec3::new(0.0, 1.2, 0.0).into(),
            Rot::from_axis_angle(&Vec3::z_axis(), std::f32::consts::FRAC_PI_4),
        );
        let (scene, states) = scene_of(&[Pose::identity(), turned], &[false, true]);
        let s = measure_penetration(&scene, &states);
        assert!((s.max - 0.007_106_8).abs() < 1e-5, "{}", s.max);
    }

    #[test]
    fn a_barely_turned_cube_on_a_wide_floor_is_not_deep() {
        // The case that ruled parry's query out: a cube resting on a 100 m floor (top at
        // y = 0), its centre 0.067 mm low and tilted by about 5e-5 rad, so that its lowest
        // corner is 0.115 mm into the floor. The depth along the floor normal is the cube's
        // half extent along y minus its centre's height; 1e-6 m is f32 round-off at 0.5 m.
        let q = Rot::from_quaternion(tumble_geometry::nalgebra::Quaternion::new(
            1.0,
            1.981689e-5,
            -8.684075e-6,
            2.8121787e-5,
        ));
        let cube = Pose::from_parts(Vec3::new(5.5274973, 0.49993333, -5.527504).into(), q);
        let floor = Pose::translation(0.0, -0.5, 0.0);
        let bodies = vec![
            BodyInfo::cuboid(false, Vec3::new(50.0, 0.5, 50.0), 0.0, floor),
            BodyInfo::cuboid(true, Vec3::new(0.5, 0.5, 0.5), 1.0, cube),
        ];
        let (scene, states) = scene_at_rest("floor", bodies, &[floor, cube]);
        let expected = scene.bodies[1].half_extent_along(&cube, &Vec3::y()) - cube.translation.y;
        assert!((expected - 1.15e-4).abs() < 1e-5, "{expected}");
        let s = measure_penetration(&scene, &states);
        assert!((s.max - expected).abs() < 1e-6, "{} vs {expected}", s.max);
    }

    #[test]
    fn separated_and_fixed_pairs_do_not_count() {
        // Two fixed cubes overlapping by half a meter are the level's business, not a
        // solver's; the dynamic cube 2 cm above them touches nothing.
        let (scene, states) = scene_of(
            &[
                Pose::translation(0.0, 0.0, 0.0),
                Pose::translation(0.5, 0.0, 0.0),
                Pose::translation(0.0, 1.02, 0.0),
            ],
            &[false, false, true],
        );
        let s = measure_penetration(&scene, &states);
        assert_eq!(s, PenetrationSample::default());
    }
}
