//! The contact cache: impulses follow feature ids under the same reference feature, fall
//! back to the nearest unclaimed old point within `PERSIST_DISTANCE` in body A's frame while
//! the normal turned by less than the angle of `PERSIST_NORMAL_COS`, and nothing else carries.

use tumble_geometry::{FeatureKind, Manifold, Point3, Pose, Real, Rot, Vec3};

use super::{manifold, material, unit_cube};
use crate::{Body, Contact, ContactCache, PERSIST_NORMAL_COS, PointImpulse};

const KEY: (u64, u64) = (3, 8);

/// Body A, turned and away from the origin, so "A's frame" differs from the world frame.
fn body_a() -> Body {
    unit_cube(
        1.0,
        Pose::from_parts(
            Vec3::new(2.0, 1.0, -1.0).into(),
            Rot::from_euler_angles(0.3, 0.5, -0.2),
        ),
        material(0.5, 0.0),
    )
}

/// A manifold with points at the given offsets (in A's frame) from a spot on A's surface,
/// normal `local_normal` in A's frame, ids from `ids`.
fn local_manifold(a: &Body, local_normal: Vec3, offsets: &[Vec3], ids: &[u32]) -> Manifold {
    let spot = Vec3::new(0.1, 0.5, -0.2);
    let points: Vec<(Point3, Real, u32)> = offsets
        .iter()
        .zip(ids)
        .map(|(o, &id)| (a.pose * Point3::from(spot + o), 0.01, id))
        .collect();
    manifold(a.pose.rotation * local_normal, &points)
}

fn impulse(k: usize) -> PointImpulse {
    PointImpulse {
        normal: 1.0 + k as Real,
        friction: Vec3::new(0.1 * k as Real, -0.2, 0.05),
    }
}

/// A cache holding one manifold of three points (ids 10, 11, 12) 10 cm apart.
fn cache_of(a: &Body) -> ContactCache {
    let offsets = [
        Vec3::zeros(),
        Vec3::new(0.1, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.1),
    ];
    let mut contact = Contact::new(0, 1, local_manifold(a, Vec3::y(), &offsets, &[10, 11, 12]));
    for k in 0..3 {
        contact.impulses[k] = impulse(k);
    }
    contact.tilt_impulse = Vec3::new(0.3, 0.0, -0.1);
    let mut cache = ContactCache::new();
    cache.store(&[KEY], &[contact], &[*a, *a]);
    cache
}

fn normals(w: &[PointImpulse]) -> Vec<Real> {
    w.iter().map(|p| p.normal).collect()
}

#[test]
fn matching_ids_carry_the_whole_impulse_whatever_the_positions() {
    let a = body_a();
    let cache = cache_of(&a);
    assert_eq!((cache.len(), cache.is_empty()), (1, false));
    assert_eq!(cache.previous_feature(&KEY), Some((FeatureKind::FaceA, 2)));
    assert_eq!(cache.previous_feature(&(3, 9)), None);
    // Same ids, moved far and reordered: ids decide.
    let far = [
        Vec3::new(0.3, 0.0, 0.3),
        Vec3::new(-0.3, 0.0, 0.0),
        Vec3::new(0.2, 0.0, -0.3),
    ];
    let m = local_manifold(&a, Vec3::y(), &far, &[12, 10, 11]);
    let warm = cache.warm_start(&KEY, &m, &a.pose);
    assert_eq!(&warm[..3], &[impulse(2), impulse(0), impulse(1)]);
    assert_eq!(warm[3], PointImpulse::default());
    // Ids match even if the normal turned a lot (the same features made the points).
    let turned = Rot::from_euler_angles(0.5, 0.0, 0.0) * Vec3::y();
    let m = local_manifold(&a, turned, &far, &[12, 10, 11]);
    assert_eq!(
        normals(&cache.warm_start(&KEY, &m, &a.pose)[..3]),
        vec![3.0, 1.0, 2.0]
    );
    // An unknown pair gets nothing.
    assert_eq!(
        cache.warm_start(&(1, 2), &m, &a.pose),
        [PointImpulse::default(); 4]
    );
}

#[test]
fn ids_of_another_reference_feature_are_not_comparable() {
    let a = body_a();
    let cache = cache_of(&a);
    let far = [Vec3::new(0.3, 0.0, 0.3), Vec3::new(-0.3, 0.0, 0.0)];
    // The same face number of the other box, and another face of the same box.
    let mut other_box = local_manifold(&a, Vec3::y(), &far, &[10, 11]);
    other_box.kind = FeatureKind::FaceB;
    let mut other_face = local_manifold(&a, Vec3::y(), &far, &[10, 11]);
    other_face.feature = 3;
    for m in [other_box, other_face] {
        assert_eq!(normals(&cache.warm_start(&KEY, &m, &a.pose)), vec![0.0; 4]);
    }
}

#[test]
fn renamed_points_inherit_from_the_nearest_old_point_within_a_centimetre() {
    let a = body_a();
    let cache = cache_of(&a);
    // New ids; the first point 9 mm from old point 10, the second 1.1 cm from old point 11
    // (either side of PERSIST_DISTANCE, 1 cm), the third right on old point 12, all measured
    // in A's frame.
    let offsets = [
        Vec3::new(0.0, 0.0, 0.009),
        Vec3::new(0.1 + 0.011, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.1),
    ];
    let m = local_manifold(&a, Vec3::y(), &offsets, &[70, 71, 72]);
    let warm = cache.warm_start(&KEY, &m, &a.pose);
    assert_eq!(
        &warm[..3],
        &[impulse(0), PointImpulse::default(), impulse(2)]
    );
    // After body A moved and turned, the same points in its frame still match: the cache
    // compares in A's frame, not in the world.
    let mut moved = a;
    moved.pose = Pose::from_parts(
        Vec3::new(-4.0, 0.0, 3.0).into(),
        Rot::from_euler_angles(-1.0, 0.2, 2.0),
    );
    let m = local_manifold(&moved, Vec3::y(), &offsets, &[70, 71, 72]);
    assert_eq!(
        &cache.warm_start(&KEY, &m, &moved.pose)[..3],
        &[impulse(0), PointImpulse::default(), impulse(2)]
    );
}

#[test]
fn an_old_point_is_inherited_once_by_the_first_new_point_near_it() {
    let a = body_a();
    let cache = cache_of(&a);
    // Two new points 2 mm and 4 mm from old point 10: the first claims it; the second's
    // nearest unclaimed old point (11, 10 cm away) is too far.
    let offsets = [Vec3::new(0.002, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.004)];
    let m = local_manifold(&a, Vec3::y(), &offsets, &[80, 81]);
    assert_eq!(
        normals(&cache.warm_start(&KEY, &m, &a.pose)[..2]),
        vec![1.0, 0.0]
    );
    // A point whose id matched does not also claim a second old point by position: point
    // 11 keeps its own impulse, and the renamed point next to old 10 gets 10's.
    let offsets = [Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.003, 0.0, 0.0)];
    let m = local_manifold(&a, Vec3::y(), &offsets, &[11, 90]);
    assert_eq!(
        normals(&cache.warm_start(&KEY, &m, &a.pose)[..2]),
        vec![2.0, 1.0]
    );
    // An old point claimed by its id is not inherited again by position.
    let offsets = [Vec3::zeros(), Vec3::new(0.002, 0.0, 0.0)];
    let m = local_manifold(&a, Vec3::y(), &offsets, &[10, 91]);
    assert_eq!(
        normals(&cache.warm_start(&KEY, &m, &a.pose)[..2]),
        vec![1.0, 0.0]
    );
}

#[test]
fn position_matching_and_the_tilt_need_a_normal_turned_less_than_five_degrees() {
    let a = body_a();
    let cache = cache_of(&a);
    let offsets = [Vec3::new(0.0, 0.0, 0.005)];
    let tilt = Vec3::new(0.3, 0.0, -0.1);
    let turned = |degrees: Real| Rot::from_euler_angles(degrees.to_radians(), 0.0, 0.0) * Vec3::y();
    // 0.996 is cos 5 degrees to three decimals (the angle is 5.13 degrees).
    assert!((5.0f32.to_radians().cos() - PERSIST_NORMAL_COS).abs() < 5e-4);
    for (degrees, carried) in [(0.0, true), (4.5, true), (5.5, false), (30.0, false)] {
        let m = local_manifold(&a, turned(degrees), &offsets, &[60]);
        let warm = cache.warm_start(&KEY, &m, &a.pose);
        let expected = if carried {
            impulse(0)
        } else {
            PointImpulse::default()
        };
        assert_eq!(warm[0], expected, "{degrees} degrees");
        let t = cache.warm_tilt(&KEY, &m, &a.pose);
        assert_eq!(
            t,
            if carried { tilt } else { Vec3::zeros() },
            "{degrees} degrees"
        );
    }
    assert_eq!(
        cache.warm_tilt(
            &(1, 2),
            &local_manifold(&a, Vec3::y(), &offsets, &[60]),
            &a.pose
        ),
        Vec3::zeros()
    );
}

#[test]
fn store_replaces_the_cache_and_forget_body_drops_its_pairs() {
    let a = body_a();
    let mut cache = cache_of(&a);
    let m = local_manifold(&a, Vec3::y(), &[Vec3::zeros()], &[1]);
    let contacts = [
        Contact::new(0, 1, m),
        Contact::new(1, 0, m),
        Contact::new(0, 1, m),
    ];
    cache.store(&[(1, 2), (2, 5), (4, 6)], &contacts, &[a, a]);
    // The old pair is gone: each store holds exactly this step's contacts.
    assert_eq!(cache.len(), 3);
    assert_eq!(cache.previous_feature(&KEY), None);
    cache.forget_body(2);
    assert_eq!(cache.len(), 1);
    assert!(cache.previous_feature(&(4, 6)).is_some());
    cache.forget_body(6);
    assert!(cache.is_empty());
    assert_eq!(cache.len(), 0);
}
