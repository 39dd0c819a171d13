//! `write_sort_keys`: each body's AABB lower bound on the sweep axis as an order-preserving
//! unsigned key, paired with the body index.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::GpuAabb;
use crate::shader::{Binding, ShaderSource, common, wgsl_file};

/// The kernel: one thread per body.
pub static WRITE_SORT_KEYS: KernelSpec = KernelSpec {
    name: "write_sort_keys",
    source: ShaderSource {
        common: &[common::CONSTANTS, common::INDEXING, common::LAYOUT],
        kernel: wgsl_file!("write_sort_keys.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`WRITE_SORT_KEYS`].
pub struct WriteSortKeysArgs<'a> {
    /// The bodies' `WorkList`.
    pub bodies: &'a wgpu::Buffer,
    /// `SweepAxis` from `choose_axis`.
    pub sweep_axis: &'a wgpu::Buffer,
    /// `array<GpuAabb>`.
    pub aabbs: &'a wgpu::Buffer,
    /// Output keys, one per body.
    pub keys: &'a wgpu::Buffer,
    /// Output body indices, one per body.
    pub values: &'a wgpu::Buffer,
}

impl KernelArgs for WriteSortKeysArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.bodies,
            self.sweep_axis,
            self.aabbs,
            self.keys,
            self.values,
        ]
    }
}

/// An unsigned key whose order is the order of the (non-NaN) floats: negative floats have
/// all bits flipped, others only the sign bit; `-0.0` maps like `+0.0` since they are equal.
pub fn order_key(x: f32) -> u32 {
    let bits = if x == 0.0 { 0 } else { x.to_bits() };
    if bits & 0x8000_0000 != 0 {
        !bits
    } else {
        bits | 0x8000_0000
    }
}

/// The CPU twin of [`WRITE_SORT_KEYS`]: `(keys, body indices)`.
pub fn write_sort_keys_cpu(aabbs: &[GpuAabb], axis: u32) -> (Vec<u32>, Vec<u32>) {
    let keys = aabbs
        .iter()
        .map(|b| order_key(b.min[axis as usize]))
        .collect();
    let values = (0..aabbs.len() as u32).collect();
    (keys, values)
}
