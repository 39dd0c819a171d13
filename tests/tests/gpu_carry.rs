//! The GPU impulse carry (`carry_impulses`) against tumble-solver's contact cache
//! (`ContactCache::warm_start`) and against its own CPU twin, on seeded manifolds whose points
//! keep, swap or lose their feature ids, stay put or move, under kept or changed reference
//! features and normals that turn a little or a lot: every point inherits the same impulse on
//! both sides, exactly (impulses are copied, never computed).
//!
//! Runs on any adapter (lavapipe in CI, with `TUMBLE_REQUIRE_GPU=1` so a missing adapter
//! fails); without one and without that variable, the test prints "skipped" and passes.
// Tolerance checks are written `!(difference <= tolerance)` so that a NaN fails them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{
    ContactPoint, Cuboid, Manifold, Point3, Pose, Rot, Vec3, nalgebra::Translation3,
};
use tumble_gpu::constants::NO_PREVIOUS;
use tumble_gpu::kernel::Kernel;
use tumble_gpu::kernels::carry_impulses::{CARRY_IMPULSES, CarryHistory, carry_impulses_cpu};
use tumble_gpu::kernels::collide_cuboids::kind_from_code;
use tumble_gpu::layout::{GpuContact, GpuLocalManifold, GpuManifold, GpuPose, WorkList};
use tumble_gpu::{GpuContext, MAX_MANIFOLD_POINTS};
use tumble_solver::{
    Body, BodyKind, Contact, ContactCache, Material, PERSIST_DISTANCE, PERSIST_NORMAL_COS,
    PointImpulse,
};
use tumble_tests::scene_support::random_vec;

const PER: usize = MAX_MANIFOLD_POINTS as usize;

/// Manifolds per step: enough for every combination of id, position, feature and normal
/// change to occur hundreds of times.
const MANIFOLDS: usize = 3_000;

/// A step's manifolds as the GPU holds them, with the poses they were found at.
#[derive(Clone)]
struct Step {
    poses: Vec<GpuPose>,
    manifolds: Vec<GpuManifold>,
    contacts: Vec<GpuContact>,
}

/// Farthest a point that "stays" moves in A's frame (m): half the 1 cm reach.
const STAY: f32 = 5e-3;
/// How far a point that "moves" goes in A's frame (m): past the reach of its own old point,
/// and short of the next one (10 cm away).
const MOVE: (f32, f32) = (0.02, 0.04);
/// Turn of a normal that stays (degrees): well inside the 5 degree limit.
const SMALL_TURN: (f32, f32) = (0.0, 3.0);
/// Turn of a normal that changes (degrees): well past the limit.
const LARGE_TURN: (f32, f32) = (8.0, 30.0);

/// A random unit vector (uniform enough for spreading directions around).
fn random_unit(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v = random_vec(rng, -1.0..1.0);
        let norm = v.norm();
        if norm > 0.1 && norm <= 1.0 {
            return v / norm;
        }
    }
}

fn random_rotation(rng: &mut ChaCha8Rng) -> Rot {
    Rot::from_euler_angles(
        rng.random_range(-3.2..3.2),
        rng.random_range(-1.6..1.6),
        rng.random_range(-3.2..3.2),
    )
}

fn padded(v: Vec3) -> [f32; 4] {
    [v.x, v.y, v.z, 0.0]
}

fn xyz(v: [f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

/// A unit vector at `angle` from `n`, turned about a random axis.
fn turned(rng: &mut ChaCha8Rng, n: Vec3, angle: f32) -> Vec3 {
    let axis = n.cross(&random_unit(rng)).normalize();
    Rot::from_scaled_axis(axis * angle) * n
}

/// Last step: body A of manifold `j` is body `j` (B, body `MANIFOLDS + j`, plays no part) at
/// a random pose within 20 m of the origin; points lie at the corners of a patch on A, at
/// least 10 cm apart, so a point that moved by less than [`PERSIST_DISTANCE`] has exactly one
/// old point in reach. Impulses are distinct per point, so a wrong match shows.
fn first_step(rng: &mut ChaCha8Rng) -> (Step, Vec<[Vec3; PER]>, Vec<Vec3>) {
    let n = MANIFOLDS;
    let mut step = Step {
        poses: vec![GpuPose::default(); 2 * n],
        manifolds: vec![GpuManifold::default(); n],
        contacts: vec![GpuContact::default(); n * PER],
    };
    let mut local_points = vec![[Vec3::zeros(); PER]; n];
    let mut local_normals = vec![Vec3::zeros(); n];
    for (k, p) in step.poses.iter_mut().enumerate() {
        let t = random_vec(rng, -20.0..20.0);
        let rotation = if k < n {
            random_rotation(rng)
        } else {
            Rot::identity()
        };
        *p = GpuPose::from_pose(&Pose::from_parts(Translation3::from(t), rotation));
    }
    for j in 0..n {
        let pose = tumble_gpu::kernels::update_aabbs::pose_from_gpu(&step.poses[j]);
        let (hx, hz) = (rng.random_range(0.05..0.5), rng.random_range(0.05..0.5));
        let corners = [(-hx, -hz), (hx, -hz), (hx, hz), (-hx, hz)];
        let len = rng.random_range(0..=PER);
        let normal = Vec3::y();
        local_normals[j] = normal;
        step.manifolds[j] = GpuManifold {
            normal: padded(pose.rotation * normal),
            body_a: j as u32,
            body_b: (n + j) as u32,
            kind: rng.random_range(0..3),
            feature: rng.random_range(0..6),
            len: len as u32,
            previous: NO_PREVIOUS,
            ..Default::default()
        };
        for i in 0..len {
            let (x, z) = corners[i];
            let local = Vec3::new(x, 0.5, z);
            local_points[j][i] = local;
            let slot = j * PER + i;
            step.contacts[slot] = GpuContact {
                position: padded((pose * Point3::from(local)).coords),
                depth: 0.01,
                // Ids from a small range, so a changed id sometimes names another old point.
                id: rng.random_range(0..8),
                normal_impulse: 1.0 + slot as f32,
                friction_impulse: [slot as f32, -(slot as f32), 0.5, 0.0],
                _pad: 0,
            };
        }
        // Ids within a manifold are distinct, as the narrow phase makes them.
        for i in 1..len {
            while (0..i).any(|h| step.contacts[j * PER + h].id == step.contacts[j * PER + i].id) {
                step.contacts[j * PER + i].id = rng.random_range(0..8);
            }
        }
    }
    (step, local_points, local_normals)
}

/// This step: manifold `k` continues last step's manifold `order[k]` (10 % start afresh), with
/// A moved by up to 2 mm and 0.3 degrees; each point either stays within [`STAY`] of an old
/// point or moves by [`MOVE`] (out of every old point's reach), keeps its id, takes a fresh
/// one or takes another old point's; a fifth of the manifolds change feature, a fifth turn
/// their normal by [`LARGE_TURN`] (past the 5 degree limit), the rest by [`SMALL_TURN`]. Every
/// decision is thus millimetres or degrees from its threshold, far beyond f32 round-off.
fn second_step(
    rng: &mut ChaCha8Rng,
    old: &Step,
    old_points: &[[Vec3; PER]],
    old_normals: &[Vec3],
) -> Step {
    let n = MANIFOLDS;
    let mut step = Step {
        poses: old.poses.clone(),
        manifolds: vec![GpuManifold::default(); n],
        contacts: vec![GpuContact::default(); n * PER],
    };
    let mut order: Vec<usize> = (0..n).collect();
    for k in (1..n).rev() {
        order.swap(k, rng.random_range(0..=k));
    }
    for p in step.poses.iter_mut().take(n) {
        let pose = tumble_gpu::kernels::update_aabbs::pose_from_gpu(p);
        let shift = random_vec(rng, -2e-3..2e-3);
        let nudge = Rot::from_scaled_axis(random_unit(rng) * 0.3f32.to_radians());
        *p = GpuPose::from_pose(&Pose::from_parts(
            Translation3::from(pose.translation.vector + shift),
            nudge * pose.rotation,
        ));
    }
    for (k, &j) in order.iter().enumerate() {
        let pose = tumble_gpu::kernels::update_aabbs::pose_from_gpu(&step.poses[j]);
        let was = &old.manifolds[j];
        let (kind, feature) = if rng.random_bool(0.2) {
            ((was.kind + 1) % 3, was.feature)
        } else {
            (was.kind, was.feature)
        };
        let angle = if rng.random_bool(0.2) {
            rng.random_range(LARGE_TURN.0..LARGE_TURN.1)
        } else {
            rng.random_range(SMALL_TURN.0..SMALL_TURN.1)
        };
        let normal = turned(rng, old_normals[j], angle.to_radians());
        let len = rng.random_range(1..=PER);
        step.manifolds[k] = GpuManifold {
            normal: padded(pose.rotation * normal),
            body_a: j as u32,
            body_b: (n + j) as u32,
            kind,
            feature,
            len: len as u32,
            previous: if rng.random_bool(0.1) {
                NO_PREVIOUS
            } else {
                j as u32
            },
            ..Default::default()
        };
        let old_len = was.len as usize;
        for i in 0..len {
            // Near an old point (the one of the same slot, or the first if there are fewer).
            let origin = old_points[j][i.min(old_len.saturating_sub(1))];
            let offset = if rng.random_bool(0.7) {
                random_unit(rng) * rng.random_range(0.0..STAY)
            } else {
                random_unit(rng) * rng.random_range(MOVE.0..MOVE.1)
            };
            let id = match rng.random_range(0..10) {
                0..=4 if i < old_len => old.contacts[j * PER + i].id,
                5 if old_len > 0 => old.contacts[j * PER + rng.random_range(0..old_len)].id,
                _ => rng.random_range(0..8) + 100,
            };
            step.contacts[k * PER + i] = GpuContact {
                position: padded((pose * Point3::from(origin + offset)).coords),
                depth: 0.01,
                id,
                ..Default::default()
            };
        }
    }
    step
}

/// Runs `carry_impulses` once on the GPU: returns the points with carried impulses and the
/// manifolds in A's frame it kept.
fn gpu_carry(
    ctx: &GpuContext,
    kernel: &Kernel,
    now: &Step,
    previous: &CarryHistory<'_>,
) -> (Vec<GpuContact>, Vec<GpuLocalManifold>) {
    let count = now.manifolds.len() as u32;
    let work = ctx.storage_buffer("work", &[WorkList::for_count(count)]);
    let poses = ctx.storage_buffer("poses", &now.poses);
    let manifolds = ctx.storage_buffer("manifolds", &now.manifolds);
    let previous_manifolds = ctx.storage_buffer("previous manifolds", previous.manifolds);
    let previous_contacts = ctx.storage_buffer("previous contacts", previous.contacts);
    let previous_locals = ctx.storage_buffer("previous locals", previous.locals);
    let contacts = ctx.storage_buffer("contacts", &now.contacts);
    let locals = ctx.storage_buffer(
        "locals",
        &vec![GpuLocalManifold::default(); now.manifolds.len()],
    );
    let group = kernel.bind_named(ctx, |name| match name {
        "work" => &work,
        "poses" => &poses,
        "manifolds" => &manifolds,
        "previous_manifolds" => &previous_manifolds,
        "previous_contacts" => &previous_contacts,
        "previous_locals" => &previous_locals,
        "contacts" => &contacts,
        "locals" => &locals,
        _ => unreachable!("no carry_impulses binding {name}"),
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        kernel.dispatch(&mut pass, &group, count);
    }
    ctx.queue.submit([encoder.finish()]);
    (
        ctx.read_buffer(&contacts, 0, u64::from(count) * PER as u64)
            .unwrap(),
        ctx.read_buffer(&locals, 0, u64::from(count)).unwrap(),
    )
}

/// The CPU solver's view of manifold `k` of `step`.
fn cpu_contact(step: &Step, k: usize) -> Contact {
    let m = &step.manifolds[k];
    let mut manifold = Manifold {
        normal: xyz(m.normal),
        kind: kind_from_code(m.kind),
        feature: m.feature,
        ..Default::default()
    };
    let mut impulses = [PointImpulse::default(); PER];
    for (i, imp) in impulses.iter_mut().enumerate().take(m.len as usize) {
        let c = &step.contacts[k * PER + i];
        manifold.push(ContactPoint {
            position: Point3::from(xyz(c.position)),
            depth: c.depth,
            id: c.id,
        });
        *imp = PointImpulse {
            normal: c.normal_impulse,
            friction: xyz(c.friction_impulse),
        };
    }
    let mut contact = Contact::new(m.body_a, m.body_b, manifold);
    contact.impulses = impulses;
    contact
}

/// The largest coordinate difference between two sets of local manifolds, over the slots in
/// use (the normal and the first `len` points of each manifold with points).
fn local_difference(
    manifolds: &[GpuManifold],
    a: &[GpuLocalManifold],
    b: &[GpuLocalManifold],
) -> f32 {
    let mut worst = 0.0f32;
    for (k, m) in manifolds.iter().enumerate().filter(|(_, m)| m.len > 0) {
        let slots = std::iter::once((&a[k].normal, &b[k].normal))
            .chain(a[k].points.iter().zip(&b[k].points).take(m.len as usize));
        for (x, y) in slots {
            for i in 0..4 {
                worst = worst.max((x[i] - y[i]).abs());
            }
        }
    }
    worst
}

#[test]
fn gpu_carry_inherits_exactly_what_the_cpu_contact_cache_warm_starts() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // The draws keep every decision clear of the thresholds: points stay within 5 mm or move
    // at least 2 cm (old points are 10 cm apart), normals turn under 3 or over 8 degrees.
    assert!(STAY < PERSIST_DISTANCE && PERSIST_DISTANCE < MOVE.0);
    assert!(SMALL_TURN.1.to_radians().cos() > PERSIST_NORMAL_COS);
    assert!(LARGE_TURN.0.to_radians().cos() < PERSIST_NORMAL_COS);
    let kernel = Kernel::new(&ctx, &CARRY_IMPULSES).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let (first, old_points, old_normals) = first_step(&mut rng);
    let none = CarryHistory {
        manifolds: &[GpuManifold::default()],
        contacts: &[GpuContact::default(); PER],
        locals: &[GpuLocalManifold::default()],
    };
    // Step one has no history: the kernel only keeps the manifolds in A's frame. The twin
    // rotates in the shader's arithmetic; coordinates within 20 m round to 2e-6 m in f32, so
    // 1e-5 m (a thousandth of the 1 cm reach) bounds the difference.
    let (carried, first_locals) = gpu_carry(&ctx, &kernel, &first, &none);
    assert_eq!(carried, first.contacts, "nothing to carry from");
    let twin_locals = carry_impulses_cpu(
        &first.poses,
        &first.manifolds,
        &mut first.contacts.clone(),
        &none,
    );
    let diff = local_difference(&first.manifolds, &first_locals, &twin_locals);
    assert!(!(diff > 1e-5), "step 1 local manifolds differ by {diff}");

    let second = second_step(&mut rng, &first, &old_points, &old_normals);
    let history = CarryHistory {
        manifolds: &first.manifolds,
        contacts: &first.contacts,
        locals: &first_locals,
    };
    let (got, second_locals) = gpu_carry(&ctx, &kernel, &second, &history);

    // The twin, from the same history, carries exactly the same.
    let mut twin = second.contacts.clone();
    let twin_locals = carry_impulses_cpu(&second.poses, &second.manifolds, &mut twin, &history);
    if let Some(i) = (0..got.len()).find(|&i| got[i] != twin[i]) {
        panic!(
            "GPU carry differs from its CPU twin at manifold {} point {}: {:?} vs {:?}",
            i / PER,
            i % PER,
            got[i],
            twin[i]
        );
    }
    let diff = local_difference(&second.manifolds, &second_locals, &twin_locals);
    assert!(!(diff > 1e-5), "step 2 local manifolds differ by {diff}");

    // The CPU contact cache, stored from last step's contacts and bodies, warm starts every
    // point with exactly the impulse the GPU carried.
    let n = MANIFOLDS;
    let key = |j: usize| (j as u64, (n + j) as u64);
    let bodies: Vec<Body> = first
        .poses
        .iter()
        .map(|p| {
            Body::new(
                BodyKind::Dynamic,
                Cuboid::new(Vec3::repeat(0.5)),
                tumble_gpu::kernels::update_aabbs::pose_from_gpu(p),
                1.0,
                Material::default(),
            )
            .unwrap()
        })
        .collect();
    let stored: Vec<usize> = (0..n).filter(|&j| first.manifolds[j].len > 0).collect();
    let keys: Vec<_> = stored.iter().map(|&j| key(j)).collect();
    let contacts: Vec<Contact> = stored.iter().map(|&j| cpu_contact(&first, j)).collect();
    let mut cache = ContactCache::new();
    cache.store(&keys, &contacts, &bodies);
    let (mut by_id, mut by_position, mut cold) = (0, 0, 0);
    for (k, m) in second.manifolds.iter().enumerate() {
        let pose_a =
            tumble_gpu::kernels::update_aabbs::pose_from_gpu(&second.poses[m.body_a as usize]);
        let want = if m.previous == NO_PREVIOUS {
            [PointImpulse::default(); PER]
        } else {
            cache.warm_start(
                &key(m.previous as usize),
                &cpu_contact(&second, k).manifold,
                &pose_a,
            )
        };
        for i in 0..m.len as usize {
            let g = &got[k * PER + i];
            let gpu = PointImpulse {
                normal: g.normal_impulse,
                friction: xyz(g.friction_impulse),
            };
            assert_eq!(gpu, want[i], "manifold {k} point {i}");
            if gpu.normal == 0.0 {
                cold += 1;
                continue;
            }
            // Which old point it came from: impulses are 1 + the old slot.
            let from = (gpu.normal - 1.0) as usize;
            let old = &first.manifolds[from / PER];
            let same_feature = old.kind == m.kind && old.feature == m.feature;
            if same_feature && first.contacts[from].id == g.id {
                by_id += 1;
            } else {
                by_position += 1;
            }
        }
    }
    let total = by_id + by_position + cold;
    eprintln!("{total} points: {by_id} by id, {by_position} by position, {cold} cold");
    // Each way occurs often (at least 10 % of points), so none of them goes untested; this
    // seed gives about 25 % by id, 17 % by position and 58 % cold.
    for (what, count) in [
        ("by id", by_id),
        ("by position", by_position),
        ("cold", cold),
    ] {
        assert!(count * 10 >= total, "only {count} of {total} points {what}");
    }
}
