//! Spatial queries over the world's current state, on the CPU: ray casts (closest hit, all
//! hits), box casts, and the bodies overlapping an AABB, containing a point, or nearest to one.
//!
//! Every backend answers them: the poses come through the same getters as
//! [`World::pose`] (on `Backend::Gpu` a lazy read of the last step's results, made once for
//! all bodies). They go through a bounding volume hierarchy over the bodies' tight boxes,
//! built on the first query after the bodies changed and kept until the next step, added or
//! removed body, or `set_pose`, so a batch of queries between two steps builds it once.
//!
//! On `Backend::Gpu`, [`World::cast_rays_gpu`] casts a batch of rays on the GPU in one
//! dispatch, against the step's own buffers, with [`World::cast_ray`]'s answers.
//!
//! The shape tests are those of `tumble_geometry`: the slab test for rays
//! ([`tumble_geometry::Cuboid::cast_ray`]) and the exact swept separating axis test for boxes
//! ([`tumble_geometry::cast_cuboid`], [`tumble_geometry::cuboids_intersect`]); both are exact
//! up to `f32` rounding (their docs give the bounds). Boxes are solid: a cast starting inside
//! a body hits it at `toi = 0` with a zero normal.

mod bvh;
mod filter;
mod gpu_rays;
pub(crate) mod input;

pub(crate) use bvh::QueryCache;
pub use filter::QueryFilter;
pub use gpu_rays::Ray;

use tumble_geometry::{Aabb, CastHit, Cuboid, Point3, Pose, Real, Vec3};
use tumble_geometry::{cast_cuboid, cuboids_intersect};

use crate::{BodyHandle, Error, World};
use bvh::{Bvh, Entry};

/// Where a ray hit a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The body hit.
    pub body: BodyHandle,
    /// The time of impact, in units of the ray's direction: the hit is at
    /// `origin + toi * dir`. 0 when the ray starts inside the body.
    pub toi: Real,
    /// The hit point, `origin + toi * dir`.
    pub point: Point3,
    /// The body's outward unit normal at the hit; zero when the ray starts inside the body.
    pub normal: Vec3,
}

/// Where a cast box first touched a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxHit {
    /// The body touched.
    pub body: BodyHandle,
    /// The time of impact, in units of the velocity: the box touches the body when moved by
    /// `toi * velocity`. 0 when it overlaps the body at the start.
    pub toi: Real,
    /// The body's outward unit normal at the touch (towards the cast box); zero when the box
    /// overlaps the body at the start.
    pub normal: Vec3,
}

/// The body nearest to a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointHit {
    /// The nearest body.
    pub body: BodyHandle,
    /// The point of the body nearest to the query point (the query point itself when inside).
    pub point: Point3,
    /// The distance from the query point to the body, m (0 inside).
    pub distance: Real,
}

/// True when `a` comes before `b` among hits: earlier, or as early and first in the world's
/// order (so that ties are broken the same way whatever the tree's shape).
fn earlier(a: (Real, usize), b: (Real, usize)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1)
}

impl World {
    /// The query tree of the current poses, built if there is none.
    fn query_tree(&self) -> Result<&Bvh, Error> {
        self.query.get_or_build(|| {
            let handles = self.handles.handles();
            let entries = (0..self.host.bodies.len())
                .map(|d| {
                    let pose = self.backend.pose(&self.host, d)?;
                    let body = &self.host.bodies[d];
                    Ok(Entry {
                        handle: handles[d],
                        dense: d,
                        kind: body.kind,
                        shape: body.shape,
                        pose,
                        aabb: body.shape.aabb(&pose, 0.0),
                    })
                })
                .collect::<Result<Vec<_>, Error>>()?;
            Ok(Bvh::build(entries))
        })
    }

    /// Whether `filter` keeps `e`. `sleep` is whether the sleep effect runs.
    /// The earliest hit among the bodies `filter` keeps of a cast from `origin` along `dir`
    /// (boxes grown by `grow` for the tree's culling) up to `max_toi`, `cast` giving one body's
    /// hit before a time; ties go to the body first in `World::handles` order.
    fn first_along(
        &self,
        origin: &Point3,
        dir: &Vec3,
        grow: &Vec3,
        max_toi: Real,
        filter: &QueryFilter<'_>,
        cast: impl Fn(&Entry, Real) -> Option<CastHit>,
    ) -> Result<Option<(CastHit, Entry)>, Error> {
        let sleep = self.effects().sleep;
        let mut best: Option<(CastHit, Entry)> = None;
        let mut max = max_toi;
        self.query_tree()?
            .along_ray(origin, dir, grow, &mut max, |e, max| {
                let Some(hit) = cast(e, *max) else {
                    return Ok(());
                };
                let better =
                    best.is_none_or(|(b, be)| earlier((hit.toi, e.dense), (b.toi, be.dense)));
                if better && self.keeps(filter, e, sleep)? {
                    *max = hit.toi;
                    best = Some((hit, *e));
                }
                Ok::<(), Error>(())
            })?;
        Ok(best)
    }

    fn keeps(&self, filter: &QueryFilter<'_>, e: &Entry, sleep: bool) -> Result<bool, Error> {
        if !filter.passes_static(e.handle, e.kind) {
            return Ok(false);
        }
        if filter.skip_sleeping && self.backend.is_sleeping(&self.host, e.dense, sleep)? {
            return Ok(false);
        }
        Ok(filter.predicate.is_none_or(|keep| keep(e.handle)))
    }

    /// The first body hit by the ray `origin + t dir`, `t` in `[0, max_toi]`, among those
    /// `filter` keeps; `None` when it hits nothing. `dir` need not be unit length: `toi` is
    /// in its units (with a unit `dir`, in metres). A ray starting inside a body hits it at
    /// `toi = 0` with a zero normal. Of two bodies hit at the same `toi`, the one first in
    /// [`World::handles`] is returned.
    ///
    /// Errs, naming the argument, on an `origin` that is not finite or lies beyond
    /// [`tumble_solver::bounds::MAX_POSITION`], a `dir` that is not finite or is zero, and a
    /// negative or NaN `max_toi` (infinity is allowed).
    ///
    /// ```
    /// use tumble::prelude::*;
    /// use tumble::QueryFilter;
    ///
    /// let mut world = World::new(WorldConfig::default())?;
    /// let floor = world.add_body(
    ///     BodyDesc::fixed().cuboid(Vec3::new(5.0, 0.5, 5.0)).translation(0.0, -0.5, 0.0),
    /// )?;
    /// let cube = world.add_body(BodyDesc::dynamic().translation(0.0, 3.0, 0.0))?;
    /// let down = -Vec3::y();
    /// // From 10 m up, straight down: the cube's top face at y = 3.5.
    /// let hit = world
    ///     .cast_ray(Point3::new(0.0, 10.0, 0.0), down, 100.0, QueryFilter::default())?
    ///     .expect("the ray hits the cube");
    /// assert_eq!(hit.body, cube);
    /// assert!((hit.toi - 6.5).abs() < 1e-5);
    /// assert!((hit.normal - Vec3::y()).norm() < 1e-6);
    /// // Beside the cube, the floor's top at y = 0.
    /// let hit = world.cast_ray(Point3::new(2.0, 10.0, 0.0), down, 100.0, QueryFilter::default())?;
    /// assert_eq!(hit.map(|h| h.body), Some(floor));
    /// // Once the cube has fallen onto the floor, the same ray sees it where it rests.
    /// for _ in 0..120 {
    ///     world.step()?;
    /// }
    /// let hit = world.cast_ray(Point3::new(0.0, 10.0, 0.0), down, 100.0, QueryFilter::default())?;
    /// assert!((hit.expect("the cube").point.y - 1.0).abs() < 0.01);
    /// // Bad input is an error naming the argument.
    /// let err = world.cast_ray(Point3::origin(), Vec3::zeros(), 1.0, QueryFilter::default());
    /// assert_eq!(err.unwrap_err().field(), Some("dir"));
    /// # Ok::<(), tumble::Error>(())
    /// ```
    pub fn cast_ray(
        &self,
        origin: Point3,
        dir: Vec3,
        max_toi: Real,
        filter: QueryFilter<'_>,
    ) -> Result<Option<RayHit>, Error> {
        ray_input(&origin, &dir, max_toi)?;
        let best =
            self.first_along(&origin, &dir, &Vec3::zeros(), max_toi, &filter, |e, max| {
                e.shape.cast_ray(&e.pose, &origin, &dir, max)
            })?;
        Ok(best.map(|(hit, e)| ray_hit(&e, &hit, &origin, &dir)))
    }

    /// Every body the ray `origin + t dir`, `t` in `[0, max_toi]`, hits among those `filter`
    /// keeps, each once at its first hit, sorted by `toi` (ties in the order of
    /// [`World::handles`]). The conventions and errors of [`World::cast_ray`].
    pub fn cast_ray_all(
        &self,
        origin: Point3,
        dir: Vec3,
        max_toi: Real,
        filter: QueryFilter<'_>,
    ) -> Result<Vec<RayHit>, Error> {
        ray_input(&origin, &dir, max_toi)?;
        let sleep = self.effects().sleep;
        let mut hits: Vec<(usize, RayHit)> = Vec::new();
        let mut max = max_toi;
        self.query_tree()?
            .along_ray(&origin, &dir, &Vec3::zeros(), &mut max, |e, max| {
                if let Some(hit) = e.shape.cast_ray(&e.pose, &origin, &dir, *max)
                    && self.keeps(&filter, e, sleep)?
                {
                    hits.push((e.dense, ray_hit(e, &hit, &origin, &dir)));
                }
                Ok::<(), Error>(())
            })?;
        hits.sort_by(|(da, a), (db, b)| a.toi.total_cmp(&b.toi).then(da.cmp(db)));
        Ok(hits.into_iter().map(|(_, h)| h).collect())
    }

    /// The first body that a box of `half_extents`, starting at `pose` and moved by
    /// `t * velocity` (no rotation), `t` in `[0, max_toi]`, touches among those `filter`
    /// keeps; `None` when it touches nothing. `toi` is in units of `velocity` (seconds for
    /// m/s). A box overlapping a body at the start touches it at `toi = 0` with a zero
    /// normal; ties go to the body first in [`World::handles`].
    ///
    /// Method: the exact swept separating axis test ([`tumble_geometry::cast_cuboid`]), so the
    /// time of impact carries only `f32` rounding: about `1e-6` of the distances involved,
    /// divided by the speed along the axis of the touch.
    ///
    /// Errs, naming the argument, on a half extent that is not finite and positive
    /// (`half_extents.x`, ...), a `pose` outside the bounds of [`World::set_pose`], a
    /// `velocity` that is not finite or is zero, and a negative or NaN `max_toi`.
    pub fn cast_box(
        &self,
        half_extents: Vec3,
        pose: Pose,
        velocity: Vec3,
        max_toi: Real,
        filter: QueryFilter<'_>,
    ) -> Result<Option<BoxHit>, Error> {
        input::half_extents(&half_extents)?;
        input::pose(&pose)?;
        input::direction("velocity", &velocity)?;
        input::reach("max_toi", max_toi)?;
        let mut pose = pose;
        pose.rotation.renormalize();
        let moving = Cuboid::new(half_extents);
        let grow = moving.aabb(&pose, 0.0).half_extents();
        let centre = Point3::from(pose.translation.vector);
        let best = self.first_along(&centre, &velocity, &grow, max_toi, &filter, |e, max| {
            cast_cuboid(&moving, &pose, &velocity, &e.shape, &e.pose, max)
        })?;
        Ok(best.map(|(hit, e)| BoxHit {
            body: e.handle,
            toi: hit.toi,
            normal: hit.normal,
        }))
    }

    /// The bodies whose box overlaps or touches `aabb` (the bodies' own oriented boxes, not
    /// their bounding boxes: exact up to rounding, by the separating axis test) among those
    /// `filter` keeps, in the order of [`World::handles`]. Errs on corners that are not
    /// finite or a `min` above `max` on some axis (`aabb`).
    pub fn bodies_in_aabb(
        &self,
        aabb: Aabb,
        filter: QueryFilter<'_>,
    ) -> Result<Vec<BodyHandle>, Error> {
        input::aabb(&aabb)?;
        let query = Cuboid::new(aabb.half_extents());
        let c = aabb.center();
        let at = Pose::translation(c.x, c.y, c.z);
        self.collect_overlapping(&aabb, filter, |e| {
            cuboids_intersect(&e.shape, &e.pose, &query, &at)
        })
    }

    /// The bodies whose closed box contains `point`, among those `filter` keeps, in the order
    /// of [`World::handles`]. Errs on a `point` that is not finite or lies beyond
    /// [`tumble_solver::bounds::MAX_POSITION`].
    pub fn bodies_containing_point(
        &self,
        point: Point3,
        filter: QueryFilter<'_>,
    ) -> Result<Vec<BodyHandle>, Error> {
        input::position("point", &point)?;
        let at = Aabb::new(point, point);
        self.collect_overlapping(&at, filter, |e| e.shape.contains_point(&e.pose, &point))
    }

    /// The body nearest to `point` within `max_dist` (m, infinity allowed) among those
    /// `filter` keeps, with its nearest point and the distance (0 for a body containing
    /// `point`); ties go to the body first in [`World::handles`]. Errs on a `point` as
    /// [`World::bodies_containing_point`] does, and on a negative or NaN `max_dist`.
    pub fn project_point(
        &self,
        point: Point3,
        max_dist: Real,
        filter: QueryFilter<'_>,
    ) -> Result<Option<PointHit>, Error> {
        input::position("point", &point)?;
        input::reach("max_dist", max_dist)?;
        let reach = Aabb::new(point, point).grown(&Vec3::repeat(max_dist));
        let sleep = self.effects().sleep;
        let mut best: Option<(PointHit, usize)> = None;
        self.query_tree()?.overlapping(&reach, |e| {
            let proj = e.shape.project_point(&e.pose, &point, true);
            let distance = if proj.is_inside {
                0.0
            } else {
                (proj.point - point).norm()
            };
            let better = best.is_none_or(|(b, d)| earlier((distance, e.dense), (b.distance, d)));
            if distance <= max_dist && better && self.keeps(&filter, e, sleep)? {
                let hit = PointHit {
                    body: e.handle,
                    point: proj.point,
                    distance,
                };
                best = Some((hit, e.dense));
            }
            Ok::<(), Error>(())
        })?;
        Ok(best.map(|(hit, _)| hit))
    }

    /// The handles of the bodies whose box meets `aabb` and passes `test` and `filter`, in
    /// dense order.
    fn collect_overlapping(
        &self,
        aabb: &Aabb,
        filter: QueryFilter<'_>,
        test: impl Fn(&Entry) -> bool,
    ) -> Result<Vec<BodyHandle>, Error> {
        let sleep = self.effects().sleep;
        let mut found: Vec<(usize, BodyHandle)> = Vec::new();
        self.query_tree()?.overlapping(aabb, |e| {
            if test(e) && self.keeps(&filter, e, sleep)? {
                found.push((e.dense, e.handle));
            }
            Ok::<(), Error>(())
        })?;
        found.sort_unstable_by_key(|&(d, _)| d);
        Ok(found.into_iter().map(|(_, h)| h).collect())
    }
}

/// The checks of a ray's arguments.
fn ray_input(origin: &Point3, dir: &Vec3, max_toi: Real) -> Result<(), Error> {
    input::position("origin", origin)?;
    input::direction("dir", dir)?;
    input::reach("max_toi", max_toi)
}

/// The world's hit from the shape's.
fn ray_hit(e: &Entry, hit: &CastHit, origin: &Point3, dir: &Vec3) -> RayHit {
    RayHit {
        body: e.handle,
        toi: hit.toi,
        point: origin + dir * hit.toi,
        normal: hit.normal,
    }
}
