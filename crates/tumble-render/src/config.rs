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
    /// The outline of each body's axis-aligned bounding box (the box's world bounds, without
    /// the broad phase's speculative margin and sweep).
    pub aabbs: bool,
    /// A line between the centres of the two bodies of each candidate pair the broad phase
    /// produced in the last step, touching or not: on `Backend::Gpu` every manifold slot in
    /// use (one per candidate pair, read from the world's buffer), elsewhere
    /// [`tumble::World::broad_phase_pairs`].
    pub pairs: bool,
    /// Contact dots filled with their manifold's graph colour ([`crate::graph_colour`]),
    /// drawn with or without `contacts`: from the solver's colour buffer on `Backend::Gpu`,
    /// from [`tumble::World::contact_colors`] elsewhere. Manifolds without a colour keep the
    /// palette's contact colour.
    pub colors: bool,
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
        aabbs: false,
        pairs: false,
        colors: false,
        dot_radius: 3.0,
        normal_length: 0.25,
    };

    /// Contact dots, 3 pixels in radius.
    pub const CONTACTS: Overlay = Overlay {
        contacts: true,
        ..Overlay::NONE
    };

    /// The names [`Overlay::from_names`] takes, each the field it turns on.
    pub const NAMES: [&'static str; 5] = ["contacts", "normals", "aabbs", "pairs", "colors"];

    /// The overlay with each named part on (names of [`Overlay::NAMES`], empty ones
    /// ignored); errs naming the first unknown one.
    pub fn from_names<S: AsRef<str>>(names: &[S]) -> Result<Overlay, RenderError> {
        let mut overlay = Overlay::NONE;
        for name in names {
            let flag = match name.as_ref().trim() {
                "" => continue,
                "contacts" => &mut overlay.contacts,
                "normals" => &mut overlay.normals,
                "aabbs" => &mut overlay.aabbs,
                "pairs" => &mut overlay.pairs,
                "colors" => &mut overlay.colors,
                other => {
                    return Err(RenderError::InvalidConfig {
                        field: "overlay",
                        value: format!("{other} (one of {})", Overlay::NAMES.join(", ")),
                    });
                }
            };
            *flag = true;
        }
        Ok(overlay)
    }

    /// Whether a part that reads the manifolds is on.
    pub(crate) fn reads_manifolds(&self) -> bool {
        self.contacts || self.normals || self.pairs || self.colors
    }
}

impl Default for Overlay {
    fn default() -> Self {
        Self::NONE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlay_names_turn_on_their_field_and_unknown_names_are_refused() {
        let o = Overlay::from_names(&["aabbs", " pairs", "colors", ""]).unwrap();
        assert!(o.aabbs && o.pairs && o.colors && !o.contacts && !o.normals);
        let all = Overlay::from_names(&Overlay::NAMES).unwrap();
        assert!(all.contacts && all.normals && all.aabbs && all.pairs && all.colors);
        let e = Overlay::from_names(&["contacts", "dots"]).unwrap_err();
        assert!(
            e.to_string().contains("overlay") && e.to_string().contains("dots"),
            "{e}"
        );
    }
}
