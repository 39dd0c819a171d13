//! Which bodies a query considers.

use std::fmt;

use tumble_solver::BodyKind;

use crate::BodyHandle;

/// Which bodies a query considers: by default every body of the world.
///
/// ```
/// use tumble::prelude::*;
/// use tumble::QueryFilter;
///
/// let mut world = World::new(WorldConfig::default())?;
/// let floor = world.add_body(BodyDesc::fixed().cuboid(Vec3::new(5.0, 0.5, 5.0)))?;
/// let player = world.add_body(BodyDesc::dynamic().translation(0.0, 2.0, 0.0))?;
/// // Straight down from inside the player, skipping it: the floor's top at y = 0.5.
/// let not_floor = |h: BodyHandle| h != floor;
/// let down = -Vec3::y();
/// let origin = Point3::new(0.0, 2.0, 0.0);
/// let hit = world.cast_ray(origin, down, 10.0, QueryFilter::new().exclude(player))?;
/// assert_eq!(hit.map(|h| h.body), Some(floor));
/// // Skipping fixed bodies, or keeping only what a predicate accepts, finds nothing else.
/// let skip = QueryFilter::new().exclude(player).skip_fixed();
/// assert!(world.cast_ray(origin, down, 10.0, skip)?.is_none());
/// let picky = QueryFilter::new().exclude(player).predicate(&not_floor);
/// assert!(world.cast_ray(origin, down, 10.0, picky)?.is_none());
/// # Ok::<(), tumble::Error>(())
/// ```
#[derive(Clone, Copy, Default)]
pub struct QueryFilter<'a> {
    /// A body to leave out (the caster itself, say).
    pub exclude: Option<BodyHandle>,
    /// Leave out fixed bodies.
    pub skip_fixed: bool,
    /// Leave out sleeping bodies.
    pub skip_sleeping: bool,
    /// Keep only the bodies it returns `true` for (called after the other conditions, only
    /// for bodies the query's shape reaches).
    pub predicate: Option<&'a dyn Fn(BodyHandle) -> bool>,
}

impl<'a> QueryFilter<'a> {
    /// Every body.
    pub fn new() -> Self {
        Self::default()
    }

    /// Leaves out `body`.
    pub fn exclude(self, body: BodyHandle) -> Self {
        Self {
            exclude: Some(body),
            ..self
        }
    }

    /// Leaves out fixed bodies.
    pub fn skip_fixed(self) -> Self {
        Self {
            skip_fixed: true,
            ..self
        }
    }

    /// Leaves out sleeping bodies.
    pub fn skip_sleeping(self) -> Self {
        Self {
            skip_sleeping: true,
            ..self
        }
    }

    /// Keeps only the bodies `keep` returns `true` for.
    pub fn predicate(self, keep: &'a dyn Fn(BodyHandle) -> bool) -> Self {
        Self {
            predicate: Some(keep),
            ..self
        }
    }

    /// The conditions that need no state beyond the body's handle and kind.
    pub(crate) fn passes_static(&self, handle: BodyHandle, kind: BodyKind) -> bool {
        self.exclude != Some(handle) && !(self.skip_fixed && kind == BodyKind::Fixed)
    }
}

impl fmt::Debug for QueryFilter<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("QueryFilter")
            .field("exclude", &self.exclude)
            .field("skip_fixed", &self.skip_fixed)
            .field("skip_sleeping", &self.skip_sleeping)
            .field(
                "predicate",
                &self.predicate.map(|_| "Fn(BodyHandle) -> bool"),
            )
            .finish()
    }
}
