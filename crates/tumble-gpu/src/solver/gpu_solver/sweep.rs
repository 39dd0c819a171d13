//! How the wide path's per-color dispatches name their color to `solve_color`: a bind group
//! per color over a `ColorPass` uniform, or one bind group per pass and the `ColorPass` as
//! immediate data (`solve_color_immediate`), where the device has it. The kernels and their
//! inputs are the same either way, so are the bits; the immediate form binds once per pass
//! kind, so wgpu skips every other bind call of a sweep.

use crate::kernel::Kernel;
use crate::layout::DispatchArgs;

use super::super::constants::{COLOR_SLOTS, OVERFLOW_COLOR};
use super::super::layout::ColorPass;

/// One pass kind's bind groups.
#[derive(Debug)]
pub(super) enum PassGroups {
    /// `[tail * COLOR_SLOTS + color]`: one group per color, then one per tail start, each
    /// over its own `ColorPass` uniform (`GpuSolver::pass_colors`, same order).
    Uniform(Vec<wgpu::BindGroup>),
    /// One group for every color; the `ColorPass` goes in as immediate data.
    Immediate(wgpu::BindGroup),
}

/// The `ColorPass` of `color` (`tail`: every constraint from `color` on, in one thread).
pub(super) fn color_pass(color: u32, tail: bool) -> ColorPass {
    ColorPass {
        color,
        tail: u32::from(tail),
        ..Default::default()
    }
}

/// Every `ColorPass` a pass dispatches with, in [`PassGroups::Uniform`]'s order.
pub(super) fn all_color_passes() -> impl Iterator<Item = ColorPass> {
    [false, true]
        .into_iter()
        .flat_map(|tail| (0..COLOR_SLOTS).map(move |color| color_pass(color, tail)))
}

impl PassGroups {
    /// Makes `kernel` and this pass's group for `pass_color` current on `pass` (wgpu drops
    /// the pipeline and group calls that change nothing).
    fn select(&self, pass: &mut wgpu::ComputePass<'_>, kernel: &Kernel, pass_color: ColorPass) {
        match self {
            PassGroups::Uniform(groups) => {
                let slot = pass_color.tail * COLOR_SLOTS + pass_color.color;
                kernel.set(pass, &groups[slot as usize]);
            }
            PassGroups::Immediate(group) => {
                kernel.set(pass, group);
                pass.set_immediates(0, bytemuck::bytes_of(&pass_color));
            }
        }
    }

    /// One pass over every color: the first `colors` one dispatch each, sized on the GPU by
    /// `color_plan` (`args`, one `DispatchArgs` per color), then the tail (the remaining
    /// colors and the overflow set) in one thread.
    pub(super) fn sweep(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        kernel: &Kernel,
        args: &wgpu::Buffer,
        colors: u32,
    ) {
        let stride = std::mem::size_of::<DispatchArgs>() as u64;
        for color in 0..colors {
            self.select(pass, kernel, color_pass(color, false));
            pass.dispatch_workgroups_indirect(args, u64::from(color) * stride);
        }
        self.select(pass, kernel, color_pass(colors, true));
        pass.dispatch_workgroups(1, 1, 1);
    }

    /// The overflow set alone, in one thread (after the per-body warm start).
    pub(super) fn overflow(&self, pass: &mut wgpu::ComputePass<'_>, kernel: &Kernel) {
        self.select(pass, kernel, color_pass(OVERFLOW_COLOR, false));
        pass.dispatch_workgroups(1, 1, 1);
    }
}
