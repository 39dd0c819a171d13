//! The settings of a [`crate::Renderer`] and of each frame's overlays.

use tumble::gpu::GpuContext;

use crate::{Palette, RenderError};

/// Size and quality of the pictures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderConfig {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Samples per pixel: 1 (no antialiasing) or 4.
    pub samples: u32,
    /// Side of the square shadow map, texels; 0 draws no shadows.
    pub shadow_map_size: u32,
    /// Colours.
    pub palette: Palette,
}

impl Default for RenderConfig {
    /// 640 x 480, 4 samples, a 1024-texel shadow map, the default palette.
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            samples: 4,
            shadow_map_size: 1024,
            palette: Palette::DEFAULT,
        }
    }
}

impl RenderConfig {
    pub(crate) fn validate(&self, ctx: &GpuContext) -> Result<(), RenderError> {
        let max = ctx.limits().max_texture_dimension_2d;
        let bad = |field, value: String| Err(RenderError::InvalidConfig { field, value });
        if self.width == 0 || self.height == 0 || self.width > max || self.height > max {
            return bad(
                "width x height",
                format!("{} x {} (1 to {max} each)", self.width, self.height),
            );
        }
        if self.samples != 1 && self.samples != 4 {
            return bad("samples", format!("{} (1 or 4)", self.samples));
        }
        if self.shadow_map_size > max {
            return bad(
                "shadow_map_size",
                format!("{} (0 to {max})", self.shadow_map_size),
            );
        }
        Ok(())
    }
}

/// What to draw over the boxes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlay {
    /// A dot at each contact point of the last step (speculative ones included).
    pub contacts: bool,
    /// A line from each contact point along its manifold's normal.
    pub normals: bool,
    /// Radius of the contact dots, pixels.
    pub dot_radius: f32,
    /// Length of the normal lines, m.
    pub normal_length: f32,
}

impl Overlay {
    /// Nothing over the boxes.
    pub const NONE: Overlay = Overlay {
        contacts: false,
        normals: false,
        dot_radius: 3.0,
        normal_length: 0.25,
    };

    /// Contact dots, 3 pixels in radius.
    pub const CONTACTS: Overlay = Overlay {
        contacts: true,
        ..Overlay::NONE
    };
}

impl Default for Overlay {
    fn default() -> Self {
        Self::NONE
    }
}
