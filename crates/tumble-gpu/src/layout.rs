//! Host twins of the structs in `shaders/common/layout.wgsl`: `#[repr(C)]`, `Pod`, explicit
//! padding, the same names and field names as in WGSL. The layout test checks each against
//! naga's layouter through [`shared_struct_layouts`].

use bytemuck::{Pod, Zeroable};

/// Declares structs shared with WGSL, each `#[repr(C)]` with the attributes and fields given,
/// and a function listing their [`StructLayout`]s (sizes and field offsets, in declaration
/// order) for the layout check: a shared struct is written once. A field is either
/// `pub name: Type` with its docs or `pad name, ...: Type`, padding fields as the WGSL struct
/// has them (public, so that other crates can build the structs with `..Default::default()`).
macro_rules! host_structs {
    (
        $(#[$fn_meta:meta])*
        pub fn $layouts:ident();
        $(
            $(#[$meta:meta])*
            pub struct $name:ident { $($body:tt)* }
        )+
    ) => {
        $($crate::layout::host_structs!(@fields [$(#[$meta])* $name] [] [] $($body)*);)+

        $(#[$fn_meta])*
        pub fn $layouts() -> Vec<$crate::layout::StructLayout> {
            vec![$($name::host_layout()),+]
        }
    };
    // Moves the next field, with its name, to the lists built so far.
    (@fields $head:tt [$($fields:tt)*] [$($names:ident)*]
        $(#[$m:meta])* pub $field:ident: $ty:ty $(, $($rest:tt)*)?) => {
        $crate::layout::host_structs!(@fields $head [$($fields)* $(#[$m])* pub $field: $ty,]
            [$($names)* $field] $($($rest)*)?);
    };
    (@fields $head:tt [$($fields:tt)*] [$($names:ident)*]
        pad $($pad:ident),+: $ty:ty $(, $($rest:tt)*)?) => {
        $crate::layout::host_structs!(@fields $head
            [$($fields)* $(#[doc = "Padding."] pub $pad: $ty,)+] [$($names)* $($pad)+]
            $($($rest)*)?);
    };
    (@fields [$(#[$meta:meta])* $name:ident] [$($fields:tt)*] [$($names:ident)*]) => {
        $(#[$meta])*
        #[repr(C)]
        pub struct $name {
            $($fields)*
        }

        impl $name {
            fn host_layout() -> $crate::layout::StructLayout {
                $crate::layout::StructLayout {
                    name: stringify!($name),
                    size: std::mem::size_of::<$name>(),
                    fields: vec![$((stringify!($names), std::mem::offset_of!($name, $names))),*],
                }
            }
        }
    };
}
pub(crate) use host_structs;

host_structs! {
    /// Every struct shared with WGSL.
    pub fn shared_struct_layouts();

    /// A body's pose. 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuPose {
            /// World position of the centre of mass; `w` unused (0).
            pub position: [f32; 4],
            /// Unit quaternion `(x, y, z, w)`, `w` the scalar part (nalgebra's storage order).
            pub rotation: [f32; 4],
    }

    /// A body's velocity. 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuVelocity {
            /// Linear velocity (m/s); `w` unused.
            pub linear: [f32; 4],
            /// Angular velocity (rad/s, world frame); `w` unused.
            pub angular: [f32; 4],
    }

    /// A body's cuboid half extents and flags. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuShape {
            /// Half extent along local x (m).
            pub hx: f32,
            /// Half extent along local y (m).
            pub hy: f32,
            /// Half extent along local z (m).
            pub hz: f32,
            /// Bit set of `BODY_*` flags.
            pub flags: u32,
    }

    /// A world-space AABB. 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuAabb {
            /// Lower corner; `w` unused.
            pub min: [f32; 4],
            /// Upper corner; `w` unused.
            pub max: [f32; 4],
    }

    /// Arguments of `dispatch_workgroups_indirect`, padded to 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct DispatchArgs {
            /// Workgroups along x.
            pub x: u32,
            /// Workgroups along y.
            pub y: u32,
            /// Workgroups along z.
            pub z: u32,
            pad _pad: u32,
    }

    /// A GPU-side count of work items and the dispatch size covering it. 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct WorkList {
            /// Items to process (an append count clamped to the capacity).
            pub count: u32,
            /// Items the producer tried to append; more than `capacity` means overflow.
            pub requested: u32,
            /// Slots in the item buffer.
            pub capacity: u32,
            pad _pad: u32,
            /// Workgroups covering one thread per item, which is also one workgroup per tile of
            /// `WORKGROUP_SIZE` items (the radix sort's tiles).
            pub groups: DispatchArgs,
    }

    /// Parameters of `update_aabbs`. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct UpdateAabbsParams {
            /// Bodies.
            pub count: u32,
            /// Distance every AABB grows by on each side (m): the speculative contact margin.
            pub margin: f32,
            /// Time step (s): AABBs also sweep by velocity times `dt`.
            pub dt: f32,
            pad _pad: u32,
    }

    /// Parameters of one radix sort pass. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct RadixPassParams {
            /// Bit offset of the digit this pass sorts on.
            pub shift: u32,
            pad _pad0, _pad1, _pad2: u32,
    }

    /// Parameters of `sweep_pairs`. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct SweepParams {
            /// Bodies.
            pub body_count: u32,
            /// Slots in the pair buffers.
            pub pair_capacity: u32,
            /// Boxes longer than this on the sweep axis (m) are paired by `long_pairs` instead of
            /// the sweep (see `shaders/common/sweep.wgsl`).
            pub long_extent: f32,
            /// Bits of the world index that lead the sweep's sort keys (0 for one world).
            pub world_bits: u32,
    }

    /// The sweep axis and the statistics it was chosen from. 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct SweepAxis {
            /// 0, 1 or 2: the axis of largest centre variance.
            pub axis: u32,
            pad _pad0, _pad1, _pad2: u32,
            /// Centre variance along x, y, z (m²); `w` unused.
            pub variance: [f32; 4],
    }

    /// Parameters of `collide_cuboids`. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct NarrowParams {
            /// Base speculative margin (m): points this far apart are still reported.
            pub margin: f32,
            /// Time step (s): the margin grows by how far a pair can close in one step.
            pub dt: f32,
            /// The world's `recycle_distance` (m): the largest slide of a recycled point
            /// across the normal is the smaller of it and `RECYCLE_SIZE_FRACTION` of the pair's
            /// smallest half extent. 0: every manifold afresh.
            pub recycle_distance: f32,
            pad _pad0: u32,
    }

    /// One contact point of a manifold. 48 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuContact {
            /// World point midway between the surfaces; `w` unused.
            pub position: [f32; 4],
            /// Accumulated friction impulse (world, N s), carried between steps; `w` unused.
            pub friction_impulse: [f32; 4],
            /// Overlap along the normal (m): positive when overlapping.
            pub depth: f32,
            /// Feature id: the same while the same features touch.
            pub id: u32,
            /// Accumulated normal impulse (N s), carried between steps.
            pub normal_impulse: f32,
            pad _pad: u32,
    }

    /// The manifold of candidate pair `k`; its points are `contacts[k * MAX_MANIFOLD_POINTS..]`.
    /// 48 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuManifold {
            /// Unit normal from A to B; `w` unused.
            pub normal: [f32; 4],
            /// Body A, the smaller index of the pair.
            pub body_a: u32,
            /// Body B.
            pub body_b: u32,
            /// `MANIFOLD_FACE_A`, `MANIFOLD_FACE_B` or `MANIFOLD_EDGE`.
            pub kind: u32,
            /// Reference face, packed edge pair (`edge_a * 12 + edge_b`), or vertex feature.
            pub feature: u32,
            /// Valid points: 0 (no contact) to `MAX_MANIFOLD_POINTS`.
            pub len: u32,
            /// Index of this pair's manifold last step, or `NO_PREVIOUS`.
            pub previous: u32,
            /// 1 when last step's manifold was reused instead of computed (contact
            /// recycling), else 0.
            pub recycled: u32,
            pad _pad0: u32,
    }

    /// A manifold in body A's frame at the poses it was found at, kept per pair slot so that the
    /// next step's `carry_impulses` can match points whose feature ids changed by where they are
    /// on A (the CPU contact cache keeps the same), and so that `collide_cuboids` can reuse it
    /// while the bodies barely moved relative to each other: the anchors of
    /// `tumble_solver::CachedManifold` follow from the points, their depths and B's frame
    /// ([`crate::kernels::recycle`]). A recycled manifold keeps the one it was recycled from,
    /// so it stays that of the manifold last computed. 112 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuLocalManifold {
            /// The manifold normal in A's frame; `w` unused.
            pub normal: [f32; 4],
            /// Each point in A's frame; `w`: its depth. Slots past the manifold's `len` zero.
            pub points: [[f32; 4]; tumble_geometry::MAX_MANIFOLD_POINTS],
            /// B's rotation in A's frame (`x, y, z, w`).
            pub frame_rotation: [f32; 4],
            /// B's origin in A's frame; `w` unused.
            pub frame_position: [f32; 4],
    }

    /// A body's AABB in sweep order, coordinates permuted so the sweep axis comes first (then the
    /// axis after it, then the one after that). 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuSweepBox {
            /// Lower bound on the sweep axis.
            pub lo_0: f32,
            /// Lower bound on the next axis.
            pub lo_1: f32,
            /// Lower bound on the last axis.
            pub lo_2: f32,
            /// The body's index.
            pub body: u32,
            /// Upper bound on the sweep axis.
            pub hi_0: f32,
            /// Upper bound on the next axis.
            pub hi_1: f32,
            /// Upper bound on the last axis.
            pub hi_2: f32,
            /// The body's `GpuShape::flags`.
            pub flags: u32,
    }

    /// A body's collision groups (`tumble_solver::CollisionGroups`): two bodies pair only when
    /// each one's memberships meet the other's filter. 8 bytes.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
    pub struct GpuCollisionGroups {
            /// The groups the body belongs to, one bit each.
            pub memberships: u32,
            /// The groups the body collides with, one bit each (`CollisionGroups::filter`; `filter`
            /// is a WGSL keyword).
            pub filter_bits: u32,
    }

    /// Where a manifold in contact sits: its pair slot and its first point in the dense list.
    /// 8 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct GpuTouching {
            /// Index of the pair (and of its manifold in the per-pair arrays).
            pub slot: u32,
            /// Index of its first point among the dense points.
            pub first_point: u32,
    }

    /// Totals of the dense contact list. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct TouchingCounts {
            /// Manifolds in contact.
            pub manifolds: u32,
            /// Their points.
            pub points: u32,
            pad _pad0, _pad1: u32,
    }

    /// Parameters of `scatter_impulses`. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct ScatterParams {
            /// Dense manifolds to scatter.
            pub count: u32,
            pad _pad0, _pad1, _pad2: u32,
    }

    /// A pair that began or ended touching, or one that touches (`contact_begins`,
    /// `contact_ends`). 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuContactEvent {
            /// `EVENT_BEGIN`, `EVENT_END` or `EVENT_TOUCHING` (`crate::kernels::contact_events`).
            pub kind: u32,
            /// The pair's first body (dense index at the step), the smaller index.
            pub body_a: u32,
            /// The pair's second body.
            pub body_b: u32,
            /// The pair's slot in its step's pair list.
            pub slot: u32,
            /// xyz: the contact point (the points' mean weighted by their normal impulses, or
            /// their plain mean when none pushed); w: the manifold's normal impulse over the
            /// step, N s.
            pub point: [f32; 4],
    }
}

/// Flag bit of [`GpuShape::flags`]: the body never moves (two static bodies never pair).
pub const BODY_STATIC: u32 = 1;

/// [`GpuShape::flags`] holds the index of the body's world from this bit up (bodies of
/// different worlds never pair; 0 in a world stepped alone).
pub const BODY_WORLD_SHIFT: u32 = 8;

/// Worlds one step can hold: the world index must fit the flags above [`BODY_WORLD_SHIFT`].
pub const MAX_WORLDS: u32 = 1 << (32 - BODY_WORLD_SHIFT);

impl GpuPose {
    /// The GPU form of a pose.
    pub fn from_pose(pose: &tumble_geometry::Pose) -> Self {
        let t = pose.translation.vector;
        let q = pose.rotation.coords;
        Self {
            position: [t.x, t.y, t.z, 0.0],
            rotation: [q.x, q.y, q.z, q.w],
        }
    }
}

impl GpuVelocity {
    /// The GPU form of a linear and an angular velocity.
    pub fn new(linear: tumble_geometry::Vec3, angular: tumble_geometry::Vec3) -> Self {
        Self {
            linear: [linear.x, linear.y, linear.z, 0.0],
            angular: [angular.x, angular.y, angular.z, 0.0],
        }
    }
}

impl GpuShape {
    /// A cuboid body's shape, flagged static when it never moves.
    pub fn cuboid(cuboid: &tumble_geometry::Cuboid, is_static: bool) -> Self {
        let h = cuboid.half_extents;
        Self {
            hx: h.x,
            hy: h.y,
            hz: h.z,
            flags: if is_static { BODY_STATIC } else { 0 },
        }
    }

    /// True when the static flag is set.
    pub fn is_static(&self) -> bool {
        self.flags & BODY_STATIC != 0
    }
}

/// Byte offset of [`WorkList::groups`], for indirect dispatch.
pub const WORK_LIST_GROUPS_OFFSET: u64 = std::mem::offset_of!(WorkList, groups) as u64;

impl WorkList {
    /// A work list for `count` items known on the host (same rule as `plan_dispatch.wgsl`).
    pub fn for_count(count: u32) -> Self {
        let (x, y) = crate::constants::workgroups_for(count);
        Self {
            count,
            requested: count,
            capacity: count,
            _pad: 0,
            groups: DispatchArgs {
                x,
                y,
                z: 1,
                _pad: 0,
            },
        }
    }
}

/// Size and field offsets of one host struct, to compare with the WGSL struct of that name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StructLayout {
    /// The struct's name (the same in Rust and WGSL).
    pub name: &'static str,
    /// `size_of` in bytes.
    pub size: usize,
    /// Field names and byte offsets, in declaration order.
    pub fields: Vec<(&'static str, usize)>,
}

impl GpuCollisionGroups {
    /// Every group, colliding with every group (the default: everything collides).
    pub const ALL: Self = Self {
        memberships: u32::MAX,
        filter_bits: u32::MAX,
    };

    /// The GPU form of a body's collision groups.
    pub fn of(groups: tumble_solver::CollisionGroups) -> Self {
        Self {
            memberships: groups.memberships,
            filter_bits: groups.filter,
        }
    }
}

impl Default for GpuCollisionGroups {
    fn default() -> Self {
        Self::ALL
    }
}
