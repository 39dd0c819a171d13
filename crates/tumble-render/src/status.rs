//! The status line: printable ASCII in light 8 x 8 glyphs, drawn twice their size, on a dark
//! translucent band in the top left corner of a picture.
//!
//! The line is drawn on the host into the picture the renderer reads back
//! ([`Renderer::set_status_line`](crate::Renderer::set_status_line)), after the scene, so the
//! scene's pixels outside the band are the same with and without it. Every channel of the
//! band is at most `255 * (255 - BAND_OPACITY) / 255` (75) and the text's is 245, so the text
//! reads over any background. `'\n'` starts a new line of the band.

use crate::{Image, RenderError};

/// Each glyph pixel is drawn as a square of this side.
pub const GLYPH_SCALE: u32 = 2;
/// The side of a character's cell in the picture, pixels.
pub const CELL: u32 = 8 * GLYPH_SCALE;
/// Band pixels between the picture's corner (and the band's edges) and the text.
pub const MARGIN: u32 = 4;
/// The colour of the text's pixels.
pub const TEXT_COLOUR: [u8; 4] = [245, 245, 245, 255];
/// How much of the picture the black band covers, of 255.
pub const BAND_OPACITY: u32 = 180;

/// The 8 x 8 bitmap of `c`: one byte per row from the top, bit 0 the leftmost pixel.
/// `None` for characters other than printable ASCII (`' '..='~'`).
pub fn glyph(c: char) -> Option<[u8; 8]> {
    matches!(c, ' '..='~').then(|| font8x8::legacy::BASIC_LEGACY[c as usize])
}

/// The band's colour over a picture pixel `under`: black at [`BAND_OPACITY`], opaque.
pub fn band_over(under: [u8; 4]) -> [u8; 4] {
    let dim = |v: u8| ((u32::from(v) * (255 - BAND_OPACITY) + 127) / 255) as u8;
    [dim(under[0]), dim(under[1]), dim(under[2]), 255]
}

/// The band's width and height in pixels for `text`: its longest line and its line count
/// in cells, and the margins.
pub fn band_size(text: &str) -> (u32, u32) {
    let columns = text
        .split('\n')
        .map(|l| l.chars().count())
        .max()
        .unwrap_or(0) as u32;
    let rows = text.split('\n').count() as u32;
    (columns * CELL + 2 * MARGIN, rows * CELL + 2 * MARGIN)
}

/// Checks that `text` can be drawn into a `width` x `height` picture: not empty, printable
/// ASCII and `'\n'` only, and a band that fits.
pub fn validate(text: &str, width: u32, height: u32) -> Result<(), RenderError> {
    let invalid = |value: String| RenderError::InvalidConfig {
        field: "status_line",
        value,
    };
    if text.is_empty() {
        return Err(invalid("\"\" (empty: use None for no status line)".into()));
    }
    if let Some(c) = text.chars().find(|&c| c != '\n' && glyph(c).is_none()) {
        return Err(invalid(format!(
            "{text:?} has {c:?} (printable ASCII and '\\n' only)"
        )));
    }
    let (w, h) = band_size(text);
    if w > width || h > height {
        return Err(invalid(format!(
            "{text:?} needs a {w} x {h} band, the picture is {width} x {height} \
             ({} characters of {CELL} px a line fit)",
            width.saturating_sub(2 * MARGIN) / CELL
        )));
    }
    Ok(())
}

/// Draws `text` on its band into the top left corner of `image`. An `Err` (from
/// [`validate`]) leaves the picture unchanged.
pub fn draw(image: &mut Image, text: &str) -> Result<(), RenderError> {
    validate(text, image.width, image.height)?;
    let (band_w, band_h) = band_size(text);
    let width = image.width as usize;
    let at = |x: u32, y: u32| (y as usize * width + x as usize) * 4;
    for y in 0..band_h {
        for x in 0..band_w {
            let i = at(x, y);
            let under: [u8; 4] = image.pixels[i..i + 4].try_into().expect("4 bytes");
            image.pixels[i..i + 4].copy_from_slice(&band_over(under));
        }
    }
    for (row, line) in text.split('\n').enumerate() {
        for (column, c) in line.chars().enumerate() {
            let bits = glyph(c).expect("validated");
            let (x0, y0) = (MARGIN + column as u32 * CELL, MARGIN + row as u32 * CELL);
            for (gy, byte) in bits.iter().enumerate() {
                for gx in 0..8 {
                    if byte & (1 << gx) == 0 {
                        continue;
                    }
                    for (dx, dy) in
                        (0..GLYPH_SCALE).flat_map(|a| (0..GLYPH_SCALE).map(move |b| (a, b)))
                    {
                        let i = at(
                            x0 + gx * GLYPH_SCALE + dx,
                            y0 + gy as u32 * GLYPH_SCALE + dy,
                        );
                        image.pixels[i..i + 4].copy_from_slice(&TEXT_COLOUR);
                    }
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(width: u32, height: u32, v: u8) -> Image {
        Image {
            width,
            height,
            pixels: vec![v; (width * height * 4) as usize],
        }
    }

    #[test]
    fn bad_lines_are_refused_naming_the_field_and_leave_the_picture_unchanged() {
        let mut image = grey(100, 40, 200);
        let before = image.clone();
        // 6 cells of 16 px and two 4 px margins are 104 px, more than the 100 px width; 3 lines
        // are 56 px, more than the 40 px height.
        for text in ["", "caf\u{e9}", "tab\there", "123456", "a\nb\nc"] {
            let err = draw(&mut image, text).expect_err(text);
            match &err {
                RenderError::InvalidConfig { field, value } => {
                    assert_eq!(*field, "status_line");
                    assert!(
                        value.contains(&format!("{text:?}")) || text.is_empty(),
                        "{value}"
                    );
                }
                other => panic!("{other:?}"),
            }
            assert_eq!(image, before, "{text:?}");
        }
        // 5 cells (88 px) and one line (24 px) fit.
        draw(&mut image, "12345").expect("fits");
        assert_ne!(image, before);
    }

    #[test]
    fn the_band_is_dark_and_the_text_light_over_any_background() {
        // The brightest band pixel (over white) against the text: 170 of 255 apart in every
        // channel, so the text reads over any scene.
        let brightest = band_over([255; 4]);
        assert!(brightest[..3].iter().all(|&v| v <= 75), "{brightest:?}");
        assert!(TEXT_COLOUR[..3].iter().all(|&t| t - brightest[0] >= 170));
        assert_eq!(band_over([0, 0, 0, 255]), [0, 0, 0, 255]);
    }
}
