//! `write_sort_keys`: each body's AABB lower bound on the sweep axis as an order-preserving
//! unsigned key, paired with the body index.

use crate::kernel::KernelSpec;
use crate::layout::GpuAabb;
use crate::shader::file;

/// The kernel: one thread per body.
pub static WRITE_SORT_KEYS: KernelSpec = KernelSpec::new(file("write_sort_keys.wgsl"));

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

/// The sort key of bound `x` in world `world` when the step's largest world index has
/// `world_bits` bits: the world leads, then the top of [`order_key`] (`sweep_key` in
/// `shaders/common/sweep.wgsl`). With one world (`world_bits` 0) it is `order_key(x)`.
pub fn sweep_key(world: u32, x: f32, world_bits: u32) -> u32 {
    if world_bits == 0 {
        return order_key(x);
    }
    (world << (32 - world_bits)) | (order_key(x) >> world_bits)
}

/// The CPU twin of [`WRITE_SORT_KEYS`] for one world: `(keys, body indices)`.
pub fn write_sort_keys_cpu(aabbs: &[GpuAabb], axis: u32) -> (Vec<u32>, Vec<u32>) {
    write_sort_keys_in_worlds_cpu(aabbs, &[], axis, 0)
}

/// The CPU twin of [`WRITE_SORT_KEYS`]: `(keys, body indices)`, body `i` in world `worlds[i]`
/// (all in world 0 when empty), `world_bits` the bits of the largest world index.
pub fn write_sort_keys_in_worlds_cpu(
    aabbs: &[GpuAabb],
    worlds: &[u32],
    axis: u32,
    world_bits: u32,
) -> (Vec<u32>, Vec<u32>) {
    let keys = aabbs
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let world = worlds.get(i).copied().unwrap_or(0);
            sweep_key(world, b.min[axis as usize], world_bits)
        })
        .collect();
    let values = (0..aabbs.len() as u32).collect();
    (keys, values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn order_keys_sort_like_the_floats() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let mut xs: Vec<f32> = (0..2000)
            .map(|_| rng.random_range(-1e3f32..1e3) * 10f32.powi(rng.random_range(-30..30)))
            .collect();
        xs.extend([
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
        ]);
        for a in &xs {
            for b in xs.iter().take(200) {
                // Same order as the floats, equal keys exactly for equal floats (-0 == +0).
                assert_eq!(order_key(*a).cmp(&order_key(*b)), a.partial_cmp(b).unwrap());
            }
        }
    }
}
