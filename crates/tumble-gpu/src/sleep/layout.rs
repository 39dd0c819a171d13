//! Host twins of `shaders/sleep/common/sleep_types.wgsl`, checked against naga's layouter
//! through [`sleep_struct_layouts`].

use bytemuck::{Pod, Zeroable};

use crate::layout::StructLayout;

/// The sleep stage's per-world settings (uniform). 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SleepParams {
    /// Bodies in the world.
    pub body_count: u32,
    /// Time step, s: what a resting body's rest time grows by per step.
    pub dt: f32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}

/// Every struct of `sleep_types.wgsl`, for the layout check against naga.
pub fn sleep_struct_layouts() -> Vec<StructLayout> {
    vec![StructLayout {
        name: "SleepParams",
        size: std::mem::size_of::<SleepParams>(),
        fields: vec![
            ("body_count", std::mem::offset_of!(SleepParams, body_count)),
            ("dt", std::mem::offset_of!(SleepParams, dt)),
            ("_pad0", std::mem::offset_of!(SleepParams, _pad0)),
            ("_pad1", std::mem::offset_of!(SleepParams, _pad1)),
        ],
    }]
}
