//! Offscreen pictures of Tumble worlds with wgpu.
//!
//! [`Renderer::render`] draws every box of a [`tumble::World`] as one instance of a unit cube,
//! reading its pose (position and quaternion) and half extents from storage buffers laid out
//! as the GPU step's (`GpuPose`, `GpuShape`):
//!
//! - on `Backend::Gpu` those are the world's own buffers ([`World::gpu_draw_buffers`]), bound
//!   as they are: nothing about the bodies is read back, and only each body's kind (4 bytes,
//!   from the host, when the bodies change) is uploaded;
//! - on the other backends the state lives on the host, and each frame uploads every pose
//!   and shape once into the renderer's buffers, in the same layout.
//!
//! Lambert and ambient light from a fixed direction, a shadow map from that light, and dark
//! edge lines make depth readable; fixed, dynamic, kinematic and sleeping bodies have the
//! colours of [`Palette`]. The optional [`Overlay`] draws a dot at each contact point, a
//! line along each manifold normal, each body's AABB outline, a line between the bodies of
//! each candidate pair of the broad phase (touching or not) and dots filled with their
//! manifold's graph colour ([`graph_colour`]), from the manifold and colour buffers on
//! `Backend::Gpu` (one manifold slot per candidate pair) and from [`World::contacts`],
//! [`World::broad_phase_pairs`] and [`World::contact_colors`] elsewhere. The picture comes back as an [`Image`], written as PNG with
//! [`Image::write_png`].
//! [`Renderer::set_status_line`] adds a line of text on a dark band in the picture's top left
//! corner ([`status`]); there is none by default.
//!
//! A picture of a cube at rest on the origin, seen from above and to the side:
//!
//! ```
//! use tumble::prelude::*;
//! use tumble_render::{Camera, Overlay, Palette, RenderConfig, Renderer};
//!
//! let mut world = World::new(WorldConfig::default())?;
//! world.add_body(BodyDesc::fixed().cuboid(Vec3::new(0.5, 0.5, 0.5)))?;
//! let config = RenderConfig { width: 64, height: 48, samples: 1, shadow_map_size: 0, ..Default::default() };
//! let mut renderer = match Renderer::for_world(&world, config) {
//!     Ok(renderer) => renderer,
//!     // Drawing needs a GPU adapter; CI has one (a software driver) and sets the variable.
//!     Err(e) if std::env::var_os("TUMBLE_REQUIRE_GPU").is_none() => {
//!         println!("skipped: {e}");
//!         return Ok(());
//!     }
//!     Err(e) => panic!("no renderer: {e}"),
//! };
//! let camera = Camera::looking_at(Point3::new(3.0, 2.0, 4.0), Point3::origin());
//! let image = renderer.render(&world, &camera, &Overlay::NONE)?;
//! assert_eq!((image.width, image.height), (64, 48));
//! // The camera looks at the cube's centre, so the middle pixel is the cube, not the sky; the
//! // top-left corner, far above the cube's silhouette, is background.
//! let background = Palette::rgba8(Palette::DEFAULT.background);
//! assert_ne!(image.pixel(32, 24), background);
//! assert_eq!(image.pixel(0, 0), background);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! [`World::gpu_draw_buffers`]: tumble::World::gpu_draw_buffers
//! [`World::contacts`]: tumble::World::contacts
//! [`World::broad_phase_pairs`]: tumble::World::broad_phase_pairs
//! [`World::contact_colors`]: tumble::World::contact_colors
#![warn(missing_docs)]

mod bodies;
pub mod camera;
mod config;
mod image;
mod pipelines;
mod renderer;
pub mod status;

pub use camera::Camera;
pub use image::Image;
pub use renderer::{Overlay, RenderConfig, Renderer, Source};

/// Colours of the picture, linear 0..1 values written to the 8-bit picture as they are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Palette {
    /// Where no box is.
    pub background: [f32; 3],
    /// Fixed bodies.
    pub fixed: [f32; 3],
    /// Dynamic bodies, awake.
    pub dynamic: [f32; 3],
    /// Kinematic bodies.
    pub kinematic: [f32; 3],
    /// Dynamic bodies asleep.
    pub sleeping: [f32; 3],
    /// Contact point dots (outlined in near black).
    pub contact: [f32; 3],
    /// AABB outlines.
    pub aabb: [f32; 3],
    /// Lines between the bodies of a pair.
    pub pair: [f32; 3],
}

impl Palette {
    /// The default colours: fixed grey, dynamic orange, kinematic blue, sleeping a dimmed
    /// brown, magenta contact dots, teal AABBs, violet pair lines, on a pale blue-grey
    /// background.
    pub const DEFAULT: Palette = Palette {
        background: [0.90, 0.92, 0.95],
        fixed: [0.56, 0.57, 0.60],
        dynamic: [0.96, 0.55, 0.16],
        kinematic: [0.22, 0.50, 0.96],
        sleeping: [0.62, 0.50, 0.40],
        contact: [0.95, 0.05, 0.75],
        aabb: [0.05, 0.55, 0.45],
        pair: [0.35, 0.20, 0.85],
    };

    /// `colour` as the 8-bit RGBA of the picture (opaque).
    pub fn rgba8(colour: [f32; 3]) -> [u8; 4] {
        let c = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        [c(colour[0]), c(colour[1]), c(colour[2]), 255]
    }

    /// The shader's override constants for these colours.
    pub(crate) fn constants(&self) -> Vec<(&'static str, f64)> {
        const NAMES: [[&str; 3]; 7] = [
            ["fixed_r", "fixed_g", "fixed_b"],
            ["dynamic_r", "dynamic_g", "dynamic_b"],
            ["kinematic_r", "kinematic_g", "kinematic_b"],
            ["sleeping_r", "sleeping_g", "sleeping_b"],
            ["dot_r", "dot_g", "dot_b"],
            ["aabb_r", "aabb_g", "aabb_b"],
            ["pair_r", "pair_g", "pair_b"],
        ];
        let colours = [
            self.fixed,
            self.dynamic,
            self.kinematic,
            self.sleeping,
            self.contact,
            self.aabb,
            self.pair,
        ];
        NAMES
            .iter()
            .zip(colours)
            .flat_map(|(names, c)| names.iter().copied().zip(c.map(f64::from)))
            .collect()
    }
}

/// Slots of the graph colour table: the solver's graph colours, then the overflow set.
pub const GRAPH_COLOUR_SLOTS: usize = tumble::solver::GRAPH_COLOR_COUNT + 1;

/// The fill of the contact dots of a manifold of graph colour `color` ([`Overlay::colors`]):
/// hues a golden angle apart, so that neighbouring colours differ most, at one saturation
/// and value; white for [`tumble::solver::OVERFLOW_COLOR`]. `None` past the overflow set.
pub fn graph_colour(color: u32) -> Option<[f32; 3]> {
    let c = color as usize;
    if c + 1 == GRAPH_COLOUR_SLOTS {
        return Some([1.0; 3]);
    }
    if c >= GRAPH_COLOUR_SLOTS {
        return None;
    }
    let hue = (c as f32 * 0.381_966).fract() * 6.0;
    let (s, v) = (0.8, 0.92);
    let x = 1.0 - (hue % 2.0 - 1.0).abs();
    let [r, g, b] = match hue as u32 {
        0 => [1.0, x, 0.0],
        1 => [x, 1.0, 0.0],
        2 => [0.0, 1.0, x],
        3 => [0.0, x, 1.0],
        4 => [x, 0.0, 1.0],
        _ => [1.0, 0.0, x],
    };
    Some([r, g, b].map(|k| v * (1.0 - s + s * k)))
}

impl Default for Palette {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why a picture could not be made.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RenderError {
    /// No device, or the device failed.
    #[error("GPU: {0}")]
    Gpu(String),
    /// A setting out of range.
    #[error("invalid render setting {field}: {value}")]
    InvalidConfig {
        /// The setting.
        field: &'static str,
        /// Its value and what it should be.
        value: String,
    },
    /// Reading the world failed.
    #[error("reading the world: {0}")]
    World(String),
    /// The PNG encoder failed.
    #[error("encoding the picture: {0}")]
    Encode(String),
    /// A file could not be written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The error.
        message: String,
    },
}

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

#[cfg(test)]
mod tests {
    #[test]
    fn graph_colours_are_distinct_and_the_overflow_set_is_white() {
        let colours: Vec<[u8; 4]> = (0..super::GRAPH_COLOUR_SLOTS as u32)
            .map(|c| super::Palette::rgba8(super::graph_colour(c).unwrap()))
            .collect();
        for (i, a) in colours.iter().enumerate() {
            for b in &colours[i + 1..] {
                // Far enough apart to tell in a picture: more than 3 of 255 in some channel.
                assert!(
                    a.iter().zip(b).any(|(x, y)| x.abs_diff(*y) > 3),
                    "{a:?} {b:?}"
                );
            }
        }
        assert_eq!(colours.last(), Some(&[255; 4]));
        assert!(super::graph_colour(super::GRAPH_COLOUR_SLOTS as u32).is_none());
    }
}
