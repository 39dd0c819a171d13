//! A stable LSD radix sort of `(key, value)` pairs of `u32` on the GPU, `RADIX_BITS` bits per
//! pass, with the item count read on the GPU from a `WorkList` (so it can sort a list whose
//! length only the GPU knows, dispatching indirectly).
//!
//! Each pass runs three kernels: `radix_histogram` (digit counts per tile), `radix_scan`
//! (digit-major exclusive scan: every tile's first slot per digit) and `radix_scatter`
//! (stable move to the sorted slots). Passes ping-pong between two copies of the key and
//! value arrays. Several sorts can be chained with keys and values swapping roles, which is
//! how pairs `(a, b)` are put in lexicographic order: sort by `b`, then stably by `a`.

use wgpu::util::DeviceExt;

use crate::kernel::{Kernel, KernelSpec};
use crate::layout::RadixPassParams;
use crate::shader::file;
use crate::{GpuContext, GpuError, RADIX, RADIX_BITS, WORKGROUP_SIZE};

// The histogram kernel has one thread store each bucket's count.
const _: () = assert!(RADIX <= WORKGROUP_SIZE);

/// Kernel: per-tile digit counts.
pub static RADIX_HISTOGRAM: KernelSpec = KernelSpec::new(file("radix_histogram.wgsl"));

/// Kernel: exclusive scan of the digit-major counts (single workgroup).
pub static RADIX_SCAN: KernelSpec = KernelSpec::new(file("radix_scan.wgsl"));

/// Kernel: stable scatter to the sorted slots.
pub static RADIX_SCATTER: KernelSpec = KernelSpec::new(file("radix_scatter.wgsl"));

/// One pass of a chain of sorts over two arrays, `first` and `second`, each double-buffered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RadixPass {
    /// Bit offset of the digit.
    pub shift: u32,
    /// True when `first` holds the keys (and `second` the values); false for the reverse.
    pub key_is_first: bool,
    /// Which copy (0 or 1) the pass reads; it writes the other.
    pub source: usize,
}

/// The passes of a chain of stable sorts, each given as `(key_is_first, key_bits)`, applied
/// in order (so the last sort is the primary order). Starts reading copy 0.
pub fn plan_passes(sorts: &[(bool, u32)]) -> Vec<RadixPass> {
    plan_digit_passes(sorts, RADIX_BITS)
}

/// [`plan_passes`] with `digit_bits` bits per pass.
fn plan_digit_passes(sorts: &[(bool, u32)], digit_bits: u32) -> Vec<RadixPass> {
    let mut passes = Vec::new();
    let mut source = 0;
    for &(key_is_first, bits) in sorts {
        for digit in 0..bits.div_ceil(digit_bits) {
            passes.push(RadixPass {
                shift: digit * digit_bits,
                key_is_first,
                source,
            });
            source = 1 - source;
        }
    }
    passes
}

/// The copy (0 or 1) holding the result after `passes`.
pub fn result_copy(passes: &[RadixPass]) -> usize {
    passes.len() % 2
}

/// Key bits needed to sort indices below `n`.
pub const fn index_bits(n: u32) -> u32 {
    let largest = n.saturating_sub(1);
    u32::BITS - if largest > 1 { largest } else { 1 }.leading_zeros()
}

/// Entries of the tile-count buffer for up to `capacity` items.
pub fn tile_count_len(capacity: u32) -> u64 {
    digit_tile_count_len(capacity, RADIX_BITS)
}

fn digit_tile_count_len(capacity: u32, digit_bits: u32) -> u64 {
    (1u64 << digit_bits) * u64::from(capacity.div_ceil(WORKGROUP_SIZE))
}

/// The buffers a chain of sorts works on.
pub struct RadixBuffers<'a> {
    /// `WorkList` with the item count and the tile dispatch size.
    pub work: &'a wgpu::Buffer,
    /// The first array, two copies.
    pub first: [&'a wgpu::Buffer; 2],
    /// The second array, two copies.
    pub second: [&'a wgpu::Buffer; 2],
    /// Scratch of [`tile_count_len`] `u32`s.
    pub tile_counts: &'a wgpu::Buffer,
}

/// Bind groups of a planned chain of passes over fixed buffers.
#[derive(Debug)]
pub struct RadixBindGroups {
    passes: Vec<(wgpu::BindGroup, wgpu::BindGroup)>,
    scan: wgpu::BindGroup,
}

/// The three kernels and one parameter block per digit position.
#[derive(Debug)]
pub struct RadixSort {
    digit_bits: u32,
    histogram: Kernel,
    scan: Kernel,
    scatter: Kernel,
    shift_params: Vec<wgpu::Buffer>,
}

impl RadixSort {
    /// Builds the kernels, [`RADIX_BITS`] bits per pass.
    pub fn new(ctx: &GpuContext) -> Result<Self, GpuError> {
        Self::with_digit_bits(ctx, RADIX_BITS)
    }

    /// Builds the kernels with `digit_bits` bits per pass (1 to 8: the histogram stores one
    /// bucket per thread). Wider digits take fewer passes over keys with few distinct values,
    /// such as colors, at a larger tile-count scan.
    pub fn with_digit_bits(ctx: &GpuContext, digit_bits: u32) -> Result<Self, GpuError> {
        if !(1..=8).contains(&digit_bits) || (1 << digit_bits) > WORKGROUP_SIZE {
            return Err(GpuError::InvalidInput {
                field: "radix digit_bits (1 to 8)".into(),
                value: digit_bits.to_string(),
            });
        }
        let overrides = [
            ("RADIX_BITS", f64::from(digit_bits)),
            ("RADIX", f64::from(1u32 << digit_bits)),
        ];
        let build = |spec: &'static crate::kernel::KernelSpec| {
            Kernel::specialized(ctx, spec, &spec.declared(&overrides)?)
        };
        let shift_params = (0..u32::BITS.div_ceil(digit_bits))
            .map(|d| {
                ctx.device
                    .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("radix pass params"),
                        contents: bytemuck::bytes_of(&RadixPassParams {
                            shift: d * digit_bits,
                            ..Default::default()
                        }),
                        usage: wgpu::BufferUsages::UNIFORM,
                    })
            })
            .collect();
        Ok(Self {
            digit_bits,
            histogram: build(&RADIX_HISTOGRAM)?,
            scan: build(&RADIX_SCAN)?,
            scatter: build(&RADIX_SCATTER)?,
            shift_params,
        })
    }

    /// [`plan_passes`] for this sort's digit width.
    pub fn plan(&self, sorts: &[(bool, u32)]) -> Vec<RadixPass> {
        plan_digit_passes(sorts, self.digit_bits)
    }

    /// [`tile_count_len`] for this sort's digit width.
    pub fn tile_count_len(&self, capacity: u32) -> u64 {
        digit_tile_count_len(capacity, self.digit_bits)
    }

    /// Bind groups for `passes` over `buffers`.
    pub fn bind(
        &self,
        ctx: &GpuContext,
        buffers: &RadixBuffers<'_>,
        passes: &[RadixPass],
    ) -> RadixBindGroups {
        let passes = passes
            .iter()
            .map(|p| {
                let (keys, values) = if p.key_is_first {
                    (buffers.first, buffers.second)
                } else {
                    (buffers.second, buffers.first)
                };
                let params = &self.shift_params[(p.shift / self.digit_bits) as usize];
                // The histogram's and the scatter's bindings, by name.
                let buffer = |name: &str| match name {
                    "pass_params" => params,
                    "work" => buffers.work,
                    "keys" | "keys_in" => keys[p.source],
                    "values_in" => values[p.source],
                    "tile_counts" | "tile_offsets" => buffers.tile_counts,
                    "keys_out" => keys[1 - p.source],
                    "values_out" => values[1 - p.source],
                    _ => unreachable!("no radix binding {name}"),
                };
                let histogram = self.histogram.bind_named(ctx, buffer);
                let scatter = self.scatter.bind_named(ctx, buffer);
                (histogram, scatter)
            })
            .collect();
        let scan = self.scan.bind_named(ctx, |name| match name {
            "work" => buffers.work,
            "tile_counts" => buffers.tile_counts,
            _ => unreachable!("no radix_scan binding {name}"),
        });
        RadixBindGroups { passes, scan }
    }

    /// Records every pass; tile dispatches read their size from `work` on the GPU.
    pub fn record(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &RadixBindGroups,
        work: &wgpu::Buffer,
    ) {
        for (histogram, scatter) in &groups.passes {
            self.histogram.dispatch_work(pass, histogram, work);
            self.scan.dispatch_workgroups(pass, &groups.scan, 1, 1);
            self.scatter.dispatch_work(pass, scatter, work);
        }
    }
}

/// The CPU twin: a stable sort of `(key, value)` by the low `bits` bits of the key, which is
/// what the passes of one sort compute.
pub fn radix_sort_cpu(keys: &[u32], values: &[u32], bits: u32) -> (Vec<u32>, Vec<u32>) {
    let digits_bits = bits.div_ceil(RADIX_BITS) * RADIX_BITS;
    let mask = if digits_bits >= u32::BITS {
        u32::MAX
    } else {
        (1 << digits_bits) - 1
    };
    let mut items: Vec<(u32, u32)> = keys.iter().copied().zip(values.iter().copied()).collect();
    items.sort_by_key(|&(k, _)| k & mask);
    items.into_iter().unzip()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_cover_the_key_bits_and_alternate_copies() {
        // 32-bit keys: 8 four-bit digits, ending back in copy 0.
        let body = plan_passes(&[(true, 32)]);
        assert_eq!(body.len(), 8);
        assert_eq!(result_copy(&body), 0);
        assert_eq!(body.last().unwrap().shift, 28);
        // Pairs of 20,000 bodies: indices below 2^15 need 15 bits, 4 digits per sort, and the
        // second sort reads where the first left off.
        assert_eq!(index_bits(20_000), 15);
        let pairs = plan_passes(&[(false, 15), (true, 15)]);
        assert_eq!(pairs.len(), 8);
        assert!(pairs[..4].iter().all(|p| !p.key_is_first));
        assert_eq!(pairs[4].source, 0);
        assert_eq!(pairs[3].source, 1);
        assert_eq!(index_bits(1), 1);
        assert_eq!(index_bits(2), 1);
        assert_eq!(index_bits(3), 2);
    }

    #[test]
    fn cpu_twin_sorts_only_on_the_low_digits_and_keeps_equal_keys_in_order() {
        let keys = [0x1_05, 0x2_03, 0x0_05, 0x3_01];
        let values = [0, 1, 2, 3];
        // 8 bits: the high nibble past bit 8 is ignored, ties keep input order.
        let (k, v) = radix_sort_cpu(&keys, &values, 8);
        assert_eq!(v, vec![3, 1, 0, 2]);
        assert_eq!(k, vec![0x3_01, 0x2_03, 0x1_05, 0x0_05]);
    }
}
