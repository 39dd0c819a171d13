//! The visiting order of the constraints (colored against sequential), the solve statistics,
//! and a step's gravity and rotation effects.

use tumble_geometry::Point3;

use super::*;
use crate::tests::{G, assert_close, floor, manifold, solve_copy};
use crate::{Coloring, SolveOrder};

fn column(n: usize) -> (Vec<Body>, Vec<BodyState>, Vec<Contact>) {
    let m = material(0.6, 0.0);
    let mut bodies = vec![floor(m)];
    let mut contacts = Vec::new();
    for k in 0..n {
        // Slightly sunk and moving, so every contact has work to do.
        let cube = unit_cube(
            1.0,
            Pose::new(
                Vec3::new(0.0, 0.49 + k as Real * 0.99, 0.0),
                Vec3::new(0.0, 0.0, 0.02 * k as Real),
            ),
            m,
        );
        let mut mf = floor_corners(&cube);
        for p in mf.contacts.iter_mut() {
            p.depth += k as Real * 0.99;
            p.position.y += 0.5 * k as Real * 0.99;
        }
        contacts.push(Contact::new(k as u32, k as u32 + 1, mf));
        bodies.push(cube);
    }
    let states = (0..=n)
        .map(|k| {
            if k == 0 {
                BodyState::default()
            } else {
                BodyState::moving(Vec3::new(0.1, -0.5, 0.0), Vec3::zeros())
            }
        })
        .collect();
    (bodies, states, contacts)
}

#[test]
fn the_colored_order_is_the_sequential_order_of_the_permuted_contacts() {
    let (bodies, states0, contacts0) = column(4);
    let coloring = color_contacts(&contacts0, &bodies);
    // A column alternates two colors: contacts 0, 2 then 1, 3.
    assert_eq!(coloring.order, vec![0, 2, 1, 3]);
    let run = |contacts: &[Contact], coloring: &Coloring, order: SolveOrder| {
        let config = SolverConfig {
            order,
            ..SolverConfig::default()
        };
        let (states, contacts, _) =
            solve_copy(&bodies, &states0, contacts, coloring, &config, &gravity());
        (states, contacts)
    };
    let permuted: Vec<Contact> = coloring
        .order
        .iter()
        .map(|&i| contacts0[i as usize])
        .collect();
    let (colored_states, colored_contacts) = run(&contacts0, &coloring, SolveOrder::Colored);
    let (permuted_states, permuted_contacts) =
        run(&permuted, &Coloring::default(), SolveOrder::Sequential);
    assert_eq!(colored_states, permuted_states);
    for (k, &i) in coloring.order.iter().enumerate() {
        assert_eq!(colored_contacts[i as usize], permuted_contacts[k]);
    }
    // The order matters for Gauss-Seidel, so the comparisons above can tell orders apart.
    let (sequential_states, _) = run(&contacts0, &Coloring::default(), SolveOrder::Sequential);
    assert_ne!(sequential_states, colored_states);
    // Sequential ignores a coloring; Colored falls back to sequential for a coloring of
    // other constraints.
    assert_eq!(
        run(&contacts0, &coloring, SolveOrder::Sequential).0,
        sequential_states
    );
    let stale = color_contacts(&contacts0[..2], &bodies);
    assert_eq!(
        run(&contacts0, &stale, SolveOrder::Colored).0,
        sequential_states
    );
}

#[test]
fn solve_stats_count_constraints_points_and_parallel_colors_only() {
    // A dynamic hub touched by 30 dynamic boxes: 24 colors of one constraint each, and the
    // last 6 in the overflow set, which never runs in parallel.
    let m = material(0.5, 0.0);
    let mut bodies = vec![unit_cube(1.0, Pose::identity(), m)];
    let mut contacts = Vec::new();
    for k in 0..30 {
        let angle = k as Real * 0.2;
        let dir = Vec3::new(angle.cos(), 0.0, angle.sin());
        bodies.push(unit_cube(1.0, Pose::translation(dir.x, 0.0, dir.z), m));
        let point = Point3::from(dir * 0.5);
        let points: Vec<(Point3, Real, u32)> =
            (0..(k % 4 + 1)).map(|id| (point, 0.01, id)).collect();
        contacts.push(Contact::new(0, k + 1, manifold(dir, &points)));
    }
    let states = vec![BodyState::moving(Vec3::new(0.0, 0.0, 0.0), Vec3::zeros()); 31];
    let pairs: Vec<(u32, u32)> = contacts.iter().map(|c| (c.body_a, c.body_b)).collect();
    let dynamic = vec![true; 31];
    let coloring = color_constraints(&pairs, &dynamic);
    assert_eq!(coloring.overflow_count(), 6);
    let run = |threshold: u32| {
        let config = SolverConfig {
            parallel_threshold: threshold,
            ..SolverConfig::default()
        };
        let (states, _, stats) = solve_copy(
            &bodies,
            &states,
            &contacts,
            &coloring,
            &config,
            &Vec3::zeros(),
        );
        (stats, states)
    };
    let (wide, wide_states) = run(1);
    let points: usize = (0..30).map(|k| k % 4 + 1).sum();
    assert_eq!(
        wide,
        SolveStats {
            constraints: 30,
            points,
            parallel_batches: 24
        }
    );
    let (narrow, narrow_states) = run(2);
    assert_eq!(narrow.parallel_batches, 0);
    // The overflow set shares the hub: it is solved one constraint after another either way.
    assert_eq!(wide_states, narrow_states);
    assert!(
        narrow_states[0].linear_velocity.norm() > 0.0
            || narrow_states[1].linear_velocity.norm() > 0.0
    );
}

#[test]
fn a_step_with_gravity_off_or_rotation_off_leaves_that_motion_out() {
    let m = material(0.5, 0.0);
    let mut cube = unit_cube(1.0, Pose::translation(0.0, 5.0, 0.0), m);
    cube.angular_damping = 3.0;
    let w0 = Vec3::new(0.0, 2.0, 0.0);
    let run = |effects: &Effects| {
        let mut bodies = [cube];
        let mut states = [BodyState::moving(Vec3::zeros(), w0)];
        step(
            &mut bodies,
            &mut states,
            &mut [],
            &SolverConfig::default(),
            &gravity(),
            effects,
        );
        (bodies[0], states[0])
    };
    let (_, all) = run(&Effects::ALL);
    assert_close(
        "falls",
        all.linear_velocity.y.into(),
        f64::from(-G * DT),
        1e-5,
    );
    // Angular damping 3/s over 6 substeps of 1/360 s: w0 / (1 + 3/360)^6.
    assert_close(
        "damped spin",
        all.angular_velocity.y.into(),
        2.0 / (1.0f64 + 3.0 / 360.0).powi(6),
        1e-5,
    );
    let (_, no_gravity) = run(&Effects {
        gravity: false,
        ..Effects::ALL
    });
    assert_eq!(no_gravity.linear_velocity, Vec3::zeros());
    // Rotation off: no body turns, whatever spin it had.
    let (b, no_rotation) = run(&Effects {
        rotation: false,
        ..Effects::ALL
    });
    assert_eq!(no_rotation.angular_velocity, Vec3::zeros());
    assert_eq!(b.pose.rotation, cube.pose.rotation);
}
