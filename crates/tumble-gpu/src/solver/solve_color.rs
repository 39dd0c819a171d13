//! `solve_color`: one pass (warm start, solve, relax or restitution) over the constraints of
//! one graph color, one thread each, or over the overflow set in one thread. Its CPU twin is
//! tumble-solver's `sweep` of the same pass over the same color order.

use crate::kernel::KernelSpec;
use crate::shader::file;

use super::constants::{PASS_RELAX, PASS_RESTITUTION, PASS_SOLVE, PASS_WARM_START};

/// Kernel: specialized per pass with the `PASS` override; the color is a uniform, one bind
/// group per color (devices without immediate data).
pub static SOLVE_COLOR: KernelSpec = KernelSpec::new(file("solver/solve_color.wgsl"));

/// The same kernel with the color as immediate data, one bind group per pass (devices with
/// [`crate::GpuContext::has_immediates`]).
pub static SOLVE_COLOR_IMMEDIATE: KernelSpec =
    KernelSpec::new(file("solver/solve_color_immediate.wgsl"));

/// The per-color pass kernel a device runs: [`SOLVE_COLOR_IMMEDIATE`] where it has immediate
/// data, [`SOLVE_COLOR`] elsewhere.
pub fn solve_color_spec(immediates: bool) -> &'static KernelSpec {
    if immediates {
        &SOLVE_COLOR_IMMEDIATE
    } else {
        &SOLVE_COLOR
    }
}

/// The passes a sweep over the colors can make.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PassKind {
    /// Re-apply last substep's impulses.
    WarmStart,
    /// Biased solve.
    Solve,
    /// Unbiased solve.
    Relax,
    /// Restitution after the substeps.
    Restitution,
}

impl PassKind {
    /// Every pass, in the order of [`Self::index`].
    pub const ALL: [PassKind; 4] = [
        PassKind::WarmStart,
        PassKind::Solve,
        PassKind::Relax,
        PassKind::Restitution,
    ];

    /// The `PASS` override value.
    pub fn code(self) -> u32 {
        match self {
            PassKind::WarmStart => PASS_WARM_START,
            PassKind::Solve => PASS_SOLVE,
            PassKind::Relax => PASS_RELAX,
            PassKind::Restitution => PASS_RESTITUTION,
        }
    }

    /// Position in [`Self::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}
