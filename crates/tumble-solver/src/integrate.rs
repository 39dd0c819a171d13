//! Integration: semi-implicit Euler for velocities, the quaternion update for rotations, and
//! the end-of-step write of poses.

use rayon::prelude::*;
use tumble_geometry::{Pose, Real, Rot, Vec3, nalgebra::Quaternion};

use crate::{Body, BodyKind, BodyState, gyroscopic_midpoint};

/// Box2D's `B2_MAX_ROTATION = 0.25 pi`: a body turning more than an eighth of a turn in one
/// substep would skip contact features, so faster spins are clamped.
pub const MAX_ROTATION_PER_SUBSTEP: Real = 0.25 * std::f32::consts::PI;

/// Box2D v3's default `maximumLinearSpeed` of 400 m/s: a guard against runaway bodies, far
/// above anything a stable scene reaches.
pub const MAX_LINEAR_SPEED: Real = 400.0;

/// Body loops go wide from this many bodies (below, a body costs less than handing it out).
pub(crate) const PARALLEL_MIN_BODIES: usize = 2048;

/// Bodies per rayon task of a wide body loop.
const BODIES_PER_TASK: usize = 512;

/// Runs `update` on every body and its state: on the rayon pool for many bodies, in order
/// otherwise. Each call touches one body only, so the order changes no bit.
fn for_each_body<F>(bodies: &[Body], states: &mut [BodyState], update: F)
where
    F: Fn(&Body, &mut BodyState) + Sync,
{
    if bodies.len() >= PARALLEL_MIN_BODIES && rayon::current_num_threads() > 1 {
        bodies
            .par_iter()
            .zip(states.par_iter_mut())
            .with_min_len(BODIES_PER_TASK)
            .for_each(|(body, state)| update(body, state));
    } else {
        for (body, state) in bodies.iter().zip(states.iter_mut()) {
            update(body, state);
        }
    }
}

/// Resets the in-step deltas at the start of a step.
pub fn begin_step(states: &mut [BodyState]) {
    for s in states {
        s.delta_position = Vec3::zeros();
        s.delta_rotation = Rot::identity();
    }
}

/// Advances dynamic bodies' velocities by one substep `h`: gravity (times the body's gravity
/// scale), the body's force and torque, the first half of the implicit gyroscopic term,
/// damping, locks. Fixed and kinematic bodies keep their velocities.
pub fn integrate_velocities(bodies: &[Body], states: &mut [BodyState], gravity: &Vec3, h: Real) {
    integrate_velocities_with(bodies, states, Some(gravity), true, h);
}

/// [`integrate_velocities`] with effects left out: no gravity term when `gravity` is `None`,
/// no angular update (gyroscopic term, damping, locks) when `rotation` is false. For a scene
/// without gravity, or whose moving bodies all have their rotations locked, the result is
/// the same as the full update: the terms left out add zero.
pub fn integrate_velocities_with(
    bodies: &[Body],
    states: &mut [BodyState],
    gravity: Option<&Vec3>,
    rotation: bool,
    h: Real,
) {
    for_each_body(bodies, states, |body, state| {
        if body.kind != BodyKind::Dynamic {
            return;
        }
        let linear_damping = 1.0 / (1.0 + h * body.linear_damping);
        // `g * 1.0` is `g` exactly: the default scale leaves the bits of the unscaled step.
        let mut v = match gravity {
            Some(g) => state.linear_velocity + (g * body.gravity_scale) * h,
            None => state.linear_velocity,
        };
        // Skipped, not added as zero, without a force: `-0 + 0` is `+0`.
        if body.force != Vec3::zeros() {
            v += body.force * (body.inverse_mass * h);
        }
        v *= linear_damping;
        state.linear_velocity = v.component_mul(&body.locks.translation_mask());
        if !rotation {
            return;
        }

        let angular_damping = 1.0 / (1.0 + h * body.angular_damping);
        if body.torque != Vec3::zeros() {
            // The world inverse inertia at the start of the step, as the contacts use it.
            state.angular_velocity += body.inverse_inertia_world() * (body.torque * h);
        }
        gyroscopic_half_step(body, state, h);
        let w = state.angular_velocity * angular_damping;
        state.angular_velocity = w.component_mul(&body.locks.rotation_mask());
    });
}

/// Half of the substep's gyroscopic update (the implicit midpoint rule over `h / 2`).
///
/// The gyroscopic term is split around the rotation update (Strang splitting): half before the
/// contacts and the position update, half after. The rotation then turns with the angular
/// velocity of mid-substep, which keeps the world angular momentum of a free body fixed to
/// second order in `h` (with the whole term before the update it drifts by about 1% over 10 s
/// at one substep of 1/60 s); `|L|` and the energy are conserved either way.
fn gyroscopic_half_step(body: &Body, state: &mut BodyState, h: Real) {
    let w = state.angular_velocity;
    let inertia = body.inertia_local();
    let symmetric = inertia.x == inertia.y && inertia.y == inertia.z;
    // Locked axes would need the lock's reaction torque in the gyroscopic balance; locked
    // bodies skip the term (a fully locked one has no angular motion anyway). A body with
    // equal moments has (I w) x w = 0.
    if symmetric || body.locks.any_rotation() || w == Vec3::zeros() {
        return;
    }
    let rotation = state.delta_rotation * body.pose.rotation;
    let local = rotation.inverse_transform_vector(&w);
    state.angular_velocity = rotation * gyroscopic_midpoint(&inertia, &local, 0.5 * h);
}

/// Advances the deltas of dynamic and kinematic bodies by one substep `h`:
/// `dp += h v`, `dq += h/2 (0, w) dq`, renormalized (the Cayley map, a rotation about `w` by
/// `2 atan(h |w| / 2)`); then the second half of the dynamic bodies' gyroscopic update.
pub fn integrate_positions(bodies: &[Body], states: &mut [BodyState], h: Real) {
    for_each_body(bodies, states, |body, state| {
        if body.kind == BodyKind::Fixed {
            return;
        }
        if body.kind == BodyKind::Dynamic {
            clamp_speeds(state, h);
        }
        state.delta_position += state.linear_velocity * h;
        let w = state.angular_velocity;
        if w != Vec3::zeros() {
            let q = state.delta_rotation.into_inner();
            let spin = Quaternion::from_imag(w) * q * (0.5 * h);
            state.delta_rotation = Rot::new_normalize(q + spin);
        }
        if body.kind == BodyKind::Dynamic {
            gyroscopic_half_step(body, state, h);
        }
    });
}

/// Applies [`MAX_ROTATION_PER_SUBSTEP`] and [`MAX_LINEAR_SPEED`].
fn clamp_speeds(state: &mut BodyState, h: Real) {
    let max_angular = MAX_ROTATION_PER_SUBSTEP / h;
    let w = state.angular_velocity.norm();
    if w > max_angular {
        state.angular_velocity *= max_angular / w;
    }
    let v = state.linear_velocity.norm();
    if v > MAX_LINEAR_SPEED {
        state.linear_velocity *= MAX_LINEAR_SPEED / v;
    }
}

/// Writes the step's deltas into the poses: `c += dp`, `q = normalize(dq q)`.
pub fn finalize_bodies(bodies: &mut [Body], states: &mut [BodyState]) {
    let finalize = |(body, state): (&mut Body, &mut BodyState)| {
        if body.kind == BodyKind::Fixed {
            return;
        }
        let translation = body.pose.translation.vector + state.delta_position;
        let rotation = Rot::new_normalize((state.delta_rotation * body.pose.rotation).into_inner());
        body.pose = Pose::from_parts(translation.into(), rotation);
        state.delta_position = Vec3::zeros();
        state.delta_rotation = Rot::identity();
    };
    if bodies.len() >= PARALLEL_MIN_BODIES && rayon::current_num_threads() > 1 {
        bodies
            .par_iter_mut()
            .zip(states.par_iter_mut())
            .with_min_len(BODIES_PER_TASK)
            .for_each(finalize);
    } else {
        bodies.iter_mut().zip(states.iter_mut()).for_each(finalize);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Material;

    #[test]
    fn free_fall_for_one_second_matches_semi_implicit_euler() {
        let mut bodies = vec![crate::tests::body(
            BodyKind::Dynamic,
            Vec3::repeat(0.5),
            Pose::translation(0.0, 10.0, 0.0),
            1.0,
            Material::default(),
        )];
        let mut states = vec![BodyState::moving(Vec3::new(1.0, 2.0, 0.0), Vec3::zeros())];
        let gravity = Vec3::new(0.0, -9.81, 0.0);
        let (steps, substeps) = (60usize, 4usize);
        let h = 1.0 / 60.0 / substeps as Real;
        for _ in 0..steps {
            begin_step(&mut states);
            for _ in 0..substeps {
                integrate_velocities(&bodies, &mut states, &gravity, h);
                integrate_positions(&bodies, &mut states, h);
            }
            finalize_bodies(&mut bodies, &mut states);
        }
        // Semi-implicit Euler: v_k = v0 + k g h, x_n = x0 + n h v0 + g h^2 n (n + 1) / 2.
        let n = (steps * substeps) as f64;
        let hd = h as f64;
        let y = 10.0 + n * hd * 2.0 + -9.81f64 * hd * hd * n * (n + 1.0) / 2.0;
        let x = n * hd * 1.0;
        let p = bodies[0].pose.translation.vector;
        // 240 f32 additions of values up to 10 m round to at most ~240 * 1e-6 m; 1e-4 m
        // separates that from any wrong scheme (explicit Euler differs by g h t / 2 = 2 cm).
        assert!((p.y as f64 - y).abs() < 1e-4, "y {} vs {y}", p.y);
        assert!((p.x as f64 - x).abs() < 1e-4, "x {} vs {x}", p.x);
        let v = states[0].linear_velocity;
        assert!((v.y as f64 - (2.0 - 9.81 * n * hd)).abs() < 1e-4);
    }

    #[test]
    fn wide_body_loops_give_the_same_bits_as_the_sequential_ones() {
        // Enough tumbling boxes (of three shapes, so the gyroscopic term acts) for the body
        // loops to go wide; one thread runs them in order. Each body's update reads only that
        // body, so the bits must be equal.
        let n = 2 * PARALLEL_MIN_BODIES + 7;
        let bodies0: Vec<Body> = (0..n)
            .map(|i| {
                crate::tests::body(
                    if i % 11 == 0 {
                        BodyKind::Kinematic
                    } else {
                        BodyKind::Dynamic
                    },
                    Vec3::new(0.5, 0.5 + (i % 3) as Real * 0.25, 1.0),
                    Pose::translation(i as Real, 0.0, 0.0),
                    1.0,
                    Material::default(),
                )
            })
            .collect();
        let states0: Vec<BodyState> = (0..n)
            .map(|i| {
                let k = i as Real * 0.01;
                BodyState::moving(Vec3::new(k, -k, 1.0), Vec3::new(3.0 + k, 1.0, -k))
            })
            .collect();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let (mut bodies, mut states) = (bodies0.clone(), states0.clone());
                let gravity = Vec3::new(0.0, -9.81, 0.0);
                for _ in 0..5 {
                    begin_step(&mut states);
                    for _ in 0..4 {
                        integrate_velocities(&bodies, &mut states, &gravity, 1.0 / 240.0);
                        integrate_positions(&bodies, &mut states, 1.0 / 240.0);
                    }
                    finalize_bodies(&mut bodies, &mut states);
                }
                (bodies.iter().map(|b| b.pose).collect::<Vec<_>>(), states)
            })
        };
        let (poses1, states1) = run(1);
        let (poses4, states4) = run(4);
        assert_eq!(poses1, poses4);
        assert_eq!(states1, states4);
        // And the loops did move every non-fixed body (a skipped loop would also agree).
        assert!(
            poses1
                .iter()
                .zip(&bodies0)
                .all(|(p, b)| p.translation.vector != b.pose.translation.vector)
        );
    }

    #[test]
    fn kinematic_bodies_move_with_their_velocity_and_ignore_gravity() {
        let mut bodies = vec![crate::tests::body(
            BodyKind::Kinematic,
            Vec3::repeat(0.5),
            Pose::identity(),
            1.0,
            Material::default(),
        )];
        let mut states = vec![BodyState::moving(Vec3::new(1.0, 0.0, 0.0), Vec3::zeros())];
        let gravity = Vec3::new(0.0, -9.81, 0.0);
        for _ in 0..60 {
            begin_step(&mut states);
            integrate_velocities(&bodies, &mut states, &gravity, 1.0 / 60.0);
            integrate_positions(&bodies, &mut states, 1.0 / 60.0);
            finalize_bodies(&mut bodies, &mut states);
        }
        let p = bodies[0].pose.translation.vector;
        // One second at 1 m/s: x = 1 up to round-off; gravity must not act (y stays 0).
        assert!((p.x - 1.0).abs() < 1e-5 && p.y == 0.0, "{p}");
    }

    #[test]
    fn a_free_tumbling_box_keeps_its_world_angular_momentum() {
        // The 1 x 2 x 3 box spinning mostly about its major axis with a wobble, one substep of
        // 1/60 s (the coarsest the solvers use), 10 s.
        let mut bodies = vec![crate::tests::body(
            BodyKind::Dynamic,
            Vec3::new(0.5, 1.0, 1.5),
            Pose::identity(),
            1.0,
            Material::default(),
        )];
        let mut states = vec![BodyState::moving(Vec3::zeros(), Vec3::new(6.0, 1.0, 1.0))];
        let momentum = |b: &Body, s: &BodyState| {
            let local = b
                .pose
                .rotation
                .inverse_transform_vector(&s.angular_velocity);
            b.pose.rotation * b.inertia_local().component_mul(&local)
        };
        let l0 = momentum(&bodies[0], &states[0]);
        let h = 1.0 / 60.0;
        let mut worst = 0.0f32;
        for _ in 0..600 {
            begin_step(&mut states);
            integrate_velocities(&bodies, &mut states, &Vec3::zeros(), h);
            integrate_positions(&bodies, &mut states, h);
            finalize_bodies(&mut bodies, &mut states);
            worst = worst.max((momentum(&bodies[0], &states[0]) - l0).norm() / l0.norm());
        }
        // With the gyroscopic update split around the rotation the error is second order in
        // h (about 2e-4 here); the unsplit scheme drifts by 1.2%, so 1e-3 tells them apart.
        assert!(worst < 1e-3, "world L drifted by {worst}");
    }
}
