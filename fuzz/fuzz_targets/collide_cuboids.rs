//! `tumble_narrow::collide_cuboids` (and its cached form) on arbitrary sizes, poses and margins.
//!
//! Checked for every input in the domain: no panic; the same call twice gives the same bits; and
//! every manifold keeps the promises of `collide.rs` and `tests/narrow_properties.rs`: one to
//! four points, a finite unit normal, finite points with distinct ids, depths no deeper than two
//! boxes can overlap (the sum of their circumradii) and no shallower than `-margin`, and each
//! point near both boxes (a point of depth `d` is the midpoint of a surface point of each box
//! along the normal, so it lies within `|d|` of each box).
//!
//! Filtered out (outside the domain a world ever hands the narrow phase, and not promised by the
//! function): half extents that are not finite and positive (`Body::new` rejects them), a margin
//! that is not finite and non-negative (`WorldConfig::validate` rejects it), a translation that
//! is not finite, and a quaternion that cannot be normalized (the world keeps rotations unit).
//! Huge, tiny and subnormal sizes, positions and margins are all kept, but the geometric checks
//! (depth range, points near both boxes, history) apply only within the domain
//! `collide_cuboids` documents: the range of lengths (`tumble_narrow::SUPPORTED_LENGTH`, 1e-9 to
//! 1e9 m: past it squared lengths and their products leave `f32`) and the thinness of the pair
//! (`tumble_narrow::SUPPORTED_ASPECT`: the smallest half extent of the two boxes at least 1e-6
//! of the largest; a thinner slab is below one `f32` step of the larger box's coordinates).
//! Outside it the manifold must still have one to four finite points and a finite normal, and
//! two calls must still give the same bits.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tumble_fuzz::{Num, vec3, vec4};
use tumble_geometry::{
    Cuboid, FeatureKind, MAX_MANIFOLD_POINTS, Manifold, Pose, Rot, Vec3,
    nalgebra::{Isometry3, Point3, Quaternion, Translation3, Vector3},
};
use tumble_narrow::{collide_cuboids, collide_cuboids_cached};

#[derive(Arbitrary, Debug)]
struct Input {
    half_a: [Num; 3],
    half_b: [Num; 3],
    pos_a: [Num; 3],
    pos_b: [Num; 3],
    /// Quaternions `[x, y, z, w]`, normalized before use.
    rot_a: [Num; 4],
    rot_b: [Num; 4],
    margin: Num,
    /// Last step's `(kind, feature)`: any kind, any feature number (most are not faces).
    previous: Option<(u8, u32)>,
}

/// A unit quaternion from four numbers, normalized in `f64`; `None` when they have no direction.
fn rotation(q: [f32; 4]) -> Option<Rot> {
    let [x, y, z, w] = q.map(f64::from);
    let n = (x * x + y * y + z * z + w * w).sqrt();
    if !n.is_finite() || n < 1e-30 {
        return None;
    }
    let q = Quaternion::new(w / n, x / n, y / n, z / n).cast::<f32>();
    // Normalized again in f32, as the world does (`renormalize` on every pose it is given).
    let r = Rot::new_normalize(q);
    r.coords.iter().all(|c| c.is_finite()).then_some(r)
}

fn half_extents(h: [f32; 3]) -> Option<Cuboid> {
    h.iter()
        .all(|c| c.is_finite() && *c > 0.0)
        .then(|| Cuboid::new(Vec3::from(h)))
}

fn pose(t: [f32; 3], r: Rot) -> Option<Pose> {
    t.iter()
        .all(|c| c.is_finite())
        .then(|| Pose::from_parts(Translation3::from(Vec3::from(t)), r))
}

/// Distance from world point `p` to box `c` at `pose`, in f64.
fn distance_to_box(c: &Cuboid, pose: &Pose, p: &Point3<f64>) -> f64 {
    let pose: Isometry3<f64> = pose.cast();
    let local = pose.inverse_transform_point(p);
    let h: Vector3<f64> = c.half_extents.cast();
    let clamped = local.coords.zip_map(&h, |x, h| x.clamp(-h, h));
    (local.coords - clamped).norm()
}

/// Whether the pair lies within the domain `collide_cuboids` documents: every length (half
/// extents, translations and margin) within [`tumble_narrow::SUPPORTED_LENGTH`], and the
/// smallest of the six half extents at least [`tumble_narrow::SUPPORTED_ASPECT`] of the largest.
fn in_supported_range(a: &Cuboid, pa: &Pose, b: &Cuboid, pb: &Pose, margin: f32) -> bool {
    let (lo, hi) = tumble_narrow::SUPPORTED_LENGTH;
    let size_ok = |h: &Vec3| h.iter().all(|&c| (lo..=hi).contains(&c));
    let pos_ok = |p: &Pose| p.translation.vector.iter().all(|c| c.abs() <= hi);
    // In f64: the world's extreme pair, a 1e-3 m box next to a 1e3 m one, lies exactly on the
    // edge, and an f32 product could round it out.
    let thinnest = f64::from(a.half_extents.min().min(b.half_extents.min()));
    let largest = f64::from(a.half_extents.max().max(b.half_extents.max()));
    let aspect_ok = thinnest >= f64::from(tumble_narrow::SUPPORTED_ASPECT) * largest;
    size_ok(&a.half_extents)
        && size_ok(&b.half_extents)
        && pos_ok(pa)
        && pos_ok(pb)
        && margin <= hi
        && aspect_ok
}

/// What holds for any finite input of positive sizes: one to four finite points and a finite
/// normal.
fn check_shape(m: &Manifold) {
    let len = m.len as usize;
    assert!(
        (1..=MAX_MANIFOLD_POINTS).contains(&len),
        "{len} points in {m:?}"
    );
    assert!(m.normal.iter().all(|c| c.is_finite()), "normal {m:?}");
    for p in m.points() {
        assert!(
            p.position.iter().all(|c| c.is_finite()) && p.depth.is_finite(),
            "non-finite point in {m:?}"
        );
    }
}

/// The geometry of a manifold of a pair in the supported range.
fn check(m: &Manifold, a: &Cuboid, pa: &Pose, b: &Cuboid, pb: &Pose, margin: f32) {
    check_shape(m);
    // Normalised in f32 and rotated once: a few ulps from unit length.
    let n = f64::from(m.normal.norm());
    assert!((n - 1.0).abs() <= 1e-5, "|normal| = {n} in {m:?}");
    let ha: Vector3<f64> = a.half_extents.cast();
    let hb: Vector3<f64> = b.half_extents.cast();
    // Rounding scale of the geometry: the larger box's size (the narrow phase's noise scale),
    // plus the translations, whose f32 rounding every world-space position carries.
    let noise = ha.max().max(hb.max());
    let far = f64::from(pa.translation.vector.norm()) + f64::from(pb.translation.vector.norm());
    // 1e-3 of the noise scale: an edge pair at the parallel cutoff (sin 1e-3) amplifies f32
    // rounding (1.2e-7) about 1e3 times in its closest points. 1e-6 of the translations: a few
    // ulps of the world coordinates. Neither is anywhere near a box size, which is the error a
    // point on the wrong feature would show.
    let tol = 1e-3 * noise + 1e-6 * far;
    let reach = ha.norm() + hb.norm();
    for (i, p) in m.points().iter().enumerate() {
        assert!(
            p.position.iter().all(|c| c.is_finite()) && p.depth.is_finite(),
            "point {i} of {m:?}"
        );
        let d = f64::from(p.depth);
        // No deeper than the boxes' bounding spheres can overlap.
        assert!(d <= reach + tol, "depth {d} beyond reach {reach} in {m:?}");
        // Nothing reported farther apart than the margin.
        assert!(
            d >= -f64::from(margin) - tol,
            "depth {d} below -margin {margin} in {m:?}"
        );
        let q: Point3<f64> = p.position.cast();
        for (name, c, pose) in [("A", a, pa), ("B", b, pb)] {
            let dist = distance_to_box(c, pose, &q);
            assert!(
                dist <= d.abs() + tol,
                "point {i} is {dist} from box {name} (depth {d}, tolerance {tol}) in {m:?}"
            );
        }
        assert!(
            m.points()[..i].iter().all(|o| o.id != p.id),
            "repeated id {} in {m:?}",
            p.id
        );
    }
}

fn bits(m: &Option<Manifold>) -> Vec<u32> {
    let Some(m) = m else { return vec![] };
    let mut out: Vec<u32> = m.normal.iter().map(|c| c.to_bits()).collect();
    out.extend([m.kind as u32, m.feature, u32::from(m.len)]);
    for p in m.points() {
        out.extend(p.position.iter().map(|c| c.to_bits()));
        out.extend([p.depth.to_bits(), p.id]);
    }
    out
}

fn kind_of(k: u8) -> FeatureKind {
    match k % 3 {
        0 => FeatureKind::FaceA,
        1 => FeatureKind::FaceB,
        _ => FeatureKind::Edge,
    }
}

fuzz_target!(|input: Input| {
    let previous = input.previous.map(|(k, f)| (kind_of(k), f));
    let margin = input.margin.get();
    // Any input at all, in the domain or not: no panic (the contract of
    // `narrow_properties.rs`'s bad-input test). The quaternion is used unnormalized.
    {
        let raw = |h: [Num; 3], t: [Num; 3], q: [Num; 4]| {
            let [x, y, z, w] = vec4(q);
            let r = Rot::new_unchecked(Quaternion::new(w, x, y, z));
            (
                Cuboid::new(Vec3::from(vec3(h))),
                Pose::from_parts(Translation3::from(Vec3::from(vec3(t))), r),
            )
        };
        let (a, pa) = raw(input.half_a, input.pos_a, input.rot_a);
        let (b, pb) = raw(input.half_b, input.pos_b, input.rot_b);
        let _ = collide_cuboids_cached(&a, &pa, &b, &pb, margin, previous);
    }

    let (Some(a), Some(b)) = (
        half_extents(vec3(input.half_a)),
        half_extents(vec3(input.half_b)),
    ) else {
        return;
    };
    let (Some(ra), Some(rb)) = (rotation(vec4(input.rot_a)), rotation(vec4(input.rot_b))) else {
        return;
    };
    let (Some(pa), Some(pb)) = (pose(vec3(input.pos_a), ra), pose(vec3(input.pos_b), rb)) else {
        return;
    };
    if !(margin.is_finite() && margin >= 0.0) {
        return;
    }
    let fresh = collide_cuboids(&a, &pa, &b, &pb, margin);
    assert_eq!(
        bits(&fresh),
        bits(&collide_cuboids(&a, &pa, &b, &pb, margin)),
        "two calls differ"
    );
    // Outside the documented range of lengths (f32 squares and products of squares
    // overflow or flush to zero) or of thinness (a slab below one f32 step of the larger box),
    // only the shape of the output is promised.
    let supported = in_supported_range(&a, &pa, &b, &pb, margin);
    let verify = |m: &Manifold| {
        if supported {
            check(m, &a, &pa, &b, &pb, margin)
        } else {
            check_shape(m)
        }
    };
    if let Some(m) = &fresh {
        verify(m);
    }
    if let Some(previous) = previous {
        let cached = collide_cuboids_cached(&a, &pa, &b, &pb, margin, Some(previous));
        // History changes which features are used, never whether boxes that overlap deeply
        // (by more than 1e-3 of A's size, the bound of `narrow_properties.rs`) touch.
        if supported && fresh.is_some_and(|m| m.max_depth() > 1e-3 * a.half_extents.max()) {
            assert!(cached.is_some(), "history {previous:?} lost {fresh:?}");
        }
        if let Some(m) = &cached {
            verify(m);
        }
    }
});
