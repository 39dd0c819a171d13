//! The default list of scenes for validation runs.

use crate::Scene;
use crate::builders::*;

/// Pool size in the canonical list: 512 cubes (8 x 8 x 8), big enough for a crowded pile,
/// small enough for a quick run.
pub const CANONICAL_POOL: usize = 512;
/// Offset of the far-from-origin column: 10 km, where f32 positions step by about 1 mm.
pub const CANONICAL_FAR_OFFSET: f32 = 10_000.0;

/// The canonical scenes, each small enough for a quick validation run.
pub fn canonical() -> Vec<Scene> {
    vec![
        stack(20),
        pyramid(12),
        wall(10, 10),
        pool(CANONICAL_POOL),
        mass_ratio(),
        wide_on_small(),
        // 30 degrees: tan = 0.577, so mu 0.3 slides and mu 0.7 sticks.
        friction_ramp(30.0, 0.3),
        friction_ramp(30.0, 0.7),
        dominoes(20),
        far_from_origin(CANONICAL_FAR_OFFSET),
        high_speed(),
        spinning_box(),
        overlap_recovery(),
    ]
}
