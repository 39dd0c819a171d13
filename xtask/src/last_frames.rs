//! The last frame of each scene's verdict run, drawn with tumble-render for the validation
//! report: the run's final poses set on a `Backend::Cpu` world of the scene, pictured on the
//! first adapter (any, lavapipe included).

use std::path::Path;

use tumble::scenes::Scene;
use tumble::{World, WorldConfig};
use tumble_render::{Camera, Overlay, RenderConfig, Renderer};

use crate::engine::BodyState;
use crate::scene_set::file_stem;

/// The report's folder for the frames.
pub const FRAMES_DIR: &str = "frames";

/// Picture size of a report frame: small enough for a table of scenes, large enough to read
/// a pile.
const SIZE: (u32, u32) = (360, 240);

/// What came of drawing the last frames.
#[derive(Clone, Debug, Default)]
pub struct LastFrames {
    /// `(scene name, path of its PNG relative to the report)` of each frame drawn.
    pub drawn: Vec<(String, String)>,
    /// Why some or all frames were not drawn (no adapter, a failed render), for the report.
    pub notes: Vec<String>,
    /// The adapter that drew them.
    pub adapter: Option<String>,
}

impl LastFrames {
    /// The report path of `scene`'s frame, when one was drawn.
    pub fn frame_of(&self, scene: &str) -> Option<&str> {
        self.drawn
            .iter()
            .find(|(name, _)| name == scene)
            .map(|(_, path)| path.as_str())
    }
}

/// Draws each scene's final states (`finals`: scene name and its bodies' states, in scene
/// order) into `dir/frames/STEM.png`. Never fails the validation: without an adapter, or
/// when a frame cannot be drawn or written, the reason goes into [`LastFrames::notes`].
pub fn draw_last_frames(
    dir: &Path,
    scenes: &[Scene],
    finals: &[(String, Vec<BodyState>)],
) -> LastFrames {
    let mut out = LastFrames::default();
    let frames = dir.join(FRAMES_DIR);
    if let Err(e) = std::fs::create_dir_all(&frames) {
        out.notes
            .push(format!("frames not drawn: {}: {e}", frames.display()));
        return out;
    }
    let config = RenderConfig {
        width: SIZE.0,
        height: SIZE.1,
        ..Default::default()
    };
    let mut renderer = match tumble::gpu::GpuContext::new() {
        Ok(ctx) => match Renderer::new(&ctx, config) {
            Ok(r) => r,
            Err(e) => {
                out.notes.push(format!("frames not drawn: {e}"));
                return out;
            }
        },
        Err(e) => {
            out.notes
                .push(format!("frames not drawn: no GPU adapter ({e})"));
            return out;
        }
    };
    out.adapter = Some(renderer.context().info.name.clone());
    for (name, states) in finals {
        let Some(scene) = scenes.iter().find(|s| &s.name == name) else {
            continue;
        };
        let file = format!("{}.png", file_stem(name));
        match draw_one(&mut renderer, scene, states, &frames.join(&file)) {
            Ok(()) => out
                .drawn
                .push((name.clone(), format!("{FRAMES_DIR}/{file}"))),
            Err(e) => out.notes.push(format!("{name}: frame not drawn: {e}")),
        }
    }
    out
}

/// One scene at `states`, framed on its moving bodies, written to `path`.
fn draw_one(
    renderer: &mut Renderer,
    scene: &Scene,
    states: &[BodyState],
    path: &Path,
) -> Result<(), String> {
    let (mut world, handles) =
        World::from_scene(scene, WorldConfig::default()).map_err(|e| e.to_string())?;
    if states.len() != handles.len() {
        return Err(format!(
            "{} final states for {} bodies",
            states.len(),
            handles.len()
        ));
    }
    for (&h, s) in handles.iter().zip(states) {
        world.set_pose(h, s.pose).map_err(|e| e.to_string())?;
    }
    let camera = Camera::frame_world(&world, renderer.aspect());
    let image = renderer
        .render(&world, &camera, &Overlay::NONE)
        .map_err(|e| e.to_string())?;
    image.write_png(path).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_render::Palette;

    /// A 3-cube column drawn from states raised 1 m: the frame is written and referenced,
    /// and shows boxes (pixels that are not background) where the column stands; without an
    /// adapter the note says so and nothing is referenced.
    #[test]
    fn the_last_frame_is_drawn_from_the_final_states_or_a_note_says_why_not() {
        let scene = tumble::scenes::stack(3);
        let (world, handles) = World::from_scene(&scene, WorldConfig::default()).unwrap();
        let states: Vec<BodyState> = handles
            .iter()
            .map(|&h| {
                let mut pose = world.pose(h).unwrap();
                pose.translation.vector.y += 1.0;
                BodyState {
                    pose,
                    linear_velocity: Default::default(),
                    angular_velocity: Default::default(),
                }
            })
            .collect();
        let dir = std::env::temp_dir().join(format!("tumble-last-frames-{}", std::process::id()));
        let frames = draw_last_frames(
            &dir,
            std::slice::from_ref(&scene),
            &[(scene.name.clone(), states)],
        );
        let Some(path) = frames.frame_of(&scene.name) else {
            assert!(
                frames.notes.iter().any(|n| n.contains("not drawn")),
                "{:?}",
                frames.notes
            );
            assert!(
                std::env::var_os("TUMBLE_REQUIRE_GPU").is_none(),
                "no frame: {:?}",
                frames.notes
            );
            println!("skipped: no GPU adapter");
            return;
        };
        assert!(frames.notes.is_empty(), "{:?}", frames.notes);
        let file = std::fs::File::open(dir.join(path)).unwrap();
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap();
        let mut pixels = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut pixels).unwrap();
        assert_eq!((info.width, info.height), SIZE);
        // The camera frames the column: its centre pixel is a box, not the sky.
        let background = Palette::rgba8(Palette::DEFAULT.background);
        let i = ((SIZE.1 / 2 * SIZE.0 + SIZE.0 / 2) * 4) as usize;
        assert_ne!(pixels[i..i + 4], background[..]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
