//! Builders of the canonical scenes, one file per kind of scene.

pub mod common;
mod dominoes;
mod far;
mod high_speed;
mod mass_ratio;
mod overlap;
mod pool;
mod ramp;
mod spinning;
mod stacks;

pub use dominoes::dominoes;
pub use far::far_from_origin;
pub use high_speed::high_speed;
pub use mass_ratio::{HEAVY_DENSITY_RATIO, WIDE_RATIO, mass_ratio, wide_on_small};
pub use overlap::overlap_recovery;
pub use pool::pool;
pub use ramp::{friction_ramp, ramp_acceleration};
pub use spinning::spinning_box;
pub use stacks::{pyramid, pyramid_cube_count, stack, wall};
