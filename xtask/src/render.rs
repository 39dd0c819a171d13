//! `cargo xtask render SCENE|FILE.json`: a scene stepped and drawn with tumble-render, one
//! PNG per frame and an animated GIF of them all.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use clap::Args;
use clap::builder::PossibleValuesParser;
use indicatif::{ProgressBar, ProgressStyle};
use tumble::scenes::Scene;
use tumble::{Backend, Point3, World, WorldConfig};
use tumble_render::{Camera, Image, Overlay, RenderConfig, Renderer};

use crate::scene_set::{file_stem, full_scenes, load_scene_files};

/// Arguments of `cargo xtask render`.
#[derive(Args)]
pub struct RenderArgs {
    /// A scene name of the validation set (e.g. pyramid_12) or a scene file (FILE.json).
    scene: String,
    /// Frames to draw; the scene steps between them.
    #[arg(long, default_value_t = 120)]
    frames: usize,
    /// Steps of the scene's time step between two frames.
    #[arg(long, default_value_t = 1)]
    steps_per_frame: usize,
    /// Output folder [default: target/render/SCENE in the workspace].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Where the step runs: cpu or gpu (gpu draws from the world's own buffers).
    #[arg(long, default_value = "cpu", value_parser = PossibleValuesParser::new(["cpu", "gpu"]))]
    backend: String,
    /// Overlays, comma-separated: contacts (a dot per contact point), normals (along each
    /// manifold normal), aabbs (box outlines), pairs (a line between the bodies of each
    /// pair), colors (contact dots in their manifold's graph colour).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        value_parser = PossibleValuesParser::new(Overlay::NAMES)
    )]
    overlay: Vec<String>,
    /// Picture size, WIDTHxHEIGHT.
    #[arg(long, default_value = "480x320", value_name = "WxH", value_parser = parse_size)]
    size: (u32, u32),
    /// The camera's eye and target, EX,EY,EZ:TX,TY,TZ in metres (e.g. 10,6,10:0,2,0)
    /// [default: framing the moving bodies of the first frame].
    #[arg(long, value_name = "EYE:TARGET", value_parser = parse_camera)]
    camera: Option<Camera>,
}

/// `X,Y,Z`, three finite numbers.
fn parse_point(text: &str) -> Result<Point3, String> {
    let numbers: Vec<&str> = text.split(',').collect();
    let [x, y, z] = numbers[..] else {
        return Err(format!("{text:?} has {} numbers, not 3", numbers.len()));
    };
    let number = |t: &str| match t.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{t:?} is not a finite number")),
    };
    Ok(Point3::new(number(x)?, number(y)?, number(z)?))
}

/// `EX,EY,EZ:TX,TY,TZ`: a camera at the eye looking at the target.
fn parse_camera(text: &str) -> Result<Camera, String> {
    let usage = "expected EX,EY,EZ:TX,TY,TZ, e.g. 10,6,10:0,2,0";
    let (eye, target) = text
        .split_once(':')
        .ok_or_else(|| format!("no ':' between eye and target; {usage}"))?;
    let eye = parse_point(eye).map_err(|e| format!("eye {e}; {usage}"))?;
    let target = parse_point(target).map_err(|e| format!("target {e}; {usage}"))?;
    if (eye - target).norm() < 1e-3 {
        return Err("the eye is at the target: it looks nowhere".into());
    }
    Ok(Camera::looking_at(eye, target))
}

/// The scene named `arg` in the validation set, or read from the file `arg`.
fn resolve_scene(arg: &str) -> Result<Scene, String> {
    if arg.ends_with(".json") || Path::new(arg).is_file() {
        return load_scene_files(&[arg])?
            .pop()
            .ok_or_else(|| format!("{arg}: no scene"));
    }
    let scenes = full_scenes();
    let names: Vec<String> = scenes.iter().map(|s| s.name.clone()).collect();
    scenes
        .into_iter()
        .find(|s| s.name == arg)
        .ok_or_else(|| format!("no scene named {arg}; the scenes: {}", names.join(", ")))
}

/// `WIDTHxHEIGHT`, each 1 to 65535 (the GIF's limit).
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || "expected WIDTHxHEIGHT, each 1 to 65535, e.g. 480x320".to_string();
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if w == 0 || h == 0 || w > u32::from(u16::MAX) || h > u32::from(u16::MAX) {
        return Err(bad());
    }
    Ok((w, h))
}

fn parse_backend(name: &str) -> Result<Backend, String> {
    match name {
        "cpu" => Ok(Backend::Cpu),
        "gpu" => Ok(Backend::Gpu),
        other => Err(format!("--backend {other}: expected cpu or gpu")),
    }
}

/// Writes the frames as an animated GIF, `delay` hundredths of a second each, looping.
fn write_gif(path: &Path, frames: &mut [Image], delay: u16) -> Result<(), String> {
    let failed = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let Some(first) = frames.first() else {
        return Ok(());
    };
    let (w, h) = (first.width as u16, first.height as u16);
    let file = File::create(path).map_err(|e| failed(&e))?;
    let mut encoder = gif::Encoder::new(BufWriter::new(file), w, h, &[]).map_err(|e| failed(&e))?;
    encoder
        .set_repeat(gif::Repeat::Infinite)
        .map_err(|e| failed(&e))?;
    for image in frames {
        // NeuQuant's speed 10: a good palette for flat-shaded boxes, fast enough.
        let mut frame = gif::Frame::from_rgba_speed(w, h, &mut image.pixels, 10);
        frame.delay = delay;
        encoder.write_frame(&frame).map_err(|e| failed(&e))?;
    }
    Ok(())
}

/// Runs the task: the frames `frame_0000.png`... and `animation.gif` in the output folder.
pub fn render(args: &RenderArgs, workspace: &Path) -> Result<bool, String> {
    let scene = resolve_scene(&args.scene)?;
    let (width, height) = args.size;
    let overlay = Overlay::from_names(&args.overlay).map_err(|e| e.to_string())?;
    let backend = parse_backend(&args.backend)?;
    let out = args.out.clone().unwrap_or_else(|| {
        workspace
            .join("target")
            .join("render")
            .join(file_stem(&scene.name))
    });
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let config = WorldConfig {
        backend,
        ..Default::default()
    };
    let (mut world, _) = World::from_scene(&scene, config).map_err(|e| e.to_string())?;
    let render_config = RenderConfig {
        width,
        height,
        ..Default::default()
    };
    let mut renderer = Renderer::for_world(&world, render_config).map_err(|e| e.to_string())?;
    let camera = args
        .camera
        .unwrap_or_else(|| Camera::frame_world(&world, renderer.aspect()));
    eprintln!(
        "{}: {} bodies, {} frames of {} step(s) on {:?}, drawn on {}",
        scene.name,
        world.body_count(),
        args.frames,
        args.steps_per_frame,
        backend,
        renderer.context().info.name
    );
    let bar = ProgressBar::new(args.frames as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames, {elapsed} ({eta} left)")
            .map_err(|e| e.to_string())?,
    );
    let mut frames = Vec::with_capacity(args.frames);
    for i in 0..args.frames {
        if i > 0 {
            for _ in 0..args.steps_per_frame {
                world.step().map_err(|e| e.to_string())?;
            }
        }
        let image = renderer
            .render(&world, &camera, &overlay)
            .map_err(|e| e.to_string())?;
        image
            .write_png(out.join(format!("frame_{i:04}.png")))
            .map_err(|e| e.to_string())?;
        frames.push(image);
        bar.inc(1);
    }
    bar.finish();
    let seconds = f64::from(scene.dt) * args.steps_per_frame as f64;
    let delay = (seconds * 100.0).round().clamp(1.0, f64::from(u16::MAX)) as u16;
    let gif = out.join("animation.gif");
    write_gif(&gif, &mut frames, delay)?;
    eprintln!("wrote {} frames and {}", frames.len(), gif.display());
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_cameras_and_scene_names_parse_or_name_their_error() {
        assert_eq!(parse_size("480x320"), Ok((480, 320)));
        assert!(parse_size("480").is_err() && parse_size("0x3").is_err());
        assert!(parse_size("70000x10").is_err());
        let cam = parse_camera("10,6,10:0,2,0").unwrap();
        assert_eq!(cam.eye, Point3::new(10.0, 6.0, 10.0));
        assert_eq!(cam.target, Point3::new(0.0, 2.0, 0.0));
        for (bad, says) in [
            ("10,6,10", "no ':'"),
            ("10,6:0,2,0", "eye"),
            ("10,6,10:0,x,0", "target"),
            ("1,1,1:1,1,1", "looks nowhere"),
            ("1,inf,1:0,0,0", "finite"),
        ] {
            let e = parse_camera(bad).unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
        assert_eq!(resolve_scene("pyramid_12").unwrap().name, "pyramid_12");
        assert!(
            resolve_scene("no_such_scene")
                .unwrap_err()
                .contains("pyramid_12")
        );
    }

    #[derive(clap::Parser)]
    struct Cli {
        #[command(flatten)]
        args: RenderArgs,
    }

    /// The command line as clap reads it: bad values are refused with the option's name.
    #[test]
    fn the_command_line_takes_camera_and_overlays_and_refuses_bad_values() {
        use clap::Parser;
        let cli = Cli::try_parse_from([
            "render",
            "pyramid_12",
            "--camera",
            "10,6,10:0,2,0",
            "--overlay",
            "contacts,aabbs,pairs,colors",
        ])
        .unwrap();
        let overlay = Overlay::from_names(&cli.args.overlay).unwrap();
        assert!(overlay.contacts && overlay.aabbs && overlay.pairs && overlay.colors);
        assert!(!overlay.normals);
        assert_eq!(cli.args.camera.unwrap().eye, Point3::new(10.0, 6.0, 10.0));
        // The error names the option and the value it refused.
        for (option, value, refused) in [
            ("--overlay", "contacts,dots", "'dots'"),
            ("--camera", "1,2,3", "'1,2,3'"),
            ("--size", "big", "'big'"),
            ("--backend", "tpu", "'tpu'"),
        ] {
            let e = Cli::try_parse_from(["render", "pyramid_12", option, value])
                .err()
                .unwrap_or_else(|| panic!("{option} {value} accepted"))
                .to_string();
            assert!(
                e.contains(option) && e.contains(refused),
                "{option} {value}: {e}"
            );
        }
    }
}
