//! The status line in a rendered picture: the glyphs of its first characters where they are
//! drawn, the dark band under them, and the scene unchanged outside the band.
//!
//! Needs a GPU (or lavapipe): without one the test prints "skipped" and passes, unless
//! `TUMBLE_REQUIRE_GPU=1`. One renderer and three 200 x 120 pictures: well under a second on
//! lavapipe.

use tumble::prelude::*;
use tumble_render::status::{CELL, GLYPH_SCALE, MARGIN, TEXT_COLOUR, band_over, band_size, glyph};
use tumble_render::{Camera, Image, Overlay, Palette, RenderConfig, Renderer};

const TEXT: &str = "Ab7 on Cpu";

fn pixel_index(image: &Image, x: u32, y: u32) -> usize {
    ((y * image.width + x) * 4) as usize
}

#[test]
fn the_status_line_draws_its_glyphs_on_a_dark_band_and_nothing_else() {
    let mut world = World::new(WorldConfig::default()).expect("world");
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(2.0, 0.5, 2.0))
                .translation(0.0, -0.5, 0.0),
        )
        .expect("floor");
    world
        .add_body(
            BodyDesc::dynamic()
                .cuboid(Vec3::repeat(0.5))
                .translation(0.0, 0.5, 0.0),
        )
        .expect("cube");
    // A fixed pillar behind, on the left, taller than the view: its top reaches the band.
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(0.3, 2.0, 0.3))
                .translation(-1.4, 2.0, -1.4),
        )
        .expect("pillar");
    let config = RenderConfig {
        width: 200,
        height: 120,
        samples: 1,
        shadow_map_size: 256,
        ..Default::default()
    };
    let mut renderer = match Renderer::for_world(&world, config) {
        Ok(renderer) => renderer,
        Err(e) if std::env::var_os("TUMBLE_REQUIRE_GPU").is_none() => {
            println!("skipped: {e}");
            return;
        }
        Err(e) => panic!("no renderer: {e}"),
    };
    // The pillar's top lies under the band: the band covers scene as well as sky.
    let camera = Camera::looking_at(Point3::new(1.8, 1.6, 2.6), Point3::new(0.0, 0.6, 0.0));
    assert_eq!(renderer.status_line(), None, "off by default");
    let off = renderer
        .render(&world, &camera, &Overlay::NONE)
        .expect("off");
    renderer
        .set_status_line(Some(TEXT.into()))
        .expect("the line fits 200 px");
    let on = renderer
        .render(&world, &camera, &Overlay::NONE)
        .expect("on");
    // A line that does not fit is refused and the one set stays.
    assert!(renderer.set_status_line(Some("x".repeat(13))).is_err());
    assert_eq!(renderer.status_line(), Some(TEXT));
    renderer.set_status_line(None).expect("none");
    let off_again = renderer
        .render(&world, &camera, &Overlay::NONE)
        .expect("off again");

    // Without the line, the top left corner is the scene as before: the sky colour at the
    // corner itself, and the picture is the same bits as the first one (one backend, one
    // renderer, the same world: rendering is deterministic).
    let background = Palette::rgba8(Palette::DEFAULT.background);
    assert_eq!(off.pixel(0, 0), background);
    assert_eq!(off_again, off);

    let (band_w, band_h) = band_size(TEXT);
    assert_eq!(
        (band_w, band_h),
        (10 * CELL + 2 * MARGIN, CELL + 2 * MARGIN)
    );
    // The band covers some scene (not only sky), so the checks below hold over both.
    let under_band_not_sky = (0..band_h)
        .flat_map(|y| (0..band_w).map(move |x| (x, y)))
        .filter(|&(x, y)| off.pixel(x, y) != background)
        .count();
    assert!(under_band_not_sky > 0, "the pillar should reach the band");

    // The line is composited on the host with integer arithmetic into the picture read back,
    // so every check is exact: outside the band the bits are the scene's, inside it each
    // pixel is either the text colour or the band over the scene's pixel.
    let mut outside = 0;
    for y in 0..on.height {
        for x in 0..on.width {
            if x >= band_w || y >= band_h {
                assert_eq!(
                    on.pixel(x, y),
                    off.pixel(x, y),
                    "({x}, {y}) outside the band"
                );
                outside += 1;
            }
        }
    }
    assert_eq!(outside, 200 * 120 - band_w * band_h);

    // The first three characters, cell by cell: a lit glyph bit is a GLYPH_SCALE square of
    // text colour, an unlit one a square of band over the scene.
    for (column, c) in TEXT.chars().take(3).enumerate() {
        let bits = glyph(c).expect("ASCII");
        let lit: u32 = bits.iter().map(|b| b.count_ones()).sum();
        // 'A', 'b' and '7' have strokes: the lit checks below are not vacuous.
        assert!(lit >= 10, "{c:?} has {lit} lit bits");
        let x0 = MARGIN + column as u32 * CELL;
        for (gy, byte) in bits.iter().enumerate() {
            for gx in 0..8u32 {
                for (dx, dy) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    assert_eq!(GLYPH_SCALE, 2);
                    let (x, y) = (x0 + gx * 2 + dx, MARGIN + gy as u32 * 2 + dy);
                    let want = if byte & (1 << gx) != 0 {
                        TEXT_COLOUR
                    } else {
                        band_over(off.pixel(x, y))
                    };
                    assert_eq!(on.pixel(x, y), want, "{c:?} bit ({gx}, {gy}) at ({x}, {y})");
                }
            }
        }
    }
    // The margin is band: the corner pixel is the sky dimmed, and dark enough (every
    // channel at most 75 of 255, against the text's 245) for the text to read.
    assert_eq!(on.pixel(0, 0), band_over(background));
    let i = pixel_index(&on, 0, 0);
    assert!(on.pixels[i..i + 3].iter().all(|&v| v <= 75));
}
