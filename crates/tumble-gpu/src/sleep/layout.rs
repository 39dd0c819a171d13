//! Host twins of `shaders/sleep/common/sleep_types.wgsl`, checked against naga's layouter
//! through [`sleep_struct_layouts`].

use bytemuck::{Pod, Zeroable};

use crate::layout::host_structs;

host_structs! {
    /// Every struct of `sleep_types.wgsl`, for the layout check against naga.
    pub fn sleep_struct_layouts();

    /// The sleep stage's per-world settings (uniform). 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct SleepParams {
            /// Bodies in the world.
            pub body_count: u32,
            /// Time step, s: what a resting body's rest time grows by per step.
            pub dt: f32,
            /// Kinematic bodies (entries of the kinematic list).
            pub kinematic_count: u32,
            pad _pad0: u32,
            /// Workgroups along x of a dispatch over every body ([`crate::constants::workgroups_for`]).
            pub body_groups_x: u32,
            /// Workgroups along y of the same dispatch.
            pub body_groups_y: u32,
            pad _pad1, _pad2: u32,
    }
}
