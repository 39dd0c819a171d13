//! Contact persistence: last step's impulses, keyed by body pair and matched by feature id.

use std::collections::HashMap;

use tumble_geometry::{FeatureKind, MAX_MANIFOLD_POINTS, Manifold, Pose, Real, Vec3};

use crate::pair_hash::PairBuildHasher;
use crate::{Body, Contact, PointImpulse};

/// Farthest a point may move in body A's frame and still inherit an impulse when its feature
/// id changed: 1 cm, Jolt's `mContactPointPreserveLambdaMaxDistSq = 0.01^2`. Ids of points
/// on exactly coincident edges (aligned stacks) flip under round-off, while the point itself
/// stays put.
pub const PERSIST_DISTANCE: Real = 0.01;

/// Smallest cosine between last step's normal and this step's for position matching: the
/// cosine of 5 degrees, as Jolt's `mContactNormalCosMaxDeltaRotation`. A normal that turned
/// more belongs to a different contact situation.
pub const PERSIST_NORMAL_COS: Real = 0.996;

/// A body pair's identity that survives body removal and reordering (the facade passes its
/// handles), smaller id first.
pub type PairKey = (u64, u64);

/// What a pair's manifold left behind for the next step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CachedManifold {
    /// Which SAT axis kind made the manifold (hysteresis input for the narrow phase).
    pub kind: FeatureKind,
    /// Reference face or packed edge pair.
    pub feature: u32,
    /// Feature id of each point.
    pub ids: [u32; MAX_MANIFOLD_POINTS],
    /// Each point in body A's local frame.
    pub local_points: [Vec3; MAX_MANIFOLD_POINTS],
    /// The manifold normal in body A's local frame.
    pub local_normal: Vec3,
    /// Impulses of each point at the end of the step.
    pub impulses: [PointImpulse; MAX_MANIFOLD_POINTS],
    /// The patch's tilt impulse (world vector).
    pub tilt_impulse: Vec3,
    /// Number of valid points.
    pub len: u8,
}

/// Impulses of the last step's manifolds, looked up by pair.
#[derive(Clone, Debug, Default)]
pub struct ContactCache {
    manifolds: HashMap<PairKey, CachedManifold, PairBuildHasher>,
}

impl ContactCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of cached pairs.
    pub fn len(&self) -> usize {
        self.manifolds.len()
    }

    /// True when nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.manifolds.is_empty()
    }

    /// Last step's feature for `key`, for the narrow phase's hysteresis.
    pub fn previous_feature(&self, key: &PairKey) -> Option<(FeatureKind, u32)> {
        self.manifolds.get(key).map(|m| (m.kind, m.feature))
    }

    /// Last step's impulses for the points of `manifold`, whose body A is at `pose_a`.
    ///
    /// A point inherits the impulse of the old point with the same feature id under the same
    /// reference feature (ids are only comparable then). Failing that, it inherits from the
    /// nearest unclaimed old point within [`PERSIST_DISTANCE`] in A's frame, provided the
    /// normal turned by less than the angle of [`PERSIST_NORMAL_COS`].
    pub fn warm_start(
        &self,
        key: &PairKey,
        manifold: &Manifold,
        pose_a: &Pose,
    ) -> [PointImpulse; MAX_MANIFOLD_POINTS] {
        let mut out = [PointImpulse::default(); MAX_MANIFOLD_POINTS];
        let Some(old) = self.manifolds.get(key) else {
            return out;
        };
        let old_len = old.len as usize;
        let mut claimed = [false; MAX_MANIFOLD_POINTS];
        let mut matched = [false; MAX_MANIFOLD_POINTS];
        if old.kind == manifold.kind && old.feature == manifold.feature {
            for (i, p) in manifold.points().iter().enumerate() {
                if let Some(j) = (0..old_len).find(|&j| !claimed[j] && old.ids[j] == p.id) {
                    out[i] = old.impulses[j];
                    claimed[j] = true;
                    matched[i] = true;
                }
            }
        }
        let normal = pose_a.rotation.inverse_transform_vector(&manifold.normal);
        if normal.dot(&old.local_normal) < PERSIST_NORMAL_COS {
            return out;
        }
        for (i, p) in manifold.points().iter().enumerate() {
            if matched[i] {
                continue;
            }
            let local = pose_a.inverse_transform_point(&p.position).coords;
            let nearest = (0..old_len)
                .filter(|&j| !claimed[j])
                .map(|j| (j, (old.local_points[j] - local).norm_squared()))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((j, d2)) = nearest
                && d2 <= PERSIST_DISTANCE * PERSIST_DISTANCE
            {
                out[i] = old.impulses[j];
                claimed[j] = true;
            }
        }
        out
    }

    /// Last step's tilt impulse of the pair, when the normal turned by less than the angle of
    /// [`PERSIST_NORMAL_COS`] (the patch is the same patch); zero otherwise.
    pub fn warm_tilt(&self, key: &PairKey, manifold: &Manifold, pose_a: &Pose) -> Vec3 {
        match self.manifolds.get(key) {
            Some(old)
                if pose_a
                    .rotation
                    .inverse_transform_vector(&manifold.normal)
                    .dot(&old.local_normal)
                    >= PERSIST_NORMAL_COS =>
            {
                old.tilt_impulse
            }
            _ => Vec3::zeros(),
        }
    }

    /// Replaces the cache with this step's contacts; `keys[i]` is `contacts[i]`'s pair and
    /// `bodies` must still hold the poses the manifolds were computed from.
    pub fn store(&mut self, keys: &[PairKey], contacts: &[Contact], bodies: &[Body]) {
        self.manifolds.clear();
        for (key, c) in keys.iter().zip(contacts) {
            let m = &c.manifold;
            let pose_a = &bodies[c.body_a as usize].pose;
            let mut ids = [0u32; MAX_MANIFOLD_POINTS];
            let mut local_points = [Vec3::zeros(); MAX_MANIFOLD_POINTS];
            for (i, p) in m.points().iter().enumerate() {
                ids[i] = p.id;
                local_points[i] = pose_a.inverse_transform_point(&p.position).coords;
            }
            self.manifolds.insert(
                *key,
                CachedManifold {
                    kind: m.kind,
                    feature: m.feature,
                    ids,
                    local_points,
                    local_normal: pose_a.rotation.inverse_transform_vector(&m.normal),
                    impulses: c.impulses,
                    tilt_impulse: c.tilt_impulse,
                    len: m.len,
                },
            );
        }
    }

    /// Every cached pair with what it left behind, sorted by pair key (a copy of the cache
    /// that does not depend on the map's iteration order).
    pub fn entries(&self) -> Vec<(PairKey, CachedManifold)> {
        let mut out: Vec<_> = self.manifolds.iter().map(|(k, m)| (*k, *m)).collect();
        out.sort_unstable_by_key(|(k, _)| *k);
        out
    }

    /// A cache holding exactly `entries` (as [`ContactCache::entries`] gave them).
    pub fn from_entries(entries: impl IntoIterator<Item = (PairKey, CachedManifold)>) -> Self {
        Self {
            manifolds: entries.into_iter().collect(),
        }
    }

    /// Forgets every pair involving `id` (a removed body).
    pub fn forget_body(&mut self, id: u64) {
        self.manifolds.retain(|k, _| k.0 != id && k.1 != id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BodyKind, Material};
    use tumble_geometry::{ContactPoint, Point3};

    fn body() -> Body {
        crate::tests::body(
            BodyKind::Dynamic,
            Vec3::repeat(0.5),
            Pose::translation(0.0, 0.5, 0.0),
            1.0,
            Material::default(),
        )
    }

    /// A manifold whose points sit at distinct places chosen by id.
    fn manifold(ids: &[u32], feature: u32) -> Manifold {
        let mut m = Manifold {
            normal: Vec3::y(),
            kind: FeatureKind::FaceA,
            feature,
            ..Default::default()
        };
        for &id in ids {
            m.push(ContactPoint {
                position: Point3::new(id as Real * 0.1, 1.0, 0.0),
                depth: 0.01,
                id,
            });
        }
        m
    }

    #[test]
    fn impulses_follow_feature_ids_and_reset_on_a_new_reference_face() {
        let key = (1, 2);
        let mut contact = Contact::new(0, 1, manifold(&[10, 11, 12], 2));
        for (i, imp) in contact.impulses.iter_mut().enumerate() {
            imp.normal = i as f32 + 1.0;
        }
        let a = body();
        let mut cache = ContactCache::new();
        cache.store(&[key], &[contact], &[a, a]);
        // Same face, points reordered and one new (far from all old points): matched by id,
        // the new one starts at 0.
        let warm = cache.warm_start(&key, &manifold(&[12, 99, 10], 2), &a.pose);
        assert_eq!(
            [warm[0].normal, warm[1].normal, warm[2].normal],
            [3.0, 0.0, 1.0]
        );
        // Another reference face, points elsewhere: nothing carries over.
        let warm = cache.warm_start(&key, &manifold(&[20, 21], 3), &a.pose);
        assert!(warm.iter().all(|w| w.normal == 0.0));
        // Same places under new ids (a corner whose id flipped): matched by position.
        let mut renamed = manifold(&[10, 11], 2);
        renamed.contacts[0].id = 77;
        renamed.contacts[1].id = 78;
        let warm = cache.warm_start(&key, &renamed, &a.pose);
        assert_eq!([warm[0].normal, warm[1].normal], [1.0, 2.0]);
        assert_eq!(cache.previous_feature(&key), Some((FeatureKind::FaceA, 2)));
        cache.forget_body(2);
        assert!(cache.is_empty());
    }
}
