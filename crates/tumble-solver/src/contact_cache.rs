//! Contact persistence: last step's impulses, keyed by body pair and matched by feature id.

use rayon::prelude::*;
use tumble_geometry::{FeatureKind, MAX_MANIFOLD_POINTS, Manifold, Pose, Real, Vec3};

use crate::pair_table::PairTable;
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
#[derive(Clone, Copy, Debug, Default, PartialEq)]
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
    /// Each point's anchor on A's surface, in A's frame: where the manifold last computed for
    /// the pair (not a recycled one) put it ([`CachedManifold::recycle`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub anchors_a: [Vec3; MAX_MANIFOLD_POINTS],
    /// Each point's anchor on B's surface, in B's frame, from the same manifold.
    #[cfg_attr(feature = "serde", serde(default))]
    pub anchors_b: [Vec3; MAX_MANIFOLD_POINTS],
    /// That manifold's normal in B's frame.
    #[cfg_attr(feature = "serde", serde(default))]
    pub normal_b: Vec3,
    /// Bit `i`: point `i` of that manifold overlapped (depth at least 0).
    #[cfg_attr(feature = "serde", serde(default))]
    pub overlapped: u8,
}

/// Stored manifolds below which the cache is written on the calling thread: one costs some
/// tens of nanoseconds, a rayon task a few microseconds.
pub(crate) const PARALLEL_MIN_STORE: usize = 2048;

/// Manifolds per rayon task when the cache is written in parallel.
const STORE_PER_TASK: usize = 512;

/// Impulses of the last step's manifolds, looked up by pair.
///
/// The step's pairs sit in two flat arrays in the order they were stored (the keys, and what
/// each manifold left), with a table of slot numbers by key beside them ([`PairTable`]). All
/// three are written on the thread pool and keep their memory from step to step; what a
/// lookup answers does not depend on the number of threads.
#[derive(Clone, Debug, Default)]
pub struct ContactCache {
    /// The stored pair of each slot.
    keys: Vec<PairKey>,
    /// What the manifold of each slot left behind, parallel to `keys`.
    manifolds: Vec<CachedManifold>,
    /// The slot of each stored pair (the last one when a pair was stored twice).
    table: PairTable,
    /// Distinct stored pairs.
    len: usize,
    /// Last store's entries, kept for their memory: the next store writes into it.
    spare: Vec<CachedManifold>,
}

impl ContactCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of cached pairs.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// What the pair `key` left behind last step, if it had a manifold.
    #[inline]
    pub fn get(&self, key: &PairKey) -> Option<&CachedManifold> {
        self.table
            .get(&self.keys, key)
            .map(|slot| &self.manifolds[slot])
    }

    /// [`Self::get`] with the entry's slot, trying slot `hint` first: a pile's pairs come in
    /// the order they were stored, so the slot after the last one found is usually the next
    /// pair's, and then the table is not read. The table answers otherwise (or when a pair
    /// was stored twice, where it holds the later slot).
    #[inline]
    pub fn get_near(&self, key: &PairKey, hint: usize) -> Option<(usize, &CachedManifold)> {
        if self.len == self.keys.len() && self.keys.get(hint) == Some(key) {
            return Some((hint, &self.manifolds[hint]));
        }
        self.table
            .get(&self.keys, key)
            .map(|slot| (slot, &self.manifolds[slot]))
    }

    /// Last step's feature for `key`, for the narrow phase's hysteresis.
    pub fn previous_feature(&self, key: &PairKey) -> Option<(FeatureKind, u32)> {
        self.get(key).map(|m| (m.kind, m.feature))
    }

    /// Last step's impulses for the points of `manifold`, whose body A is at `pose_a`
    /// ([`CachedManifold::warm_start`] on the pair's entry; zero when it has none).
    pub fn warm_start(
        &self,
        key: &PairKey,
        manifold: &Manifold,
        pose_a: &Pose,
    ) -> [PointImpulse; MAX_MANIFOLD_POINTS] {
        match self.get(key) {
            Some(old) => old.warm_start(manifold, pose_a),
            None => [PointImpulse::default(); MAX_MANIFOLD_POINTS],
        }
    }

    /// Last step's tilt impulse of the pair ([`CachedManifold::warm_tilt`]; zero when it has
    /// no entry).
    pub fn warm_tilt(&self, key: &PairKey, manifold: &Manifold, pose_a: &Pose) -> Vec3 {
        self.get(key)
            .map_or_else(Vec3::zeros, |old| old.warm_tilt(manifold, pose_a))
    }

    /// Replaces the cache with this step's contacts; `keys[i]` is `contacts[i]`'s pair and
    /// `bodies` must still hold the poses the manifolds were computed from. A pair given
    /// twice keeps its later manifold.
    pub fn store(&mut self, keys: &[PairKey], contacts: &[Contact], bodies: &[Body]) {
        let n = keys.len().min(contacts.len());
        let (keys, contacts) = (&keys[..n], &contacts[..n]);
        // The same pairs in the same order as last time, each once (every key went into the
        // table): slot `i` held `keys[i]`, so contact `i`'s old entry is slot `i`, and the
        // table built from these keys is the one already here. A resting pile's pairs are.
        let same = self.len == self.keys.len() && self.keys[..] == keys[..];
        if same {
            // Each entry is updated where it is: a recycled contact's keeps what it had beside
            // the points and impulses, the others are replaced.
            let update = |(c, entry): (&Contact, &mut CachedManifold)| {
                let pose_a = &bodies[c.body_a as usize].pose;
                if c.recycled {
                    entry.take_recycled(c, pose_a);
                } else {
                    *entry = CachedManifold::of(c, pose_a, &bodies[c.body_b as usize].pose);
                }
            };
            let entries = &mut self.manifolds[..n];
            if n >= PARALLEL_MIN_STORE && rayon::current_num_threads() > 1 {
                contacts
                    .par_iter()
                    .zip(entries.par_iter_mut())
                    .with_min_len(STORE_PER_TASK)
                    .for_each(update);
            } else {
                contacts.iter().zip(entries.iter_mut()).for_each(update);
            }
            return;
        }
        // The new entries are built beside the old ones: a recycled contact keeps the anchors
        // of its pair's entry, which is looked up in the old cache.
        let mut fresh = std::mem::take(&mut self.spare);
        let old = &*self;
        let cached = |(key, c): (&PairKey, &Contact)| {
            let pose_a = &bodies[c.body_a as usize].pose;
            if c.recycled
                && let Some(last) = old.get(key)
            {
                return CachedManifold::recycled_of(c, pose_a, last);
            }
            CachedManifold::of(c, pose_a, &bodies[c.body_b as usize].pose)
        };
        if n >= PARALLEL_MIN_STORE && rayon::current_num_threads() > 1 {
            keys.par_iter()
                .zip(contacts.par_iter())
                .with_min_len(STORE_PER_TASK)
                .map(cached)
                .collect_into_vec(&mut fresh);
        } else {
            fresh.clear();
            fresh.extend(keys.iter().zip(contacts).map(cached));
        }
        self.spare = std::mem::replace(&mut self.manifolds, fresh);
        self.keys.clear();
        self.keys.extend_from_slice(keys);
        self.len = self.table.rebuild(&self.keys);
    }

    /// Every cached pair with what it left behind, sorted by pair key (a copy of the cache
    /// that does not depend on the table's layout).
    pub fn entries(&self) -> Vec<(PairKey, CachedManifold)> {
        let mut out: Vec<_> = self
            .table
            .slots()
            .map(|s| (self.keys[s], self.manifolds[s]))
            .collect();
        out.sort_unstable_by_key(|(k, _)| *k);
        out
    }

    /// A cache holding exactly `entries` (as [`ContactCache::entries`] gave them).
    pub fn from_entries(entries: impl IntoIterator<Item = (PairKey, CachedManifold)>) -> Self {
        let (keys, manifolds): (Vec<PairKey>, Vec<CachedManifold>) = entries.into_iter().unzip();
        let mut table = PairTable::default();
        let len = table.rebuild(&keys);
        Self {
            keys,
            manifolds,
            table,
            len,
            spare: Vec::new(),
        }
    }

    /// Forgets every pair involving `id` (a removed body).
    pub fn forget_body(&mut self, id: u64) {
        let kept = |k: &PairKey| k.0 != id && k.1 != id;
        let mut keep = self.keys.iter().map(kept);
        self.manifolds.retain(|_| keep.next().unwrap_or(false));
        self.spare.clear();
        self.keys.retain(kept);
        self.len = self.table.rebuild(&self.keys);
    }
}

impl CachedManifold {
    /// What `contact` leaves behind, its bodies at `pose_a` and `pose_b` (the poses the
    /// manifold came from): points and normal in A's frame, feature ids, impulses, and the
    /// anchors [`CachedManifold::recycle`] reuses it by.
    pub fn of(contact: &Contact, pose_a: &Pose, pose_b: &Pose) -> Self {
        let m = &contact.manifold;
        let mut ids = [0u32; MAX_MANIFOLD_POINTS];
        let mut local_points = [Vec3::zeros(); MAX_MANIFOLD_POINTS];
        let mut anchors_a = [Vec3::zeros(); MAX_MANIFOLD_POINTS];
        let mut anchors_b = [Vec3::zeros(); MAX_MANIFOLD_POINTS];
        let mut overlapped = 0u8;
        for (i, p) in m.points().iter().enumerate() {
            ids[i] = p.id;
            local_points[i] = pose_a.inverse_transform_point(&p.position).coords;
            // The position is midway between the surfaces along the normal: A's surface lies
            // half the depth towards B, B's half the depth back.
            let half = m.normal * (0.5 * p.depth);
            anchors_a[i] = pose_a.inverse_transform_point(&(p.position + half)).coords;
            anchors_b[i] = pose_b.inverse_transform_point(&(p.position - half)).coords;
            if p.depth >= 0.0 {
                overlapped |= 1 << i;
            }
        }
        CachedManifold {
            kind: m.kind,
            feature: m.feature,
            ids,
            local_points,
            local_normal: pose_a.rotation.inverse_transform_vector(&m.normal),
            impulses: contact.impulses,
            tilt_impulse: contact.tilt_impulse,
            len: m.len,
            anchors_a,
            anchors_b,
            normal_b: pose_b.rotation.inverse_transform_vector(&m.normal),
            overlapped,
        }
    }

    /// What a recycled `contact` leaves behind: [`CachedManifold::of`] with the anchors,
    /// normals and overlap signs of `last`, the entry it was recycled from, so that they stay
    /// those of the manifold last computed (`of(..).with_anchors_of(last)`, without computing
    /// the anchors it would replace).
    pub fn recycled_of(contact: &Contact, pose_a: &Pose, last: &CachedManifold) -> Self {
        let mut entry = *last;
        entry.take_recycled(contact, pose_a);
        entry
    }

    /// Makes this entry, the one `contact`'s recycled manifold came from, the entry of that
    /// manifold in place: [`Self::recycled_of`] without a copy of what stays.
    pub fn take_recycled(&mut self, contact: &Contact, pose_a: &Pose) {
        let m = &contact.manifold;
        let mut ids = [0u32; MAX_MANIFOLD_POINTS];
        let mut local_points = [Vec3::zeros(); MAX_MANIFOLD_POINTS];
        for (i, p) in m.points().iter().enumerate() {
            ids[i] = p.id;
            local_points[i] = pose_a.inverse_transform_point(&p.position).coords;
        }
        self.kind = m.kind;
        self.feature = m.feature;
        self.ids = ids;
        self.local_points = local_points;
        self.impulses = contact.impulses;
        self.tilt_impulse = contact.tilt_impulse;
        self.len = m.len;
    }

    /// This entry (of a recycled manifold) with the anchors, normals and signs of `last`, the
    /// entry it was recycled from, so that they stay those of the manifold last computed.
    pub fn with_anchors_of(self, last: &CachedManifold) -> Self {
        CachedManifold {
            local_normal: last.local_normal,
            anchors_a: last.anchors_a,
            anchors_b: last.anchors_b,
            normal_b: last.normal_b,
            overlapped: last.overlapped,
            ..self
        }
    }

    /// These impulses carried to the points of this step's `manifold` of the same pair, whose
    /// body A is at `pose_a`.
    ///
    /// A point inherits the impulse of the old point with the same feature id under the same
    /// reference feature (ids are only comparable then). Failing that, it inherits from the
    /// nearest unclaimed old point within [`PERSIST_DISTANCE`] in A's frame, provided the
    /// normal turned by less than the angle of [`PERSIST_NORMAL_COS`].
    pub fn warm_start(
        &self,
        manifold: &Manifold,
        pose_a: &Pose,
    ) -> [PointImpulse; MAX_MANIFOLD_POINTS] {
        let old = self;
        let mut out = [PointImpulse::default(); MAX_MANIFOLD_POINTS];
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

    /// This tilt impulse, when this step's `manifold` of the pair (body A at `pose_a`) has a
    /// normal turned by less than the angle of [`PERSIST_NORMAL_COS`] (the patch is the same
    /// patch); zero otherwise.
    pub fn warm_tilt(&self, manifold: &Manifold, pose_a: &Pose) -> Vec3 {
        let normal = pose_a.rotation.inverse_transform_vector(&manifold.normal);
        if normal.dot(&self.local_normal) >= PERSIST_NORMAL_COS {
            self.tilt_impulse
        } else {
            Vec3::zeros()
        }
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
