//! The solve stage (`solve.rs`): a resting box's impulse, speculative points, the colored
//! solve on any number of threads.

use crate::tests::{DT, G as GRAVITY, floor, floor_corners, gravity, solve_copy, step, unit_cube};
use crate::{Body, BodyState, Contact, Effects, SolverConfig};
use crate::{Coloring, Material, SolveKernel, color_contacts};
use tumble_geometry::Pose;
use tumble_geometry::{Real, Vec3};

/// A fixed floor (top face at y = 0) and a unit cube of density 2 resting on it.
fn floor_and_cube() -> (Vec<Body>, Vec<BodyState>) {
    let m = Material::default();
    let cube = unit_cube(2.0, Pose::translation(0.0, 0.5, 0.0), m);
    (vec![floor(m), cube], vec![BodyState::default(); 2])
}

fn run_resting(config: &SolverConfig, steps: usize) -> (Body, Contact) {
    let (mut bodies, mut states) = floor_and_cube();
    let mut contact = Contact::new(0, 1, floor_corners(&bodies[1]));
    for _ in 0..steps {
        contact.manifold = floor_corners(&bodies[1]);
        let mut contacts = [contact];
        step(
            &mut bodies,
            &mut states,
            &mut contacts,
            config,
            &gravity(),
            &Effects::ALL,
        );
        contact = contacts[0];
    }
    (bodies[1], contact)
}

#[test]
fn a_resting_box_receives_m_g_dt_per_step() {
    let mass = 2.0;
    for config in [SolverConfig::default(), SolverConfig::baumgarte()] {
        let (cube, contact) = run_resting(&config, 120);
        let total: Real = contact.total_normal_impulse.iter().sum();
        let expected = mass * GRAVITY * DT;
        // At rest the contact carries the weight exactly; 1% leaves room for the residual
        // settling of a soft contact, and catches a missing substep factor (4x) or a
        // dropped warm start (the box would sink or bounce).
        assert!(
            (total - expected).abs() < 0.01 * expected,
            "{:?}: impulse {total} vs m g dt {expected}",
            config.kind
        );
        // And the box sits on the floor: at most a few mm of overlap, no drift.
        let p = cube.pose.translation.vector;
        assert!((p.y - 0.5).abs() < 0.005, "{:?}: y {}", config.kind, p.y);
        assert!(p.x.abs() < 1e-4 && p.z.abs() < 1e-4, "{p}");
    }
}

#[test]
fn speculative_points_stop_a_fast_box_at_the_gap() {
    // The cube falls at 50 m/s, 0.3 m above the floor: one step moves it 0.83 m, so only
    // the speculative points (negative depth) can stop it.
    let (mut bodies, mut states) = floor_and_cube();
    bodies[1].pose = Pose::translation(0.0, 0.8, 0.0);
    states[1].linear_velocity = Vec3::new(0.0, -50.0, 0.0);
    let mut contacts = [Contact::new(0, 1, floor_corners(&bodies[1]))];
    let config = SolverConfig::default();
    let effects = Effects::ALL;
    step(
        &mut bodies,
        &mut states,
        &mut contacts,
        &config,
        &Vec3::zeros(),
        &effects,
    );
    // The bottom face may touch the floor but not cross it by more than round-off.
    assert!(
        bodies[1].pose.translation.y > 0.5 - 1e-3,
        "{}",
        bodies[1].pose.translation.y
    );
}

/// Columns of two cubes on the floor: floor-bottom and bottom-top contacts, `n` columns.
fn columns(n: usize) -> (Vec<Body>, Vec<BodyState>, Vec<Contact>) {
    let (floor_and_first, _) = floor_and_cube();
    let mut bodies = vec![floor_and_first[0]];
    let mut contacts = Vec::new();
    for i in 0..n {
        let x = 2.0 * i as Real;
        for level in 0..2 {
            let mut cube = floor_and_first[1];
            // Slightly sunk and tilted, so the solver has real work to do.
            cube.pose = Pose::new(
                Vec3::new(x, 0.5 + level as Real - 0.01, 0.0),
                Vec3::new(0.0, 0.0, 0.01 * (i % 7) as Real),
            );
            let below = if level == 0 {
                0
            } else {
                bodies.len() as u32 - 1
            };
            let mut m = floor_corners(&cube);
            for p in m.contacts.iter_mut() {
                p.depth += level as Real;
                p.position.y += 0.5 * level as Real;
            }
            contacts.push(Contact::new(below, bodies.len() as u32, m));
            bodies.push(cube);
        }
    }
    let states = vec![BodyState::moving(Vec3::new(0.1, -1.0, 0.0), Vec3::zeros()); bodies.len()];
    (bodies, states, contacts)
}

#[test]
fn colored_parallel_solve_does_not_depend_on_threads() {
    let (bodies, states0, contacts0) = columns(300);
    let coloring = color_contacts(&contacts0, &bodies);
    let run = |threshold: u32, threads: usize| {
        let config = SolverConfig {
            parallel_threshold: threshold,
            ..Default::default()
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            solve_copy(
                &bodies,
                &states0,
                &contacts0,
                &coloring,
                &config,
                &gravity(),
            )
        })
    };
    let (serial_states, serial_contacts, serial) = run(u32::MAX, 1);
    let (wide_states, wide_contacts, wide) = run(1, 4);
    assert_eq!(serial.parallel_batches, 0);
    assert!(wide.parallel_batches >= 2, "{wide:?}");
    // Bit-for-bit: a color's constraints share no dynamic body, so gathering them in any
    // order on any number of threads computes the same floats.
    assert_eq!(serial_states, wide_states);
    assert_eq!(serial_contacts, wide_contacts);
}

#[test]
fn a_color_that_shares_a_body_is_solved_in_order_on_any_pool() {
    // 8,200 columns: 16,400 constraints, past the count from which the colors are checked on
    // the pool. The greedy coloring gives two colors (floor-bottom, bottom-top); the first
    // column's bottom-top contact is moved into the first color, which then holds two
    // constraints on the same dynamic cube. That color must be visited in order by the
    // scalar kernel (a lane block or a parallel sweep would let one write of the shared
    // cube's velocity overwrite the other), so every kernel on every pool must give the bits
    // of the scalar kernel on one thread.
    let (bodies, states0, contacts0) = columns(8200);
    let valid = color_contacts(&contacts0, &bodies);
    assert_eq!(valid.used_colors(), 2);
    let mut colors = valid.colors.clone();
    assert_ne!(
        colors[0], colors[1],
        "one column's two contacts share its bottom cube"
    );
    colors[1] = colors[0];
    let broken = Coloring::from_colors(colors);
    let run = |coloring: &Coloring, kernel: SolveKernel, threads: usize| {
        let config = SolverConfig {
            parallel_threshold: 1,
            kernel,
            ..Default::default()
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| solve_copy(&bodies, &states0, &contacts0, coloring, &config, &gravity()))
    };
    let (reference_states, reference_contacts, reference) = run(&broken, SolveKernel::Scalar, 1);
    // The broken color runs in order; the other one still spreads.
    assert_eq!(reference.parallel_batches, 1, "{reference:?}");
    assert_eq!(run(&valid, SolveKernel::Scalar, 1).2.parallel_batches, 2);
    for kernel in [SolveKernel::Scalar, SolveKernel::Lanes] {
        for threads in [1, 4] {
            let (states, contacts, stats) = run(&broken, kernel, threads);
            assert_eq!(stats.parallel_batches, 1, "{kernel:?}, {threads} threads");
            assert_eq!(states, reference_states, "{kernel:?}, {threads} threads");
            assert_eq!(
                contacts, reference_contacts,
                "{kernel:?}, {threads} threads"
            );
        }
    }
}
