//! Contact persistence: last step's impulses, keyed by body pair and matched by feature id.

use std::collections::HashMap;

use tumble_geometry::{FeatureKind, MAX_MANIFOLD_POINTS, Manifold};

use crate::{Contact, PointImpulse};

/// A body pair's identity that survives body removal and reordering (the facade passes its
/// handles), smaller id first.
pub type PairKey = (u64, u64);

/// What a pair's manifold left behind for the next step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CachedManifold {
    /// Which SAT axis kind made the manifold (hysteresis input for the narrow phase).
    pub kind: FeatureKind,
    /// Reference face or packed edge pair.
    pub feature: u32,
    /// Feature id of each point.
    pub ids: [u32; MAX_MANIFOLD_POINTS],
    /// Impulses of each point at the end of the step.
    pub impulses: [PointImpulse; MAX_MANIFOLD_POINTS],
    /// Number of valid points.
    pub len: u8,
}

/// Impulses of the last step's manifolds, looked up by pair.
#[derive(Clone, Debug, Default)]
pub struct ContactCache {
    manifolds: HashMap<PairKey, CachedManifold>,
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

    /// Last step's impulses for the points of `manifold` whose feature ids match. Ids are only
    /// comparable under the same reference feature, so a changed feature starts cold.
    pub fn warm_start(
        &self,
        key: &PairKey,
        manifold: &Manifold,
    ) -> [PointImpulse; MAX_MANIFOLD_POINTS] {
        let mut out = [PointImpulse::default(); MAX_MANIFOLD_POINTS];
        let Some(old) = self.manifolds.get(key) else {
            return out;
        };
        if old.kind != manifold.kind || old.feature != manifold.feature {
            return out;
        }
        for (slot, p) in out.iter_mut().zip(manifold.points()) {
            if let Some(j) = old.ids[..old.len as usize]
                .iter()
                .position(|&id| id == p.id)
            {
                *slot = old.impulses[j];
            }
        }
        out
    }

    /// Replaces the cache with this step's contacts; `keys[i]` is `contacts[i]`'s pair.
    pub fn store(&mut self, keys: &[PairKey], contacts: &[Contact]) {
        self.manifolds.clear();
        for (key, c) in keys.iter().zip(contacts) {
            let m = &c.manifold;
            let mut ids = [0u32; MAX_MANIFOLD_POINTS];
            for (slot, p) in ids.iter_mut().zip(m.points()) {
                *slot = p.id;
            }
            self.manifolds.insert(
                *key,
                CachedManifold {
                    kind: m.kind,
                    feature: m.feature,
                    ids,
                    impulses: c.impulses,
                    len: m.len,
                },
            );
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
    use tumble_geometry::{ContactPoint, Point3, Vec3};

    fn manifold(ids: &[u32], feature: u32) -> Manifold {
        let mut m = Manifold {
            normal: Vec3::y(),
            kind: FeatureKind::FaceA,
            feature,
            ..Default::default()
        };
        for &id in ids {
            m.push(ContactPoint {
                position: Point3::origin(),
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
        let mut cache = ContactCache::new();
        cache.store(&[key], &[contact]);
        // Same face, points reordered and one new: matched by id, the new one starts at 0.
        let warm = cache.warm_start(&key, &manifold(&[12, 99, 10], 2));
        assert_eq!(
            [warm[0].normal, warm[1].normal, warm[2].normal],
            [3.0, 0.0, 1.0]
        );
        // Another reference face: nothing carries over.
        let warm = cache.warm_start(&key, &manifold(&[10, 11], 3));
        assert!(warm.iter().all(|w| w.normal == 0.0));
        assert_eq!(cache.previous_feature(&key), Some((FeatureKind::FaceA, 2)));
        cache.forget_body(2);
        assert!(cache.is_empty());
    }
}
