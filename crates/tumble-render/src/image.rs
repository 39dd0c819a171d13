//! A rendered picture: RGBA, 8 bits per channel, rows from the top, and its PNG form.

use std::io::Write;
use std::path::Path;

use crate::RenderError;

/// An RGBA picture, 8 bits per channel, row by row from the top left.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// `width * height * 4` bytes: R, G, B, A of each pixel.
    pub pixels: Vec<u8>,
}

impl Image {
    /// The pixel at column `x`, row `y` (from the top). Panics outside the picture.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside the picture"
        );
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.pixels[i],
            self.pixels[i + 1],
            self.pixels[i + 2],
            self.pixels[i + 3],
        ]
    }

    /// Pixels whose channels differ from `other`'s by more than `tolerance` in any channel.
    /// Panics when the sizes differ.
    pub fn count_different(&self, other: &Image, tolerance: u8) -> usize {
        assert_eq!((self.width, self.height), (other.width, other.height));
        self.pixels
            .chunks_exact(4)
            .zip(other.pixels.chunks_exact(4))
            .filter(|(a, b)| a.iter().zip(*b).any(|(x, y)| x.abs_diff(*y) > tolerance))
            .count()
    }

    /// The picture as PNG, written to `out`.
    pub fn write_png_to(&self, out: impl Write) -> Result<(), RenderError> {
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(png_error)?;
        writer.write_image_data(&self.pixels).map_err(png_error)?;
        writer.finish().map_err(png_error)
    }

    /// The picture as a PNG file at `path`.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), RenderError> {
        let path = path.as_ref();
        let file = std::fs::File::create(path).map_err(|e| RenderError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        self.write_png_to(std::io::BufWriter::new(file))
    }
}

fn png_error(e: png::EncodingError) -> RenderError {
    RenderError::Encode(e.to_string())
}
