//! Determinism with sleep: two runs alike, and skipped idle steps alike to recorded ones.

use super::*;

#[test]
fn two_runs_with_sleep_give_the_same_bits_and_the_same_sleepers_at_every_step() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // The pool through settling and falling asleep (it sleeps at about step 84; 100 steps
    // cover the island searches of every step before and the first steps after).
    let bodies = uneven_pool();
    let mut a = sleeping_world(&ctx, &bodies);
    let mut b = sleeping_world(&ctx, &bodies);
    let mut slept = 0;
    for step in 0..100 {
        a.step().unwrap();
        b.step().unwrap();
        let (sa, sb) = (a.read_now(STATE).unwrap(), b.read_now(STATE).unwrap());
        assert_eq!(sa.sleeping, sb.sleeping, "step {step}: sleepers differ");
        for i in 0..bodies.len() {
            assert!(
                same_bits(&sa.poses[i], &sb.poses[i]),
                "step {step}: body {i}"
            );
        }
        slept = sa.sleeping_count();
    }
    assert_eq!(
        slept,
        bodies.len() - 1,
        "the pool did not fall asleep in the run"
    );
}

/// Steps `a` (idle steps skipped) and `b` (every step recorded) once each and checks that
/// their poses, velocities and sleeping flags agree bit for bit; the snapshot of `a`.
fn step_both_alike(a: &mut GpuWorld, b: &mut GpuWorld, step: usize) -> Snapshot {
    a.step().unwrap();
    b.step().unwrap();
    let (sa, sb) = (a.read_now(STATE).unwrap(), b.read_now(STATE).unwrap());
    assert_eq!(sa.sleeping, sb.sleeping, "step {step}: sleepers differ");
    for i in 0..sa.poses.len() {
        assert!(
            same_bits(&sa.poses[i], &sb.poses[i]),
            "step {step}: body {i}: {:?} against {:?}",
            sa.poses[i],
            sb.poses[i]
        );
        let (va, vb) = (&sa.velocities[i], &sb.velocities[i]);
        assert_eq!(
            velocity_bits(va),
            velocity_bits(vb),
            "step {step}: body {i}'s velocity"
        );
    }
    sa
}

#[test]
fn idle_steps_are_skipped_and_step_bit_for_bit_like_recorded_ones() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // The uneven pool settles and sleeps in two worlds: `a` skips the steps that would
    // repeat an idle one, `b` records every stage of every step. Skipping must change no bit
    // of any pose, velocity or sleeping flag, at every step: while settling, once asleep,
    // after a host impulse wakes the pool, and once it sleeps again.
    let bodies = uneven_pool();
    let recorded = GpuWorldConfig {
        skip_idle_steps: false,
        ..Default::default()
    };
    let mut a = sleeping_world(&ctx, &bodies);
    let mut b = sleeping_world_with(&ctx, &bodies, recorded);
    let dynamic = bodies.len() - 1;
    let mut step = 0;
    let mut asleep_at = None;
    while step < SETTLE_STEPS + 60 {
        let snap = step_both_alike(&mut a, &mut b, step);
        step += 1;
        if asleep_at.is_none() && snap.sleeping_count() == dynamic {
            asleep_at = Some(step);
        }
        if asleep_at.is_some_and(|s| step >= s + 60) {
            break;
        }
    }
    let asleep_at = asleep_at.expect("the pool fell asleep");
    assert_eq!(b.idle_steps(), 0, "skipping was off in b");
    // After the step the pool fell asleep in, one step forms no pair but still carries the
    // last contacts; the step after it is idle, and its stats arrive two steps later
    // (STATS_LAG): from then on every step is a repeat. So of the 60 steps after falling
    // asleep, all but at most 5 are skipped.
    let skipped = a.idle_steps();
    assert!(
        (55..=60).contains(&skipped),
        "{skipped} of the 60 steps after the pool fell asleep (step {asleep_at}) were skipped"
    );
    // An upward impulse on a top-layer cube (the last body) wakes the pool: both worlds must
    // move it again, and `a` must record the steps it takes to settle.
    let top = bodies.len() - 1;
    let before = a.read_now(STATE).unwrap().pose(top).translation.y;
    let mass = 1.0 / bodies[top].inverse_mass;
    for w in [&mut a, &mut b] {
        let centre = Point3::from(w.read_now(STATE).unwrap().pose(top).translation.vector);
        w.apply_impulse(top, &Vec3::new(0.0, 0.5 * mass, 0.0), &centre)
            .unwrap();
    }
    let mut highest = before;
    let mut slept_again = false;
    for _ in 0..SETTLE_STEPS {
        let snap = step_both_alike(&mut a, &mut b, step);
        step += 1;
        highest = highest.max(snap.pose(top).translation.y);
        if snap.sleeping_count() == dynamic {
            slept_again = true;
            break;
        }
    }
    // Thrown up at 0.5 m/s, the cube rises v^2 / 2g = 12.7 mm; half of that shows it moved.
    assert!(
        highest - before > 0.006,
        "the woken cube rose {} m",
        highest - before
    );
    assert!(slept_again, "the pool did not fall asleep again");
    let skipped_before = a.idle_steps();
    for _ in 0..20 {
        step_both_alike(&mut a, &mut b, step);
        step += 1;
    }
    assert!(
        a.idle_steps() - skipped_before >= 15,
        "asleep again, only {} of 20 steps were skipped",
        a.idle_steps() - skipped_before
    );
}
