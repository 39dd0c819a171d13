//! A sequence of `tumble::World` calls on the CPU backend, decoded from the input: add a body,
//! remove one, step, set a pose, set velocities, apply an impulse, set a kinematic target, all
//! with arbitrary `f32` values (NaN, infinities, subnormals, huge and tiny ones included) and
//! handles that may be stale.
//!
//! Checked: no panic; a call that returns `Err` leaves the world bitwise unchanged (the body
//! count, the handles, and every body's pose and velocities, compared bit by bit before and
//! after); after an accepted step every pose and velocity is finite (known finding `nonfinite`:
//! the world accepts finite values so large or small that the step overflows; see
//! `tumble_fuzz::skipped` and docs/reliability.md).
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tumble::{
    BodyDesc, BodyHandle, Point3, Pose, Rot, Vec3, World, WorldConfig,
    nalgebra::{Quaternion, Translation3},
};
use tumble_fuzz::{Num, skipped, vec3, vec4};

/// At most this many live bodies and calls per input: enough for stacks, contacts and removals
/// in the middle of them, small enough for thousands of sequences a second.
const MAX_BODIES: usize = 12;
const MAX_CALLS: usize = 48;

#[derive(Arbitrary, Debug)]
struct RawPose {
    translation: [Num; 3],
    /// `[x, y, z, w]`.
    rotation: [Num; 4],
    /// Passed as given (`Rot::new_unchecked`) rather than normalized first: the world says it
    /// renormalizes the rotations it is given.
    unnormalized: bool,
}

impl RawPose {
    fn get(&self) -> Pose {
        let [x, y, z, w] = vec4(self.rotation);
        let q = Quaternion::new(w, x, y, z);
        let r = if self.unnormalized {
            Rot::new_unchecked(q)
        } else {
            Rot::new_normalize(q)
        };
        Pose::from_parts(Translation3::from(Vec3::from(vec3(self.translation))), r)
    }
}

#[derive(Arbitrary, Debug)]
enum Call {
    Add {
        kind: u8,
        half_extents: [Num; 3],
        pose: RawPose,
        density: Num,
        friction: Num,
        restitution: Num,
        linear_velocity: [Num; 3],
        angular_velocity: [Num; 3],
        locks: u8,
        linear_damping: Num,
        angular_damping: Num,
    },
    Remove(u8),
    Step,
    SetPose(u8, RawPose),
    SetLinearVelocity(u8, [Num; 3]),
    SetAngularVelocity(u8, [Num; 3]),
    ApplyImpulse(u8, [Num; 3], [Num; 3]),
    SetKinematicTarget(u8, RawPose),
}

/// Everything a call may change, as bits (so that NaN compares equal to itself and -0 differs
/// from 0).
fn snapshot(world: &World) -> (usize, Vec<BodyHandle>, Vec<u32>) {
    let bits = world
        .handles()
        .iter()
        .flat_map(|&h| state(world, h))
        .map(f32::to_bits)
        .collect();
    (world.body_count(), world.handles().to_vec(), bits)
}

/// Body `h`'s 13 state numbers: position, rotation quaternion, linear and angular velocity.
fn state(world: &World, h: BodyHandle) -> Vec<f32> {
    let pose = world.pose(h).expect("a listed handle is live");
    let v = world.linear_velocity(h).expect("a listed handle is live");
    let w = world.angular_velocity(h).expect("a listed handle is live");
    pose.translation
        .vector
        .iter()
        .chain(pose.rotation.coords.iter())
        .chain(v.iter())
        .chain(w.iter())
        .copied()
        .collect()
}

fn all_finite(world: &World) -> bool {
    world
        .handles()
        .iter()
        .all(|&h| state(world, h).iter().all(|c| c.is_finite()))
}

fn desc(call: &Call) -> Option<BodyDesc> {
    let Call::Add {
        kind,
        half_extents,
        pose,
        density,
        friction,
        restitution,
        linear_velocity,
        angular_velocity,
        locks,
        linear_damping,
        angular_damping,
    } = call
    else {
        return None;
    };
    let base = match kind % 3 {
        0 => BodyDesc::dynamic(),
        1 => BodyDesc::fixed(),
        _ => BodyDesc::kinematic(),
    };
    let bit = |k: u8| locks & (1 << k) != 0;
    Some(
        base.cuboid(Vec3::from(vec3(*half_extents)))
            .pose(pose.get())
            .density(density.get())
            .friction(friction.get())
            .restitution(restitution.get())
            .linear_velocity(Vec3::from(vec3(*linear_velocity)))
            .angular_velocity(Vec3::from(vec3(*angular_velocity)))
            .lock_translations([bit(0), bit(1), bit(2)])
            .lock_rotation_axes([bit(3), bit(4), bit(5)])
            .linear_damping(linear_damping.get())
            .angular_damping(angular_damping.get()),
    )
}

fuzz_target!(|calls: Vec<Call>| {
    let mut world = World::new(WorldConfig::default()).expect("the default world");
    // Every handle ever issued, removed ones too: a call on a stale handle must be an `Err`.
    let mut issued: Vec<BodyHandle> = Vec::new();
    let pick =
        |issued: &[BodyHandle], k: u8| issued.get(usize::from(k) % issued.len().max(1)).copied();
    for call in calls.iter().take(MAX_CALLS) {
        let before = snapshot(&world);
        let result: Result<(), tumble::Error> = match call {
            Call::Add { .. } => {
                if world.body_count() >= MAX_BODIES {
                    continue;
                }
                let d = desc(call).expect("an add call");
                world.add_body(d).map(|h| issued.push(h))
            }
            Call::Step => {
                let r = world.step();
                if r.is_ok() && !skipped("nonfinite") {
                    assert!(
                        all_finite(&world),
                        "non-finite state after an accepted step: {:?}",
                        snapshot(&world)
                    );
                }
                r
            }
            _ => {
                let Some(h) = pick(
                    &issued,
                    match call {
                        Call::Remove(k)
                        | Call::SetPose(k, _)
                        | Call::SetLinearVelocity(k, _)
                        | Call::SetAngularVelocity(k, _)
                        | Call::ApplyImpulse(k, _, _)
                        | Call::SetKinematicTarget(k, _) => *k,
                        Call::Add { .. } | Call::Step => unreachable!("handled above"),
                    },
                ) else {
                    continue;
                };
                match call {
                    Call::Remove(_) => world.remove_body(h),
                    Call::SetPose(_, p) => world.set_pose(h, p.get()),
                    Call::SetLinearVelocity(_, v) => {
                        world.set_linear_velocity(h, Vec3::from(vec3(*v)))
                    }
                    Call::SetAngularVelocity(_, w) => {
                        world.set_angular_velocity(h, Vec3::from(vec3(*w)))
                    }
                    Call::ApplyImpulse(_, j, p) => {
                        world.apply_impulse(h, Vec3::from(vec3(*j)), Point3::from(vec3(*p)))
                    }
                    Call::SetKinematicTarget(_, p) => world.set_kinematic_target(h, p.get()),
                    Call::Add { .. } | Call::Step => unreachable!("handled above"),
                }
            }
        };
        if let Err(e) = &result {
            assert_eq!(
                snapshot(&world),
                before,
                "{call:?} returned Err({e}) but changed the world"
            );
            // The error names what was wrong (a field, or the handle).
            assert!(!e.to_string().is_empty());
        }
    }
});
