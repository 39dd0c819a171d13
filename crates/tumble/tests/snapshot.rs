//! Snapshots: a world restored mid-run (into itself, or into a new world) continues bit for
//! bit as the original; a snapshot from another backend, or one altered after it was taken,
//! is refused with the world unchanged.

mod common;

use common::*;
use tumble::prelude::*;
use tumble::{EffectSwitch, WorldSnapshot};

/// Every pose and velocity, as bits: equal bits mean the same state, not merely a close one.
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

/// A small pile that is still settling at the snapshot: tilted and spinning boxes that hit the
/// floor and each other, so warm starts, manifolds and (with sleep) rest timers all matter.
fn pile(sleep: bool) -> World {
    let mut config = WorldConfig::default();
    if sleep {
        config.effects.sleep = EffectSwitch::On;
    }
    let mut w = World::new(config).unwrap();
    floor(&mut w);
    for i in 0..6 {
        let f = i as Real;
        let rot = Rot::from_euler_angles(0.3 * f, 0.2, 0.1 * f);
        let pose = Pose::from_parts(
            Point3::new(0.3 * (f - 2.5), 0.6 + 1.1 * f, 0.1 * f).into(),
            rot,
        );
        w.add_body(
            BodyDesc::dynamic()
                .pose(pose)
                .angular_velocity(Vec3::new(0.5, -0.3 * f, 0.2)),
        )
        .unwrap();
    }
    // A removed body leaves a free slot, so the restored handle map must reuse it alike.
    let gone = cube_at(&mut w, 8.0, 0.5, 0.0);
    w.remove_body(gone).unwrap();
    w.set_contact_events(true).unwrap();
    w
}

fn run(w: &mut World, n: usize) -> Vec<Vec<u32>> {
    (0..n)
        .map(|_| {
            w.step().unwrap();
            bits(w)
        })
        .collect()
}

/// The pile after `steps` steps, and its snapshot then.
fn pile_snapshot(sleep: bool, steps: usize) -> (World, WorldSnapshot) {
    let mut w = pile(sleep);
    run(&mut w, steps);
    let snap = w.snapshot().unwrap();
    (w, snap)
}

#[test]
fn a_restored_world_continues_bit_for_bit() {
    // Without sleep the snapshot is taken while the pile still settles; with it, late enough
    // that islands fall asleep during the 60 steps after it.
    for (sleep, before) in [(false, 40), (true, 100)] {
        let (mut w, snap) = pile_snapshot(sleep, before);
        assert_eq!(snap.step_count(), before as u64);
        assert_eq!(snap.body_count(), 7);
        // The same body added after the snapshot and after the restore gets the same handle
        // (the removed body's slot, at its next generation).
        let added = cube_at(&mut w, -5.0, 0.5, 0.0);
        let original = run(&mut w, 60);
        let events = w.contact_events().to_vec();
        let asleep = w.sleeping_count();
        if sleep {
            // Some island fell asleep after the snapshot: the rest timers it carried mattered.
            assert!(asleep > 0, "nothing slept");
        }

        w.restore(&snap).unwrap();
        assert_eq!(w.step_count(), before as u64);
        assert_eq!(cube_at(&mut w, -5.0, 0.5, 0.0), added);
        assert_eq!(
            run(&mut w, 60),
            original,
            "restored in place, sleep {sleep}"
        );
        assert_eq!(w.contact_events(), &events[..]);
        assert_eq!(w.sleeping_count(), asleep);

        let mut fresh = World::from_snapshot(&snap).unwrap();
        assert_eq!(cube_at(&mut fresh, -5.0, 0.5, 0.0), added);
        assert_eq!(run(&mut fresh, 60), original, "new world, sleep {sleep}");
        assert_eq!(fresh.sleeping_count(), asleep);
    }
}

#[test]
fn snapshots_refuse_another_backend() {
    let w = pile(false);
    let snap = w.snapshot().unwrap();
    for backend in [Backend::Gpu, Backend::Hybrid] {
        let Some(mut other) = world_on(backend, WorldConfig::default()) else {
            continue;
        };
        floor(&mut other);
        let err = other.restore(&snap).unwrap_err();
        assert_eq!(err.field(), Some("backend"), "{err}");
        // The world is unchanged: its one body, no step taken.
        assert_eq!(other.body_count(), 1);
        assert_eq!(other.step_count(), 0);
        // Its own snapshot is of its own backend (tests/snapshot_gpu.rs restores them).
        assert_eq!(other.snapshot().unwrap().config().backend, backend);
    }
}

#[cfg(feature = "serde")]
mod json {
    use super::*;

    #[test]
    fn a_json_round_trip_keeps_every_bit() {
        let (mut w, snap) = pile_snapshot(true, 35);
        let text = serde_json::to_string(&snap).unwrap();
        let back: WorldSnapshot = serde_json::from_str(&text).unwrap();
        let original = run(&mut w, 40);
        let mut fresh = World::from_snapshot(&back).unwrap();
        assert_eq!(run(&mut fresh, 40), original);
    }

    #[test]
    fn an_altered_snapshot_is_refused_and_the_world_left_unchanged() {
        let (mut w, snap) = pile_snapshot(false, 10);
        let text = serde_json::to_value(&snap).unwrap();
        let before = bits(&w);
        type Alter = fn(&mut serde_json::Value);
        let cases: [(&str, Alter); 5] = [
            ("snapshot.format", |v| v["format"] = 7.into()),
            ("snapshot.states", |v| {
                v["states"].as_array_mut().unwrap().pop();
            }),
            ("snapshot.handles", |v| {
                v["handles"]["handles"][0]["generation"] = 9.into()
            }),
            ("snapshot.contacts", |v| {
                v["contacts"][0]["body_b"] = 99.into()
            }),
            ("dt", |v| v["config"]["dt"] = (-1.0).into()),
        ];
        for (field, alter) in cases {
            let mut v = text.clone();
            alter(&mut v);
            let bad: WorldSnapshot = serde_json::from_value(v).unwrap();
            let err = w.restore(&bad).unwrap_err();
            assert_eq!(err.field(), Some(field), "{err}");
            assert_eq!(bits(&w), before, "{field}: the world changed");
            assert_eq!(w.step_count(), 10);
            assert!(World::from_snapshot(&bad).is_err());
        }
    }
}
