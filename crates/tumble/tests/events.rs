//! Contact events: a box dropped on a floor begins touching once when it lands, carries its
//! weight while it rests, and ends once when it is lifted away or removed, on every backend
//! (the GPU ones when an adapter is present; `TUMBLE_REQUIRE_GPU=1` makes a missing adapter a
//! failure).

mod common;

use common::*;
use tumble::prelude::*;
use tumble::{ContactEvent, ContactEventKind};

const BACKENDS: [Backend; 3] = [Backend::Cpu, Backend::Hybrid, Backend::Gpu];

/// The unit cube's mass, kg (density 1, side 1 m).
const MASS: Real = 1.0;

/// Steps of the drop: from 1 m above the floor the box lands after about 0.45 s (27 steps);
/// 90 steps leave it a second at rest.
const DROP_STEPS: usize = 90;

fn step_collecting(w: &mut World, n: usize, into: &mut Vec<(u64, ContactEvent)>) {
    for _ in 0..n {
        w.step().unwrap();
        let step = w.step_count();
        into.extend(w.contact_events().iter().map(|e| (step, *e)));
    }
}

fn count(events: &[(u64, ContactEvent)], kind: ContactEventKind) -> usize {
    events.iter().filter(|(_, e)| e.kind == kind).count()
}

/// Runs `check` on a default world of each backend that opens here (see `world_on`).
fn on_every_backend(check: fn(Backend, World)) {
    for backend in BACKENDS {
        if let Some(w) = world_on(backend, WorldConfig::default()) {
            check(backend, w);
        }
    }
}

#[test]
fn a_dropped_box_begins_once_rests_with_its_weight_and_ends_once_when_lifted() {
    on_every_backend(drop_and_lift_on);
}

fn drop_and_lift_on(backend: Backend, mut w: World) {
    let ground = floor(&mut w);
    let cube = cube_at(&mut w, 0.0, 1.5, 0.0);
    w.set_contact_events(true).unwrap();
    let mut events = Vec::new();
    // The box's vertical velocity before each step and the floor's impulse in it, for the
    // momentum balance of the landing.
    let mut history = Vec::new();
    for _ in 0..DROP_STEPS {
        let vy = w.linear_velocity(cube).unwrap().y;
        let mut one = Vec::new();
        step_collecting(&mut w, 1, &mut one);
        events.extend(one);
        let j: Real = w.touching_pairs().iter().map(|p| p.normal_impulse).sum();
        history.push((vy, j));
    }
    // One pair, one landing: a speculative contact catches the box, it neither bounces off
    // (restitution 0) nor flickers while resting, so exactly one begin and no end.
    assert_eq!(
        count(&events, ContactEventKind::Begin),
        1,
        "{backend:?}: {events:?}"
    );
    assert_eq!(
        count(&events, ContactEventKind::End),
        0,
        "{backend:?}: {events:?}"
    );
    // Sleep is on by default, and a second at rest puts the box to sleep (the GPU backend
    // forms no pair for it then): falling asleep must end nothing, which the count above
    // checks only if the box does sleep.
    assert!(
        w.is_sleeping(cube).unwrap(),
        "{backend:?}: the box is awake after a second at rest"
    );
    let (landed, begin) = events[0];
    let (a, b) = if ground < cube {
        (ground, cube)
    } else {
        (cube, ground)
    };
    assert_eq!((begin.body_a, begin.body_b), (a, b), "{backend:?}");
    // Free fall of 1 m takes sqrt(2 / g) = 0.45 s = 27 steps: the begin comes within a few
    // steps of it (the speculative margin catches the box up to one step early).
    assert!(
        (24..=30).contains(&landed),
        "{backend:?}: landed at step {landed}"
    );
    // The floor pushed in the step the pair began.
    assert!(
        begin.normal_impulse > 0.0,
        "{backend:?}: begin impulse {}",
        begin.normal_impulse
    );
    // Momentum balance from the landing on: the floor's impulses (the touching pairs', summed
    // over the steps) stop a box falling at sqrt(2 g) = 4.4 m/s and carry its weight for the
    // rest, J = m (v_end - v_before) + m g dt * steps. Friction is horizontal and nothing else
    // touches the box, so only round-off and the resting box's last small oscillation remain:
    // 1%.
    let first = landed as usize - 1;
    let v_before = history[first].0;
    let v_end = w.linear_velocity(cube).unwrap().y;
    let total: Real = history[first..].iter().map(|(_, j)| j).sum();
    let steps = (DROP_STEPS - first) as Real;
    let expected = MASS * (v_end - v_before) + MASS * G * DT * steps;
    assert!(
        v_before < -4.0,
        "{backend:?}: hit the floor at {v_before} m/s"
    );
    assert!(
        (total - expected).abs() < 0.01 * expected,
        "{backend:?}: floor impulse {total} N s, momentum balance {expected} N s"
    );
    // The contact point lies under the box's footprint, midway between the floor's top face
    // (y = 0) and the falling box: the speculative contact reaches at most the margin plus
    // the closing speed times dt (0.02 + 4.4 / 60 = 0.094 m) ahead, so its midpoint is below
    // 0.047 m.
    assert!(
        begin.point.y > -0.01 && begin.point.y < 0.047,
        "{backend:?}: {:?}",
        begin.point
    );
    assert!(begin.point.x.abs() < 0.5 && begin.point.z.abs() < 0.5);

    // At rest the floor carries the weight: m g dt per step. 2% allows the soft contact's
    // residual oscillation a second after landing (the solver's own rest test is tighter).
    let touching = w.touching_pairs();
    assert_eq!(touching.len(), 1, "{backend:?}");
    let expected = MASS * G * DT;
    let impulse = touching[0].normal_impulse;
    assert!(
        (impulse - expected).abs() < 0.02 * expected,
        "{backend:?}: resting impulse {impulse}, m g dt = {expected}"
    );
    // Under a centred box at rest the impulse-weighted point is the footprint's centre.
    let p = touching[0].point;
    assert!(
        p.x.abs() < 0.01 && p.z.abs() < 0.01 && p.y.abs() < 0.01,
        "{p:?} pose {:?} contacts {:?}",
        w.pose(cube).unwrap(),
        w.contacts()
    );

    // Lifted 2 m and thrown upward: the pair ends at the next step, once, and nothing else
    // happens while the box is away (at 3 m/s it rises for 0.3 s, 18 steps).
    w.set_pose(cube, Pose::translation(0.0, 2.5, 0.0)).unwrap();
    w.set_linear_velocity(cube, Vec3::new(0.0, 3.0, 0.0))
        .unwrap();
    let mut after = Vec::new();
    step_collecting(&mut w, 15, &mut after);
    assert_eq!(after.len(), 1, "{backend:?}: {after:?}");
    let (step, end) = after[0];
    assert_eq!(end.kind, ContactEventKind::End);
    assert_eq!((end.body_a, end.body_b), (a, b));
    assert_eq!(
        step,
        DROP_STEPS as u64 + 1,
        "{backend:?}: ended at step {step}"
    );
    assert!(w.touching_pairs().is_empty());
}

#[test]
fn removing_a_touching_body_ends_its_pair_once() {
    on_every_backend(remove_on);
}

fn remove_on(backend: Backend, mut w: World) {
    let ground = floor(&mut w);
    let cube = cube_at(&mut w, 0.0, 0.5, 0.0);
    let other = cube_at(&mut w, 3.0, 0.5, 0.0);
    w.set_contact_events(true).unwrap();
    let mut events = Vec::new();
    step_collecting(&mut w, 5, &mut events);
    // Both boxes start resting on the floor: two begins at the first step, sorted by pair.
    assert_eq!(events.len(), 2, "{backend:?}: {events:?}");
    assert!(
        events
            .iter()
            .all(|(s, e)| *s == 1 && e.kind == ContactEventKind::Begin)
    );
    let pairs: Vec<_> = events.iter().map(|(_, e)| (e.body_a, e.body_b)).collect();
    let mut sorted = pairs.clone();
    sorted.sort();
    assert_eq!(pairs, sorted, "{backend:?}: events not sorted by pair");

    w.remove_body(cube).unwrap();
    let mut after = Vec::new();
    step_collecting(&mut w, 5, &mut after);
    // The removed box's pair ends at the next step, once; the other box keeps resting.
    assert_eq!(after.len(), 1, "{backend:?}: {after:?}");
    let (step, end) = after[0];
    assert_eq!(step, 6);
    assert_eq!(end.kind, ContactEventKind::End);
    let (a, b) = if ground < cube {
        (ground, cube)
    } else {
        (cube, ground)
    };
    assert_eq!((end.body_a, end.body_b), (a, b));
    assert_eq!(w.touching_pairs().len(), 1);
    assert!(w.contains(other));
}

#[test]
fn events_off_compute_nothing_and_change_no_result() {
    for backend in BACKENDS {
        let Some(mut on) = world_on(backend, WorldConfig::default()) else {
            continue;
        };
        let mut off = world_on(backend, WorldConfig::default()).unwrap();
        let mut cubes = Vec::new();
        for w in [&mut on, &mut off] {
            floor(w);
            cubes.push(cube_at(w, 0.0, 1.5, 0.0));
            cubes.push(cube_at(w, 0.2, 2.7, 0.1));
        }
        on.set_contact_events(true).unwrap();
        assert!(!off.contact_events_enabled());
        let mut begins = 0;
        for _ in 0..60 {
            on.step().unwrap();
            off.step().unwrap();
            begins += on.contact_events().len();
            assert!(off.contact_events().is_empty() && off.touching_pairs().is_empty());
        }
        // Two boxes falling onto the floor and each other touched: events were produced.
        assert!(begins >= 2, "{backend:?}: {begins} events");
        for (&a, &b) in cubes[..2].iter().zip(&cubes[2..]) {
            let (pa, pb) = (on.pose(a).unwrap(), off.pose(b).unwrap());
            assert_eq!(pa, pb, "{backend:?}: events changed the result");
        }
        // Turned off, the world forgets its pairs; on again, the next step begins every
        // pair that touches then.
        on.set_contact_events(false).unwrap();
        on.step().unwrap();
        assert!(on.contact_events().is_empty());
        on.set_contact_events(true).unwrap();
        on.step().unwrap();
        let touching = on.touching_pairs().len();
        assert!(touching >= 1);
        assert_eq!(on.contact_events().len(), touching, "{backend:?}");
    }
}
