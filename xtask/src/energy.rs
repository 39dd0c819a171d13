//! Mechanical energy of a scene: kinetic (translation and rotation) plus gravitational
//! potential, summed over dynamic bodies, and the energy scale that drift is measured against.

use crate::engine::BodyState;
use crate::scene_info::SceneInfo;

/// Kinetic plus potential energy of the dynamic bodies, in joules.
///
/// Potential energy is `-m g . p`: its zero is arbitrary, which is harmless because only
/// differences between two instants of the same run are ever used.
pub fn total_energy(scene: &SceneInfo, states: &[BodyState]) -> f64 {
    scene
        .bodies
        .iter()
        .zip(states)
        .filter(|(b, _)| b.dynamic)
        .map(|(b, s)| {
            let m = f64::from(b.mass);
            let v2 = f64::from(s.linear_velocity.norm_squared());
            // Rotational energy in the body frame, where the inertia tensor is diagonal.
            let w = s
                .pose
                .rotation
                .inverse_transform_vector(&s.angular_velocity);
            let rot = f64::from(w.component_mul(&w).dot(&b.inertia));
            let potential = -m * f64::from(scene.gravity.dot(&s.pose.translation.vector));
            0.5 * m * v2 + 0.5 * rot + potential
        })
        .sum()
}

/// The energy a run's drift is divided by: the initial kinetic energy plus the potential
/// energy every dynamic body would release by falling to the level of the lowest dynamic
/// body's underside. For a resting stack this is the energy a collapse would set free, so a
/// drift of 0.01 means "1 % of a full collapse's worth of energy appeared or vanished".
/// Returns `None` when the scene has no such energy (no gravity, nothing moving).
pub fn energy_scale(scene: &SceneInfo, states: &[BodyState]) -> Option<f64> {
    let up = scene.up();
    let g = f64::from(scene.gravity.norm());
    let dynamic = || scene.bodies.iter().zip(states).filter(|(b, _)| b.dynamic);
    let floor = dynamic()
        .map(|(b, s)| s.pose.translation.vector.dot(&up) - b.half_extent_along(&s.pose, &up))
        .fold(f32::INFINITY, f32::min);
    if !floor.is_finite() {
        return None;
    }
    let scale: f64 = dynamic()
        .map(|(b, s)| {
            let m = f64::from(b.mass);
            let height = f64::from(s.pose.translation.vector.dot(&up) - floor);
            let w = s
                .pose
                .rotation
                .inverse_transform_vector(&s.angular_velocity);
            let kinetic = 0.5 * m * f64::from(s.linear_velocity.norm_squared())
                + 0.5 * f64::from(w.component_mul(&w).dot(&b.inertia));
            m * g * height + kinetic
        })
        .sum();
    (scale > 0.0).then_some(scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_info::BodyInfo;
    use tumble_geometry::{Pose, Vec3};

    fn one_box(y: f32) -> SceneInfo {
        SceneInfo {
            name: "box".into(),
            bodies: vec![BodyInfo::cuboid(
                true,
                Vec3::new(0.5, 0.5, 0.5),
                2.0,
                Pose::translation(0.0, y, 0.0),
            )],
            gravity: Vec3::new(0.0, -10.0, 0.0),
            dt: 1.0 / 60.0,
        }
    }

    fn state(y: f32, vy: f32, w: Vec3) -> BodyState {
        BodyState {
            pose: Pose::translation(0.0, y, 0.0),
            linear_velocity: Vec3::new(0.0, vy, 0.0),
            angular_velocity: w,
        }
    }

    #[test]
    fn falling_converts_potential_into_kinetic_energy_exactly() {
        // Free fall from rest through h = 1.25 m at g = 10 reaches v = 5 m/s: the total must
        // not change. 1e-4 J is f32 round-off on energies of about 25 J.
        let scene = one_box(3.0);
        let before = total_energy(&scene, &[state(3.0, 0.0, Vec3::zeros())]);
        let after = total_energy(&scene, &[state(1.75, -5.0, Vec3::zeros())]);
        assert!((before - after).abs() < 1e-4, "{before} vs {after}");
    }

    #[test]
    fn spin_energy_uses_the_cuboid_inertia() {
        // A 2 kg unit cube has I = m (0.25 + 0.25) / 3 = 1/3 kg m^2 per axis; at 3 rad/s its
        // spin energy is I w^2 / 2 = 1.5 J.
        let scene = one_box(0.0);
        let still = total_energy(&scene, &[state(0.0, 0.0, Vec3::zeros())]);
        let spinning = total_energy(&scene, &[state(0.0, 0.0, Vec3::new(0.0, 0.0, 3.0))]);
        assert!(
            (spinning - still - 1.5).abs() < 1e-5,
            "{}",
            spinning - still
        );
    }

    #[test]
    fn scale_is_the_collapse_energy_of_a_stack() {
        // Two 2 kg unit cubes stacked on y = 0: the lowest underside is at 0, centres at
        // 0.5 and 1.5, so the scale is m g (0.5 + 1.5) = 2 * 10 * 2 = 40 J.
        let mut scene = one_box(0.5);
        scene.bodies.push(BodyInfo::cuboid(
            true,
            Vec3::new(0.5, 0.5, 0.5),
            2.0,
            Pose::translation(0.0, 1.5, 0.0),
        ));
        let states = [
            state(0.5, 0.0, Vec3::zeros()),
            state(1.5, 0.0, Vec3::zeros()),
        ];
        let scale = energy_scale(&scene, &states).expect("a stack under gravity has a scale");
        assert!((scale - 40.0).abs() < 1e-4, "{scale}");
    }

    #[test]
    fn no_gravity_and_no_motion_has_no_scale() {
        let mut scene = one_box(0.5);
        scene.gravity = Vec3::zeros();
        assert_eq!(
            energy_scale(&scene, &[state(0.5, 0.0, Vec3::zeros())]),
            None
        );
    }
}
