//! Snapshots on `Backend::Gpu` and `Backend::Hybrid`: the device state (pair history with its
//! warm-start impulses, colors, tilt impulses, sleep timers, lagged step statistics) is read
//! back into the snapshot and written into the restored world, which then continues bit for
//! bit; a snapshot of one backend is refused by a world of another. Small scenes and few
//! steps: these run on a software adapter in CI.

mod common;

use common::*;
use tumble::prelude::*;
use tumble::{EffectSwitch, WorldSnapshot};

/// Every pose and velocity, as bits.
fn bits(w: &World) -> Vec<u32> {
    let mut out = Vec::new();
    for &h in w.handles() {
        let p = w.pose(h).unwrap();
        let v = w.linear_velocity(h).unwrap();
        let a = w.angular_velocity(h).unwrap();
        let values = p
            .translation
            .vector
            .iter()
            .chain(p.rotation.coords.iter())
            .chain(v.iter())
            .chain(a.iter());
        out.extend(values.map(|x| x.to_bits()));
    }
    out
}

/// Four tilted, spinning boxes dropped on a floor and onto each other: at the snapshot they
/// are landing, so manifolds, warm-start impulses and tilt impulses carried from the step
/// before decide the next steps (a world that lost them would diverge in the first bits).
fn pile(backend: Backend, sleep: bool) -> Option<World> {
    let mut config = WorldConfig::default();
    if sleep {
        config.effects.sleep = EffectSwitch::On;
    }
    let mut w = world_on(backend, config)?;
    floor(&mut w);
    for i in 0..4 {
        let f = i as Real;
        let rot = Rot::from_euler_angles(0.3 * f, 0.2, 0.1 * f);
        let pose = Pose::from_parts(
            Point3::new(0.3 * (f - 1.5), 0.6 + 1.1 * f, 0.1 * f).into(),
            rot,
        );
        w.add_body(
            BodyDesc::dynamic()
                .pose(pose)
                .angular_velocity(Vec3::new(0.5, -0.3 * f, 0.2)),
        )
        .unwrap();
    }
    w.set_contact_events(true).unwrap();
    Some(w)
}

/// The state after each of `n` steps, as bits.
fn run(w: &mut World, n: usize) -> Vec<Vec<u32>> {
    (0..n)
        .map(|_| {
            w.step().unwrap();
            bits(w)
        })
        .collect()
}

/// Contacts of the last step that pushed (a positive total normal impulse).
fn touching(w: &World) -> usize {
    w.contacts()
        .iter()
        .filter(|c| c.normal_impulse() > 0.0)
        .count()
}

#[test]
fn gpu_backends_restored_mid_run_continue_bit_for_bit() {
    // Without sleep the snapshot is taken while the boxes land; with it, late enough that
    // the pile falls asleep in the steps after it (rest timers and islands carried; on
    // lavapipe the first island sleeps near step 115). Hybrid's sleep stage is the CPU's,
    // whose state the host arrays carry (tests/snapshot.rs), so it runs without.
    let runs = [
        (Backend::Gpu, false, 20, 10),
        (Backend::Gpu, true, 100, 30),
        (Backend::Hybrid, false, 20, 10),
    ];
    for (backend, sleep, before, after) in runs {
        {
            let Some(mut w) = pile(backend, sleep) else {
                return;
            };
            run(&mut w, before);
            // Contacts exist at the snapshot: their impulses are part of what is carried.
            assert!(touching(&w) >= 1, "{backend:?}: {} touching", touching(&w));
            let snap = w.snapshot().unwrap();
            assert_eq!(snap.step_count(), before as u64);
            assert_eq!(snap.config().backend, backend);
            let original = run(&mut w, after);
            let events = w.contact_events().to_vec();
            let asleep = w.sleeping_count();
            if sleep {
                assert!(
                    asleep > 0,
                    "{backend:?}: nothing fell asleep after the snapshot"
                );
            }
            // The run after the snapshot moved the boxes: equal bits below are not two
            // copies of a pile at rest.
            assert_ne!(
                original[0],
                original[after - 1],
                "{backend:?}: nothing moved"
            );

            w.restore(&snap).unwrap();
            assert_eq!(w.step_count(), before as u64);
            let again = run(&mut w, after);
            for (k, (a, b)) in original.iter().zip(&again).enumerate() {
                assert_eq!(
                    a, b,
                    "{backend:?} sleep {sleep}: restored in place, step {k}"
                );
            }
            assert_eq!(w.contact_events(), &events[..], "{backend:?}");
            assert_eq!(w.sleeping_count(), asleep, "{backend:?}");

            let mut fresh = World::from_snapshot(&snap).unwrap();
            let from_new = run(&mut fresh, after);
            for (k, (a, b)) in original.iter().zip(&from_new).enumerate() {
                assert_eq!(a, b, "{backend:?} sleep {sleep}: new world, step {k}");
            }
            assert_eq!(fresh.sleeping_count(), asleep, "{backend:?}");
        }
    }
}

#[test]
fn a_snapshot_without_its_device_state_diverges() {
    // The device state matters: the same bodies, velocities and contacts restored on the
    // CPU's snapshot path (a new GPU world uploading the host arrays, warm starts lost)
    // differ within a few steps. Shown by a world that takes the snapshot's bodies alone.
    let Some(mut w) = pile(Backend::Gpu, false) else {
        return;
    };
    run(&mut w, 25);
    let snap = w.snapshot().unwrap();
    let mut cold = World::new(*snap.config()).unwrap();
    for &h in w.handles() {
        let desc = match w.kind(h).unwrap() {
            BodyKind::Fixed => BodyDesc::fixed(),
            _ => BodyDesc::dynamic()
                .linear_velocity(w.linear_velocity(h).unwrap())
                .angular_velocity(w.angular_velocity(h).unwrap()),
        };
        let desc = desc
            .pose(w.pose(h).unwrap())
            .cuboid(w.half_extents(h).unwrap());
        cold.add_body(desc).unwrap();
    }
    let warm = run(&mut w, 5);
    let lost = run(&mut cold, 5);
    assert_ne!(warm, lost, "warm starts made no difference");
    let mut restored = World::from_snapshot(&snap).unwrap();
    assert_eq!(run(&mut restored, 5), warm);
}

#[test]
fn snapshots_are_refused_by_a_world_on_another_backend() {
    let backends = [Backend::Cpu, Backend::Gpu, Backend::Hybrid];
    for from in backends {
        let Some(mut w) = pile(from, false) else {
            return;
        };
        run(&mut w, 3);
        let snap: WorldSnapshot = w.snapshot().unwrap();
        for to in backends.into_iter().filter(|&b| b != from) {
            let Some(mut other) = world_on(to, WorldConfig::default()) else {
                return;
            };
            floor(&mut other);
            other.step().unwrap();
            let before = bits(&other);
            let err = other.restore(&snap).unwrap_err();
            assert_eq!(err.field(), Some("backend"), "{from:?} into {to:?}: {err}");
            let message = err.to_string();
            assert!(
                message.contains(&format!("{from:?}")) && message.contains(&format!("{to:?}")),
                "{message}"
            );
            // Unchanged: its one body, its one step, the same bits.
            assert_eq!(other.body_count(), 1);
            assert_eq!(other.step_count(), 1);
            assert_eq!(bits(&other), before);
        }
    }
}

#[cfg(feature = "serde")]
mod json {
    use super::*;

    #[test]
    fn a_json_round_trip_of_a_gpu_snapshot_keeps_every_bit() {
        for backend in [Backend::Gpu, Backend::Hybrid] {
            let Some(mut w) = pile(backend, true) else {
                return;
            };
            run(&mut w, 20);
            let snap = w.snapshot().unwrap();
            let text = serde_json::to_string(&snap).unwrap();
            let back: WorldSnapshot = serde_json::from_str(&text).unwrap();
            let original = run(&mut w, 15);
            let mut fresh = World::from_snapshot(&back).unwrap();
            assert_eq!(run(&mut fresh, 15), original, "{backend:?}");
        }
    }

    #[test]
    fn a_gpu_snapshot_with_altered_device_state_is_refused() {
        let Some(mut w) = pile(Backend::Gpu, false) else {
            return;
        };
        run(&mut w, 10);
        let snap = w.snapshot().unwrap();
        let value = serde_json::to_value(&snap).unwrap();
        let before = bits(&w);
        type Alter = fn(&mut serde_json::Value);
        let cases: [(&str, Alter); 3] = [
            // A buffer the device world does not hold.
            ("snapshot.device", |v| {
                v["backend"]["Gpu"]["state"]["collision"]["buffers"][0]["name"] =
                    "no such buffer".into()
            }),
            // More bytes than the buffer holds.
            ("snapshot.device", |v| {
                v["backend"]["Gpu"]["state"]["world_buffers"][0]["size"] = 4.into()
            }),
            // Handles and device bodies that disagree.
            ("snapshot.device", |v| {
                v["backend"]["Gpu"]["uploaded"]
                    .as_array_mut()
                    .unwrap()
                    .pop();
            }),
        ];
        for (field, alter) in cases {
            let mut v = value.clone();
            alter(&mut v);
            let bad: WorldSnapshot = serde_json::from_value(v).unwrap();
            let err = w.restore(&bad).unwrap_err();
            assert_eq!(err.field(), Some(field), "{err}");
            assert_eq!(bits(&w), before, "{field}: the world changed");
            assert_eq!(w.step_count(), 10);
            assert!(World::from_snapshot(&bad).is_err());
        }
        // Still usable, and still continuing as before.
        let mut fresh = World::from_snapshot(&snap).unwrap();
        assert_eq!(run(&mut w, 3), run(&mut fresh, 3));
    }
}
