//! The facade's sleep: a box at rest sleeps, wakes by hand or when its support goes, and then
//! falls like any awake box, on every backend whose sleep stage is the CPU's.

mod common;

use common::*;
use tumble::prelude::*;

/// The backends whose sleep stage is the CPU's.
const BACKENDS: [Backend; 2] = [Backend::Cpu, Backend::Hybrid];

#[test]
fn wake_up_puts_a_sleeping_box_back_under_gravity() {
    for backend in BACKENDS {
        wake_up_on(backend);
    }
}

/// A step in which nothing can move (every body asleep or fixed) forms no pairs: its broad
/// phase list is empty, as `World::broad_phase_pairs` promises, on every such step in a row,
/// and the pair comes back when the box wakes. The CPU backend writes each step's list into
/// the array of the list before last; one left uncleared showed that old list here.
#[test]
fn a_step_where_nothing_moves_reports_no_broad_phase_pairs() {
    for backend in BACKENDS {
        let mut config = WorldConfig::default();
        config.effects.sleep = tumble::EffectSwitch::On;
        let Some(mut w) = world_on(backend, config) else {
            continue;
        };
        floor(&mut w);
        let b = cube_at(&mut w, 0.0, 0.5, 0.0);
        w.step().unwrap();
        assert_eq!(w.broad_phase_pairs().len(), 1, "{backend:?}: floor and box");
        let mut n = 0;
        while !w.is_sleeping(b).unwrap() {
            w.step().unwrap();
            n += 1;
            assert!(n <= 60, "{backend:?}: the resting box never fell asleep");
        }
        for _ in 0..3 {
            w.step().unwrap();
            assert!(
                w.broad_phase_pairs().is_empty(),
                "{backend:?}: {:?} after a step where nothing moved",
                w.broad_phase_pairs()
            );
            assert_eq!(w.stats().pairs, 0);
        }
        w.wake_up(b).unwrap();
        w.step().unwrap();
        assert_eq!(w.broad_phase_pairs().len(), 1, "{backend:?}: awake again");
    }
}

fn wake_up_on(backend: Backend) {
    let mut config = WorldConfig::default();
    config.effects.sleep = tumble::EffectSwitch::On;
    let Some(mut w) = world_on(backend, config) else {
        return;
    };
    let ground = floor(&mut w);
    let b = cube_at(&mut w, 0.0, 0.5, 0.0);
    // At rest from the start, the box sleeps after TIME_TO_SLEEP (0.5 s, 30 steps).
    let mut n = 0;
    while !w.is_sleeping(b).unwrap() {
        w.step().unwrap();
        n += 1;
        assert!(n <= 60, "{backend:?}: the resting box never fell asleep");
    }
    // Woken by hand while resting on the floor, it is awake with a fresh rest timer: it stays
    // awake for almost TIME_TO_SLEEP again before the island sleeps once more.
    w.wake_up(b).unwrap();
    assert!(!w.is_sleeping(b).unwrap());
    assert_eq!(w.sleeping_count(), 0);
    let mut again = 0;
    while !w.is_sleeping(b).unwrap() {
        w.step().unwrap();
        again += 1;
        assert!(again <= 60, "the woken box never slept again");
    }
    assert!(
        again >= 25,
        "slept again after {again} steps: the rest timer was not reset"
    );
    // Removing the floor under the sleeping box wakes it: it lost its support.
    let slept = w.pose(b).unwrap();
    w.remove_body(ground).unwrap();
    assert!(
        !w.is_sleeping(b).unwrap(),
        "the floor went, the box must wake"
    );
    assert_eq!(w.sleeping_count(), 0);
    // Awake, it falls freely. Semi-implicit Euler over K substeps of h: v = -g K h, and the
    // drop is g h^2 K (K + 1) / 2 (1.2331 m after 0.5 s, against 1/2 g t^2 = 1.2263 m): 1 mm
    // is far below either difference and far below any fall at all.
    let steps_awake = 30;
    steps(&mut w, steps_awake);
    let k = (steps_awake as i32 * substeps(&w)) as Real;
    let h = DT / substeps(&w) as Real;
    let v = w.linear_velocity(b).unwrap().y;
    assert!(
        (v + G * k * h).abs() < 1e-4,
        "v {v}, expected {}",
        -G * k * h
    );
    let drop = slept.translation.y - w.pose(b).unwrap().translation.y;
    let expected = G * h * h * k * (k + 1.0) / 2.0;
    assert!(
        (drop - expected).abs() < 1e-3,
        "fell {drop} m, expected {expected} m"
    );
    // A fresh rest timer: it does not fall back asleep in mid-air.
    assert!(!w.is_sleeping(b).unwrap());
}
