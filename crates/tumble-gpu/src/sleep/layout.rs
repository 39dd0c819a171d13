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
    /// Kinematic bodies (entries of the kinematic list).
    pub kinematic_count: u32,
    /// Padding.
    pub _pad: u32,
}

/// Every struct of `sleep_types.wgsl`, for the layout check against naga.
pub fn sleep_struct_layouts() -> Vec<StructLayout> {
    vec![StructLayout {
        name: "SleepParams",
        size: std::mem::size_of::<SleepParams>(),
        fields: vec![
            ("body_count", std::mem::offset_of!(SleepParams, body_count)),
            ("dt", std::mem::offset_of!(SleepParams, dt)),
            (
                "kinematic_count",
                std::mem::offset_of!(SleepParams, kinematic_count),
            ),
            ("_pad", std::mem::offset_of!(SleepParams, _pad)),
        ],
    }]
}
