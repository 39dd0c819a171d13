//! tumble-render's pictures checked pixel by pixel: a floor and three boxes at known poses,
//! drawn from the host (`Backend::Cpu`) and from the GPU world's own buffers
//! (`Backend::Gpu`), checked where the host's projection of known points says they land.
//!
//! Needs a GPU (or lavapipe): without one the tests print "skipped: no GPU adapter" and pass,
//! unless `TUMBLE_REQUIRE_GPU=1`. Each picture is 240 x 160: a few milliseconds on lavapipe.

use tumble::gpu::GpuContext;
use tumble::prelude::*;
use tumble_render::{Camera, Image, Overlay, Palette, RenderConfig, Renderer, Source};

const WIDTH: u32 = 240;
const HEIGHT: u32 = 160;

/// An empty world without gravity on `backend`, and the 6 m x 1 m x 6 m fixed floor (top at
/// y = 0) every test puts in it.
fn zero_gravity_world(backend: Backend) -> (World, BodyDesc) {
    let world = World::new(WorldConfig {
        gravity: Vec3::zeros(),
        backend,
        ..Default::default()
    })
    .expect("world");
    let floor = BodyDesc::fixed()
        .cuboid(Vec3::new(3.0, 0.5, 3.0))
        .translation(0.0, -0.5, 0.0);
    (world, floor)
}

/// The world of every test: a fixed floor (top at y = 0), a dynamic cube resting on it at
/// the origin, a dynamic box turned 30 degrees about y, and a kinematic cube, all at rest
/// on the floor and without gravity, so a step leaves the poses where they are and finds
/// the floor contacts.
fn world(backend: Backend) -> (World, [BodyHandle; 4]) {
    let (mut world, floor) = zero_gravity_world(backend);
    let cube = BodyDesc::dynamic()
        .cuboid(Vec3::repeat(0.5))
        .translation(0.0, 0.5, 0.0);
    let mut turned = Pose::translation(-1.6, 0.4, 1.0);
    turned.rotation = Rot::from_axis_angle(&Vec3::y_axis(), 30f32.to_radians());
    let slab = BodyDesc::dynamic()
        .cuboid(Vec3::new(0.6, 0.4, 0.3))
        .pose(turned);
    let kinematic = BodyDesc::kinematic()
        .cuboid(Vec3::repeat(0.4))
        .translation(1.6, 0.4, -1.4);
    let handles = [floor, cube, slab, kinematic].map(|d| world.add_body(d).expect("body"));
    world.step().expect("step");
    (world, handles)
}

fn camera() -> Camera {
    Camera::looking_at(Point3::new(4.0, 4.0, 6.0), Point3::new(0.0, 0.3, 0.0))
}

fn config() -> RenderConfig {
    RenderConfig {
        width: WIDTH,
        height: HEIGHT,
        shadow_map_size: 512,
        ..Default::default()
    }
}

/// The pixel `point` projects into.
fn pixel_at(image: &Image, point: Point3) -> [u8; 4] {
    let [x, y, _] = camera().project(point, WIDTH, HEIGHT).expect("in front");
    assert!(
        (0.0..WIDTH as f32).contains(&x) && (0.0..HEIGHT as f32).contains(&y),
        "{point} projects outside the picture"
    );
    image.pixel(x as u32, y as u32)
}

/// Whether `px` is `base` lit or shaded: `base` times one factor within the light's range,
/// channel by channel within 6 of 255. The factor runs from 0.46 (ambient, in shadow, on a
/// face looking up) to 1.04 (full light); 0.2..1.1 leaves room for the edge lines' darkening
/// and excludes the background, which is 1.6 times the fixed grey.
fn tinted(px: [u8; 4], base: [f32; 3]) -> bool {
    let p = [px[0], px[1], px[2]].map(|c| f32::from(c) / 255.0);
    let k = (0..3).map(|i| p[i] * base[i]).sum::<f32>()
        / (0..3).map(|i| base[i] * base[i]).sum::<f32>();
    (0.2..1.1).contains(&k) && (0..3).all(|i| (p[i] - k * base[i]).abs() <= 6.0 / 255.0)
}

/// Within 3 of 255 per channel: a flat colour through 8-bit rounding.
fn near(px: [u8; 4], colour: [f32; 3]) -> bool {
    let want = Palette::rgba8(colour);
    (0..3).all(|i| px[i].abs_diff(want[i]) <= 3)
}

fn top_centre(world: &World, h: BodyHandle) -> Point3 {
    let pose = world.pose(h).unwrap();
    let half = world.half_extents(h).unwrap();
    Point3::from(pose.translation.vector + Vec3::new(0.0, half.y, 0.0))
}

/// The checks every picture of the world passes, whichever backend drew it.
fn check_picture(image: &Image, world: &World, [floor, cube, slab, kinematic]: [BodyHandle; 4]) {
    let palette = Palette::DEFAULT;
    // The top left corner looks over the floor's far edge, at the sky.
    assert_eq!(image.pixel(0, 0), Palette::rgba8(palette.background));
    assert_eq!(
        image.pixel(WIDTH - 1, 0),
        Palette::rgba8(palette.background)
    );
    let cube_px = pixel_at(image, top_centre(world, cube));
    assert!(tinted(cube_px, palette.dynamic), "cube top {cube_px:?}");
    let slab_px = pixel_at(image, top_centre(world, slab));
    assert!(tinted(slab_px, palette.dynamic), "slab top {slab_px:?}");
    let kin_px = pixel_at(image, top_centre(world, kinematic));
    assert!(
        tinted(kin_px, palette.kinematic),
        "kinematic top {kin_px:?}"
    );
    // Floor points away from the boxes, in light and in the cube's shadow alike.
    let _ = floor;
    for p in [
        Point3::new(2.0, 0.0, 2.0),
        Point3::new(-2.2, 0.0, -2.2),
        Point3::new(0.9, 0.0, 1.5),
    ] {
        let px = pixel_at(image, p);
        assert!(tinted(px, palette.fixed), "floor at {p}: {px:?}");
    }
}

fn check_contact_dots(image: &Image, world: &World, cube: BodyHandle) {
    let reports = world.contacts();
    let points: Vec<Point3> = reports
        .iter()
        .filter(|r| r.body_a == cube || r.body_b == cube)
        .flat_map(|r| r.points.iter().map(|p| p.position))
        .collect();
    assert!(
        points.len() >= 4,
        "the cube rests on the floor on 4 points: {points:?}"
    );
    for p in points {
        let px = pixel_at(image, p);
        assert!(
            near(px, Palette::DEFAULT.contact),
            "contact dot at {p}: {px:?}"
        );
    }
}

#[test]
fn cpu_world_picture_shows_each_box_in_its_colour_and_the_contact_dots() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let (world, handles) = world(Backend::Cpu);
    let mut renderer = Renderer::new(&ctx, config()).expect("renderer");
    let image = renderer
        .render(&world, &camera(), &Overlay::CONTACTS)
        .expect("render");
    assert_eq!(renderer.last_source(), Some(Source::Uploaded));
    check_picture(&image, &world, handles);
    check_contact_dots(&image, &world, handles[1]);
    // Without the overlay the dots' pixels show the boxes and floor again.
    let plain = renderer
        .render(&world, &camera(), &Overlay::NONE)
        .expect("render");
    check_picture(&plain, &world, handles);
    assert!(plain.count_different(&image, 24) > 0);
}

/// The GPU world is drawn from its own buffers with no byte read back, and its picture is
/// the CPU world's within a few pixels.
///
/// Threshold: at most 0.5% of the pixels (192 of 38,400) differ by more than 24 of 255 in a
/// channel. The two worlds hold the same poses up to the GPU step's round-off (no gravity,
/// resting contacts), so only antialiased edge pixels may change; a box drawn with a wrong
/// pose, half extent or colour changes hundreds of pixels, a missing box thousands.
#[test]
fn gpu_world_is_drawn_from_its_buffers_like_the_cpu_world() {
    if GpuContext::for_tests().is_none() {
        return;
    }
    let (gpu_world, _) = world(Backend::Gpu);
    let ctx = gpu_world.gpu_context().expect("a GPU world has a device");
    let mut renderer = Renderer::new(&ctx, config()).expect("renderer");
    let read_before = gpu_world.readback_bytes();
    let gpu_image = renderer
        .render(&gpu_world, &camera(), &Overlay::NONE)
        .expect("render");
    let gpu_dots = renderer
        .render(&gpu_world, &camera(), &Overlay::CONTACTS)
        .expect("render");
    assert_eq!(renderer.last_source(), Some(Source::WorldBuffers));
    assert_eq!(
        gpu_world.readback_bytes(),
        read_before,
        "rendering read nothing back"
    );

    let (cpu_world, cpu_handles) = world(Backend::Cpu);
    let cpu_image = renderer
        .render(&cpu_world, &camera(), &Overlay::NONE)
        .expect("render");
    assert_eq!(renderer.last_source(), Some(Source::Uploaded));
    let differing = gpu_image.count_different(&cpu_image, 24);
    let allowed = (WIDTH * HEIGHT / 200) as usize;
    assert!(
        differing <= allowed,
        "{differing} pixels differ (at most {allowed})"
    );

    check_picture(&gpu_image, &cpu_world, cpu_handles);
    // The GPU's manifolds, drawn from its buffers, have dots where the CPU's points are.
    check_contact_dots(&gpu_dots, &cpu_world, cpu_handles[1]);
}

/// One sample per pixel: the overlays' lines are one pixel wide, and a line that covers part
/// of a pixel's samples would resolve to a blend of its colour and what lies below.
fn overlay_config() -> RenderConfig {
    RenderConfig {
        samples: 1,
        ..config()
    }
}

/// Whether a pixel within one of where `point` projects has `colour`: a one-pixel line
/// passes within a pixel of each of its points, whichever way the rasterizer rounds.
fn drawn_near(image: &Image, camera: &Camera, point: Point3, colour: [f32; 3]) -> bool {
    let [x, y, _] = camera.project(point, WIDTH, HEIGHT).expect("in front");
    let (x, y) = (x as i64, y as i64);
    (-1..=1).any(|dy| {
        (-1..=1).any(|dx| {
            let (px, py) = (x + dx, y + dy);
            (0..WIDTH as i64).contains(&px)
                && (0..HEIGHT as i64).contains(&py)
                && near(image.pixel(px as u32, py as u32), colour)
        })
    })
}

fn count_near(image: &Image, colour: [f32; 3]) -> usize {
    (0..HEIGHT)
        .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
        .filter(|&(x, y)| near(image.pixel(x, y), colour))
        .count()
}

fn centre(world: &World, h: BodyHandle) -> Point3 {
    Point3::from(world.pose(h).unwrap().translation.vector)
}

/// The midpoints of the 12 edges of `h`'s world bounds.
fn aabb_edge_midpoints(world: &World, h: BodyHandle) -> Vec<Point3> {
    let pose = world.pose(h).unwrap();
    let r = pose.rotation.to_rotation_matrix();
    let half = r.matrix().abs() * world.half_extents(h).unwrap();
    let c = pose.translation.vector;
    let mut mids = Vec::new();
    for axis in 0..3 {
        for corner in 0..4 {
            let mut p = Vec3::zeros();
            p[(axis + 1) % 3] = if corner & 1 == 0 { -1.0 } else { 1.0 };
            p[(axis + 2) % 3] = if corner & 2 == 0 { -1.0 } else { 1.0 };
            mids.push(Point3::from(c + p.component_mul(&half)));
        }
    }
    mids
}

/// AABB outlines run through the midpoint of each edge of the cube's and the turned slab's
/// world bounds, and pair lines along the floor-cube and floor-slab segments, on the host
/// and the GPU world alike; the fixed floor and the kinematic cube, which no step pairs,
/// have no line between them. Neither colour appears in the picture without its overlay.
#[test]
fn aabb_and_pair_overlays_draw_where_the_bounds_and_pairs_project() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let palette = Palette::DEFAULT;
    let cam = camera();
    for backend in [Backend::Cpu, Backend::Gpu] {
        let (world, [floor, cube, slab, kinematic]) = world(backend);
        let ctx = world.gpu_context().unwrap_or_else(|| ctx.clone());
        let mut renderer = Renderer::new(&ctx, overlay_config()).expect("renderer");
        let plain = renderer.render(&world, &cam, &Overlay::NONE).unwrap();
        assert_eq!(count_near(&plain, palette.aabb), 0, "{backend:?}");
        assert_eq!(count_near(&plain, palette.pair), 0, "{backend:?}");

        let aabbs = Overlay {
            aabbs: true,
            ..Overlay::NONE
        };
        let image = renderer.render(&world, &cam, &aabbs).unwrap();
        for h in [cube, slab] {
            for mid in aabb_edge_midpoints(&world, h) {
                assert!(
                    drawn_near(&image, &cam, mid, palette.aabb),
                    "{backend:?}: no AABB line at {mid}"
                );
            }
        }
        // Four outlines of 12 edges, each tens of pixels long: hundreds of pixels at least.
        let outline = count_near(&image, palette.aabb);
        assert!(outline > 300, "{backend:?}: {outline} AABB pixels");

        let pairs = Overlay {
            pairs: true,
            ..Overlay::NONE
        };
        let image = renderer.render(&world, &cam, &pairs).unwrap();
        let along = |a: Point3, b: Point3, t: f32| a + (b - a) * t;
        for body in [cube, slab] {
            let (a, b) = (centre(&world, floor), centre(&world, body));
            for t in [0.25, 0.5, 0.75] {
                assert!(
                    drawn_near(&image, &cam, along(a, b, t), palette.pair),
                    "{backend:?}: no pair line at {t} of floor-{body:?}"
                );
            }
        }
        let unpaired = along(centre(&world, floor), centre(&world, kinematic), 0.5);
        assert!(
            !drawn_near(&image, &cam, unpaired, palette.pair),
            "{backend:?}: a line between the floor and the kinematic cube"
        );
    }
}

/// A cube on the floor and a smaller one on it: the two manifolds share the dynamic lower
/// cube, so the solver gives them different graph colours, and every dot of a manifold is
/// filled with its manifold's colour. On `Backend::Cpu` the colours are
/// `World::contact_colors`' (checked against `graph_colour`); on `Backend::Gpu` they come
/// from the solver's buffer, which the host does not read: the dots of each manifold share
/// one colour of the table, not the plain dot colour, and the two manifolds' differ.
#[test]
fn colour_overlay_fills_each_manifolds_dots_with_its_graph_colour() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let cam = Camera::looking_at(Point3::new(3.0, 3.0, 4.5), Point3::new(0.0, 0.6, 0.0));
    let colours = Overlay {
        colors: true,
        ..Overlay::NONE
    };
    let table: Vec<[f32; 3]> = (0..tumble_render::GRAPH_COLOUR_SLOTS as u32)
        .map(|c| tumble_render::graph_colour(c).unwrap())
        .collect();
    let stack = |backend| {
        let (mut world, floor) = zero_gravity_world(backend);
        let lower = BodyDesc::dynamic()
            .cuboid(Vec3::repeat(0.5))
            .translation(0.0, 0.5, 0.0);
        let upper = BodyDesc::dynamic()
            .cuboid(Vec3::repeat(0.3))
            .translation(0.0, 1.3, 0.0);
        for d in [floor, lower, upper] {
            world.add_body(d).expect("body");
        }
        world.step().expect("step");
        world
    };
    let cpu = stack(Backend::Cpu);
    let reports = cpu.contacts();
    assert_eq!(reports.len(), 2, "floor-lower and lower-upper");
    let cpu_colours = cpu.contact_colors();
    assert_eq!(cpu_colours.len(), 2);
    let mut renderer = Renderer::new(&ctx, overlay_config()).expect("renderer");
    let image = renderer.render(&cpu, &cam, &colours).unwrap();
    let [x, y] = [cpu_colours[0], cpu_colours[1]].map(|c| c.expect("a colored manifold"));
    assert_ne!(x, y, "the manifolds share the lower cube");
    for (report, c) in reports.iter().zip([x, y]) {
        let want = tumble_render::graph_colour(c).unwrap();
        for p in &report.points {
            let px = pixel_at_with(&image, &cam, p.position);
            assert!(
                near(px, want),
                "CPU dot at {}: {px:?}, colour {c}",
                p.position
            );
        }
    }

    let gpu = stack(Backend::Gpu);
    let gpu_ctx = gpu.gpu_context().expect("a GPU world has a device");
    let mut renderer = Renderer::new(&gpu_ctx, overlay_config()).expect("renderer");
    let image = renderer.render(&gpu, &cam, &colours).unwrap();
    assert_eq!(renderer.last_source(), Some(Source::WorldBuffers));
    // The GPU's points are the CPU's up to round-off: each lands in the same pixel.
    let manifold_colour = |report: &tumble::ContactReport| {
        let found: Vec<usize> = report
            .points
            .iter()
            .map(|p| {
                let px = pixel_at_with(&image, &cam, p.position);
                table.iter().position(|&t| near(px, t)).unwrap_or_else(|| {
                    panic!("GPU dot at {}: {px:?} in no graph colour", p.position)
                })
            })
            .collect();
        assert!(
            found.windows(2).all(|w| w[0] == w[1]),
            "one colour per manifold: {found:?}"
        );
        found[0]
    };
    let (a, b) = (manifold_colour(&reports[0]), manifold_colour(&reports[1]));
    assert_ne!(a, b, "the GPU's manifolds share the lower cube");
}

/// The pixel `point` projects into through `camera`.
fn pixel_at_with(image: &Image, camera: &Camera, point: Point3) -> [u8; 4] {
    let [x, y, _] = camera.project(point, WIDTH, HEIGHT).expect("in front");
    image.pixel(x as u32, y as u32)
}

/// The pair lines are the broad phase's candidate pairs, touching or not. Two cubes turned
/// 45 degrees about z, their centres 1.2 m apart along x and along y: their AABBs (0.707 m
/// half wide in x and y) overlap by 0.21 m on both axes, but their facing faces are 0.70 m
/// apart along the diagonal (1.2 * sqrt(2) - 1), far beyond the speculative margin at rest,
/// so the broad phase pairs them and the narrow phase finds no contact. Two more cubes
/// 4 m apart are not paired. No gravity, no floor: nothing moves. On every backend the
/// picture has a pair line along the near pair's centres, none between the far pair's.
#[test]
fn pair_overlay_draws_the_broad_phase_pairs_touching_or_not() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let palette = Palette::DEFAULT;
    let cam = Camera::looking_at(Point3::new(0.0, 1.0, 9.0), Point3::new(0.0, 1.0, 0.0));
    let turned = |x: f32, y: f32| {
        let mut pose = Pose::translation(x, y, 0.0);
        pose.rotation = Rot::from_axis_angle(&Vec3::z_axis(), 45f32.to_radians());
        BodyDesc::dynamic().cuboid(Vec3::repeat(0.5)).pose(pose)
    };
    let far = |x: f32| {
        BodyDesc::dynamic()
            .cuboid(Vec3::repeat(0.4))
            .translation(x, -1.5, 0.0)
    };
    let pairs = Overlay {
        pairs: true,
        ..Overlay::NONE
    };
    let mut host_renderer = Renderer::new(&ctx, overlay_config()).expect("renderer");
    for backend in [Backend::Cpu, Backend::Hybrid, Backend::Gpu] {
        let mut world = World::new(WorldConfig {
            gravity: Vec3::zeros(),
            backend,
            ..Default::default()
        })
        .expect("world");
        let [a, b, c, d] = [turned(-0.6, 0.4), turned(0.6, 1.6), far(-2.0), far(2.0)]
            .map(|desc| world.add_body(desc).expect("body"));
        world.step().expect("step");
        // Meaningful only if the near pair has no manifold: a line from the contacts would
        // not be drawn.
        assert!(
            world.contacts().is_empty(),
            "{backend:?}: {:?}",
            world.contacts()
        );
        if backend != Backend::Gpu {
            assert_eq!(world.broad_phase_pairs(), &[(a, b)], "{backend:?}");
        }
        // The host worlds share one renderer (building one compiles its pipelines); the GPU
        // world is drawn on its own device, from its buffers.
        let mut own = None;
        let renderer = match world.gpu_context() {
            Some(world_ctx) => {
                own.insert(Renderer::new(&world_ctx, overlay_config()).expect("renderer"))
            }
            None => &mut host_renderer,
        };
        let image = renderer.render(&world, &cam, &pairs).unwrap();
        let plain = renderer.render(&world, &cam, &Overlay::NONE).unwrap();
        assert_eq!(count_near(&plain, palette.pair), 0, "{backend:?}");
        let along = |p: Point3, q: Point3, t: f32| p + (q - p) * t;
        let (pa, pb) = (centre(&world, a), centre(&world, b));
        // 0.5 lies in the gap between the cubes, 0.25 and 0.75 over the cubes' faces.
        for t in [0.25, 0.5, 0.75] {
            assert!(
                drawn_near(&image, &cam, along(pa, pb, t), palette.pair),
                "{backend:?}: no pair line at {t} of the near pair"
            );
        }
        let (pc, pd) = (centre(&world, c), centre(&world, d));
        for t in [0.25, 0.5, 0.75] {
            assert!(
                !drawn_near(&image, &cam, along(pc, pd, t), palette.pair),
                "{backend:?}: a pair line at {t} between the far cubes"
            );
        }
        // One line 1.7 m long seen from 9 m: tens of pixels, not hundreds.
        let line = count_near(&image, palette.pair);
        assert!((20..200).contains(&line), "{backend:?}: {line} pair pixels");
    }
}
