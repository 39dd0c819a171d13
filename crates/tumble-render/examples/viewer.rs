//! A window on a scene: `cargo run -p tumble-render --example viewer -- SCENE|FILE.json [options]`.
//!
//! Right drag orbits, the wheel zooms, a left drag picks the body under the mouse and pulls it
//! (its velocity is set each step towards the mouse on the plane facing the camera). Space
//! pauses, S steps once while paused, B switches between `Backend::Cpu` and `Backend::Gpu`
//! (the bodies' poses and velocities carry over). A status line in the picture's top left
//! corner (and the title) shows the scene, backend, paused or running, the step time and the
//! counts.
//!
//! Each frame is drawn by tumble-render (from the GPU world's own buffers on `Backend::Gpu`)
//! and its picture is copied into the window's surface on a device of the window's own.
//!
//! Scripted mode, for a check under Xvfb: `--frames N` quits after N frames, `--drag
//! X0,Y0:X1,Y1` presses the left button at (X0, Y0) pixels on frame 5 and moves to (X1, Y1)
//! by frame N - 10, through the same handlers as the mouse, printing the picked body's
//! position before and after; `--screenshot FILE.png` writes the last frame shown.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use tumble::nalgebra::Vector4;
use tumble::{Backend, BodyHandle, Point3, QueryFilter, Vec3, World, WorldConfig};
use tumble_render::{Camera, Image, Overlay, RenderConfig, Renderer, status};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

const WIDTH: u32 = 640;
const HEIGHT: u32 = 400;

struct Args {
    scene: String,
    backend: Backend,
    frames: Option<u64>,
    drag: Option<([f32; 2], [f32; 2])>,
    screenshot: Option<PathBuf>,
}

fn parse_pixel(text: &str) -> Result<[f32; 2], String> {
    let (x, y) = text.split_once(',').ok_or("expected X,Y")?;
    let n = |t: &str| {
        t.trim()
            .parse::<f32>()
            .map_err(|_| format!("{t:?} is not a number"))
    };
    Ok([n(x)?, n(y)?])
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        scene: String::new(),
        backend: Backend::Cpu,
        frames: None,
        drag: None,
        screenshot: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name}: missing value"));
        match a.as_str() {
            "--backend" => {
                args.backend = match value("--backend")?.as_str() {
                    "cpu" => Backend::Cpu,
                    "gpu" => Backend::Gpu,
                    other => return Err(format!("--backend {other}: expected cpu or gpu")),
                }
            }
            "--frames" => {
                let v = value("--frames")?;
                let n = v.parse::<u64>().ok().filter(|&n| n >= 20);
                args.frames =
                    Some(n.ok_or(format!("--frames {v}: expected a count of 20 or more"))?);
            }
            "--drag" => {
                let v = value("--drag")?;
                let (a, b) = v
                    .split_once(':')
                    .ok_or(format!("--drag {v}: expected X0,Y0:X1,Y1"))?;
                let bad = |e| format!("--drag {v}: {e}");
                args.drag = Some((parse_pixel(a).map_err(bad)?, parse_pixel(b).map_err(bad)?));
            }
            "--screenshot" => args.screenshot = Some(value("--screenshot")?.into()),
            s if s.starts_with("--") => return Err(format!("unknown option {s}")),
            s => args.scene = s.to_string(),
        }
    }
    if args.drag.is_some() && args.frames.is_none() {
        return Err("--drag needs --frames".into());
    }
    Ok(args)
}

/// The world of `name`: a scene file when it ends in `.json` (the scene format of
/// `tumble::scenes`, as `cargo xtask render` reads it), else a canonical scene by name.
fn scene_world(name: &str, backend: Backend) -> Result<World, String> {
    let scenes = tumble::scenes::canonical();
    let from_file;
    let scene = if name.ends_with(".json") {
        let text = std::fs::read_to_string(name).map_err(|e| format!("{name}: {e}"))?;
        from_file = tumble::scenes::Scene::from_json(&text).map_err(|e| format!("{name}: {e}"))?;
        &from_file
    } else {
        let names: Vec<&str> = scenes.iter().map(|s| s.name.as_str()).collect();
        scenes.iter().find(|s| s.name == name).ok_or(format!(
            "no scene named {name:?} (nor a .json scene file); the scenes: {}",
            names.join(", ")
        ))?
    };
    let config = WorldConfig {
        backend,
        ..Default::default()
    };
    Ok(World::from_scene(scene, config)
        .map_err(|e| e.to_string())?
        .0)
}

/// The camera as yaw, pitch and distance around a target.
struct Orbit {
    target: Point3,
    yaw: f32,
    pitch: f32,
    distance: f32,
}

impl Orbit {
    fn from_camera(c: &Camera) -> Self {
        let d = c.eye - c.target;
        Self {
            target: c.target,
            yaw: d.x.atan2(d.z),
            pitch: (d.y / d.norm()).asin(),
            distance: d.norm(),
        }
    }

    fn camera(&self) -> Camera {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let eye = self.target + Vec3::new(sy * cp, sp, cy * cp) * self.distance;
        Camera::looking_at(eye, self.target)
    }
}

/// The ray through pixel `(x, y)`: origin on the near plane, unit direction.
fn pixel_ray(camera: &Camera, [x, y]: [f32; 2]) -> (Point3, Vec3) {
    let inv = camera
        .view_projection(WIDTH as f32 / HEIGHT as f32)
        .try_inverse()
        .expect("an invertible camera");
    let ndc = [2.0 * x / WIDTH as f32 - 1.0, 1.0 - 2.0 * y / HEIGHT as f32];
    let at = |z: f32| {
        let p = inv * Vector4::new(ndc[0], ndc[1], z, 1.0);
        Point3::from(p.xyz() / p.w)
    };
    let (near, far) = (at(0.0), at(1.0));
    (near, (far - near).normalize())
}

/// A body held by the mouse: the grabbed point's offset from its centre, and the plane
/// (through the grabbed point, facing the camera) the mouse moves it on.
struct Grab {
    body: BodyHandle,
    offset: Vec3,
    plane_point: Point3,
    plane_normal: Vec3,
    target: Point3,
}

struct Present {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    // The device the surface was configured on, kept as long as the surface.
    _device: wgpu::Device,
    queue: wgpu::Queue,
    swap_red_blue: bool,
}

struct App {
    args: Args,
    world: World,
    renderer: Renderer,
    orbit: Orbit,
    present: Option<Present>,
    paused: bool,
    step_once: bool,
    frame: u64,
    mouse: [f32; 2],
    orbiting: bool,
    grab: Option<Grab>,
    step_ms: f64,
    last: Option<Image>,
    error: Option<String>,
}

fn render_config() -> RenderConfig {
    RenderConfig {
        width: WIDTH,
        height: HEIGHT,
        ..Default::default()
    }
}

impl App {
    fn new(args: Args) -> Result<Self, String> {
        let world = scene_world(&args.scene, args.backend)?;
        let renderer = Renderer::for_world(&world, render_config()).map_err(|e| e.to_string())?;
        let orbit = Orbit::from_camera(&Camera::frame_world(&world, renderer.aspect()));
        Ok(Self {
            args,
            world,
            renderer,
            orbit,
            present: None,
            paused: false,
            step_once: false,
            frame: 0,
            mouse: [0.0; 2],
            orbiting: false,
            grab: None,
            step_ms: 0.0,
            last: None,
            error: None,
        })
    }

    fn press(&mut self, at: [f32; 2]) {
        let (origin, dir) = pixel_ray(&self.orbit.camera(), at);
        let filter = QueryFilter::new().skip_fixed();
        let Ok(Some(hit)) = self.world.cast_ray(origin, dir, 1e4, filter) else {
            println!("no body under ({}, {})", at[0], at[1]);
            return;
        };
        let centre = self.world.pose(hit.body).map(|p| p.translation.vector);
        let Ok(centre) = centre else { return };
        println!(
            "picked body {} at ({:.3}, {:.3}, {:.3})",
            hit.body.index(),
            centre.x,
            centre.y,
            centre.z
        );
        self.grab = Some(Grab {
            body: hit.body,
            offset: hit.point.coords - centre,
            plane_point: hit.point,
            plane_normal: -dir,
            target: hit.point,
        });
    }

    fn move_to(&mut self, at: [f32; 2]) {
        let camera = self.orbit.camera();
        if let Some(grab) = &mut self.grab {
            let (origin, dir) = pixel_ray(&camera, at);
            let denom = dir.dot(&grab.plane_normal);
            if denom.abs() > 1e-6 {
                let t = (grab.plane_point - origin).dot(&grab.plane_normal) / denom;
                grab.target = origin + dir * t;
            }
        } else if self.orbiting {
            self.orbit.yaw -= (at[0] - self.mouse[0]) * 0.01;
            self.orbit.pitch = (self.orbit.pitch + (at[1] - self.mouse[1]) * 0.01).clamp(-1.4, 1.4);
        }
        self.mouse = at;
    }

    fn release(&mut self) {
        if let Some(grab) = self.grab.take()
            && let Ok(p) = self.world.pose(grab.body)
        {
            let c = p.translation.vector;
            println!(
                "released body {} at ({:.3}, {:.3}, {:.3})",
                grab.body.index(),
                c.x,
                c.y,
                c.z
            );
        }
    }

    /// Pulls the held body: a velocity that closes a fifth of the gap each step.
    fn pull(&mut self) -> Result<(), tumble::Error> {
        let Some(grab) = &self.grab else {
            return Ok(());
        };
        let dt = self.world.config().dt;
        let held = Point3::from(self.world.pose(grab.body)?.translation.vector + grab.offset);
        let v = (grab.target - held) / (5.0 * dt);
        self.world.set_linear_velocity(grab.body, v)?;
        self.world.set_angular_velocity(grab.body, Vec3::zeros())
    }

    fn switch_backend(&mut self) -> Result<(), String> {
        let next = match self.world.config().backend {
            Backend::Gpu => Backend::Cpu,
            _ => Backend::Gpu,
        };
        let mut world = scene_world(&self.args.scene, next)?;
        let e = |e: tumble::Error| e.to_string();
        for (&old, &new) in self
            .world
            .handles()
            .iter()
            .zip(world.handles().to_vec().iter())
        {
            world
                .set_pose(new, self.world.pose(old).map_err(e)?)
                .map_err(e)?;
            world
                .set_linear_velocity(new, self.world.linear_velocity(old).map_err(e)?)
                .map_err(e)?;
            world
                .set_angular_velocity(new, self.world.angular_velocity(old).map_err(e)?)
                .map_err(e)?;
        }
        self.renderer = Renderer::for_world(&world, render_config()).map_err(|e| e.to_string())?;
        self.world = world;
        self.grab = None;
        Ok(())
    }

    /// The scripted drag's events for this frame.
    fn script(&mut self) {
        let (Some((from, to)), Some(frames)) = (self.args.drag, self.args.frames) else {
            return;
        };
        let (start, end) = (5, frames - 10);
        if self.frame == start {
            self.mouse = from;
            self.press(from);
        } else if self.frame > start && self.frame <= end {
            let t = (self.frame - start) as f32 / (end - start) as f32;
            self.move_to([
                from[0] + (to[0] - from[0]) * t,
                from[1] + (to[1] - from[1]) * t,
            ]);
        } else if self.frame == end + 1 {
            self.release();
        }
    }

    fn frame(&mut self) -> Result<(), String> {
        self.script();
        if !self.paused || std::mem::take(&mut self.step_once) {
            self.pull().map_err(|e| e.to_string())?;
            let started = Instant::now();
            self.world.step().map_err(|e| e.to_string())?;
            self.step_ms = started.elapsed().as_secs_f64() * 1e3;
        }
        let s = self.world.stats();
        let state = if self.paused { "paused" } else { "running" };
        let status = status_line(&[
            format!(
                "{} on {:?}, {state}",
                self.args.scene,
                self.world.config().backend
            ),
            format!(
                "step {:.2} ms, {} bodies",
                self.step_ms,
                self.world.body_count()
            ),
            format!(
                "{} pairs, {} manifolds, {} points",
                s.pairs, s.manifolds, s.contact_points
            ),
        ]);
        self.renderer
            .set_status_line(Some(status))
            .map_err(|e| e.to_string())?;
        let image = self
            .renderer
            .render(&self.world, &self.orbit.camera(), &Overlay::CONTACTS)
            .map_err(|e| e.to_string())?;
        let title = format!(
            "tumble viewer: {} on {:?}, step {:.2} ms, {} bodies, {} pairs, {} manifolds, {} points, {} colors{}",
            self.args.scene,
            self.world.config().backend,
            self.step_ms,
            self.world.body_count(),
            s.pairs,
            s.manifolds,
            s.contact_points,
            s.colors,
            if self.paused { " (paused)" } else { "" }
        );
        if let Some(p) = &self.present {
            p.window.set_title(&title);
            show(p, &image);
        }
        if self.frame.is_multiple_of(60) {
            println!("{title}");
        }
        self.last = Some(image);
        self.frame += 1;
        Ok(())
    }
}

/// The status line's text: `lines` with characters other than printable ASCII replaced by
/// `?` and cut to the characters that fit the picture's width (a scene file's long path).
fn status_line(lines: &[String]) -> String {
    let columns = ((WIDTH - 2 * status::MARGIN) / status::CELL) as usize;
    let fit = |line: &String| -> String {
        line.chars()
            .map(|c| if status::glyph(c).is_some() { c } else { '?' })
            .take(columns)
            .collect()
    };
    lines.iter().map(fit).collect::<Vec<_>>().join("\n")
}

/// Copies `image` into the window's next surface texture and presents it.
fn show(p: &Present, image: &Image) {
    let frame = match p.surface.get_current_texture() {
        wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
        _ => return,
    };
    let mut bytes = image.pixels.clone();
    if p.swap_red_blue {
        bytes.chunks_exact_mut(4).for_each(|px| px.swap(0, 2));
    }
    p.queue.write_texture(
        frame.texture.as_image_copy(),
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * image.width),
            rows_per_image: Some(image.height),
        },
        frame.texture.size(),
    );
    p.queue.submit([]);
    p.queue.present(frame);
}

fn open_present(window: Arc<Window>) -> Result<Present, String> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let surface = instance
        .create_surface(window.clone())
        .map_err(|e| e.to_string())?;
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        compatible_surface: Some(&surface),
        ..Default::default()
    }))
    .map_err(|e| e.to_string())?;
    let (device, queue) = pollster::block_on(adapter.request_device(&Default::default()))
        .map_err(|e| e.to_string())?;
    let caps = surface.get_capabilities(&adapter);
    let format = [
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureFormat::Bgra8Unorm,
    ]
    .into_iter()
    .find(|f| caps.formats.contains(f))
    .ok_or(format!(
        "no 8-bit RGBA or BGRA surface format in {:?}",
        caps.formats
    ))?;
    if !caps.usages.contains(wgpu::TextureUsages::COPY_DST) {
        return Err("the surface cannot be copied into".into());
    }
    surface.configure(
        &device,
        &wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_DST,
            format,
            width: WIDTH,
            height: HEIGHT,
            present_mode: wgpu::PresentMode::Fifo,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes[0],
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        },
    );
    Ok(Present {
        window,
        surface,
        _device: device,
        queue,
        swap_red_blue: format == wgpu::TextureFormat::Bgra8Unorm,
    })
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.present.is_some() {
            return;
        }
        let attributes = Window::default_attributes()
            .with_title("tumble viewer")
            .with_resizable(false)
            .with_inner_size(winit::dpi::PhysicalSize::new(WIDTH, HEIGHT));
        let opened = event_loop
            .create_window(attributes)
            .map_err(|e| e.to_string())
            .and_then(|w| open_present(Arc::new(w)));
        match opened {
            Ok(p) => {
                p.window.request_redraw();
                self.present = Some(p);
            }
            Err(e) => {
                self.error = Some(format!("window: {e}"));
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.frame() {
                    self.error = Some(e);
                    event_loop.exit();
                    return;
                }
                if self.args.frames.is_some_and(|n| self.frame >= n) {
                    event_loop.exit();
                    return;
                }
                if let Some(p) = &self.present {
                    p.window.request_redraw();
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.move_to([position.x as f32, position.y as f32]);
            }
            WindowEvent::MouseInput { state, button, .. } => match (button, state) {
                (MouseButton::Left, ElementState::Pressed) => self.press(self.mouse),
                (MouseButton::Left, ElementState::Released) => self.release(),
                (MouseButton::Right, s) => self.orbiting = s == ElementState::Pressed,
                _ => {}
            },
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.orbit.distance = (self.orbit.distance * 0.9f32.powf(lines)).max(0.1);
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                match event.logical_key.as_ref() {
                    Key::Named(NamedKey::Space) => self.paused = !self.paused,
                    Key::Character("s") => self.step_once = true,
                    Key::Character("b") => {
                        if let Err(e) = self.switch_backend() {
                            eprintln!("backend switch failed: {e}");
                        }
                    }
                    Key::Named(NamedKey::Escape) => event_loop.exit(),
                    _ => {}
                }
            }
            _ => {}
        }
    }
}

fn main() -> Result<(), String> {
    let args = parse_args()?;
    if args.scene.is_empty() {
        return Err("usage: viewer SCENE|FILE.json [--backend cpu|gpu] [--frames N] [--drag X0,Y0:X1,Y1] [--screenshot FILE.png]".into());
    }
    let mut app = App::new(args)?;
    let event_loop = EventLoop::new().map_err(|e| e.to_string())?;
    event_loop.set_control_flow(ControlFlow::Poll);
    event_loop.run_app(&mut app).map_err(|e| e.to_string())?;
    if let Some(e) = app.error {
        return Err(e);
    }
    if let (Some(path), Some(image)) = (&app.args.screenshot, &app.last) {
        image.write_png(path).map_err(|e| e.to_string())?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
