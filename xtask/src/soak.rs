//! `cargo xtask soak`: long runs that must stay sound. The pyramid of 24 (4,901 boxes) for
//! 100,000 steps on the CPU and 20,000 on the GPU, and a pool whose bodies are added and
//! removed every step. Every sample checks that each pose and velocity is finite, that the
//! pyramid's mechanical energy has not grown and its top box still stands, and records the
//! process's resident memory and the world's GPU buffer bytes, which must stay flat.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};
use tumble::prelude::*;
use tumble::{BodyHandle, EffectOverrides, World};

/// Arguments of `cargo xtask soak`.
#[derive(Args)]
pub struct SoakArgs {
    /// Steps of the pyramid on the CPU backend.
    #[arg(long, default_value_t = 100_000)]
    cpu_steps: u64,
    /// Steps of the pyramid on the GPU backend.
    #[arg(long, default_value_t = 20_000)]
    gpu_steps: u64,
    /// Steps of the pool (bodies added and removed every step), on each backend.
    #[arg(long, default_value_t = 20_000)]
    pool_steps: u64,
    /// Layers of the pyramid (24: 4,901 boxes).
    #[arg(long, default_value_t = 24)]
    pyramid: usize,
    /// Steps between two samples.
    #[arg(long, default_value_t = 1_000)]
    sample_every: u64,
    /// Backends to soak, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [SoakBackend::Cpu, SoakBackend::Gpu])]
    backends: Vec<SoakBackend>,
    /// Report folder [default: target/soak in the workspace].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// A backend to soak.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SoakBackend {
    /// Every stage on the CPU.
    Cpu,
    /// Every stage on the GPU.
    Gpu,
}

impl SoakBackend {
    fn backend(self) -> Backend {
        match self {
            Self::Cpu => Backend::Cpu,
            Self::Gpu => Backend::Gpu,
        }
    }
}

/// Energy may not grow by more than this fraction of what a full collapse would release: a
/// resting pile loses energy to contacts and friction and gains none, and a solver that
/// pumps energy into it shows here long before the pile moves.
const MAX_ENERGY_GAIN: f64 = 0.01;
/// The pyramid's top box may move by at most this much (m): a standing pile settles by
/// millimetres; a collapse moves the top by metres.
const MAX_TOP_DRIFT: f32 = 0.05;
/// Memory is flat when the highest sample of the run's second half is within this factor of
/// the highest of its first half (from the first sample on, after the warm-up). Peaks rather
/// than the first and last sample: the allocator hands memory back and takes it again, so one
/// sample may sit anywhere in a band (on the 2-core build machine the CPU pyramid's resident
/// memory moved between 70.1 and 96.6 MiB from sample to sample with no trend), while a leak
/// raises every later peak.
const MAX_MEMORY_GROWTH: f64 = 1.10;
/// Bodies the pool holds once full: each step adds one and, from then on, removes the oldest.
const POOL_BODIES: usize = 256;

/// Every sample, from the first (after the warm-up, in which buffers and caches reach their
/// size) on, of the process's resident bytes and the world's GPU buffer bytes.
#[derive(Default)]
struct Memory {
    rss: Vec<u64>,
    device: Vec<u64>,
}

/// The first and last of `samples`, and the highest of each half (the middle sample of an odd
/// count in the first); zeros when there are none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Band {
    first: u64,
    last: u64,
    first_half_peak: u64,
    second_half_peak: u64,
}

impl Band {
    fn of(samples: &[u64]) -> Self {
        let (Some(&first), Some(&last)) = (samples.first(), samples.last()) else {
            return Band::default();
        };
        let (early, late) = samples.split_at(samples.len().div_ceil(2));
        let peak = |s: &[u64]| s.iter().copied().max().unwrap_or(0);
        Band {
            first,
            last,
            first_half_peak: peak(early),
            // One sample: the second half is that sample too.
            second_half_peak: if late.is_empty() { last } else { peak(late) },
        }
    }

    /// Whether the second half's peak rose past [`MAX_MEMORY_GROWTH`] times the first's.
    fn grew(&self) -> bool {
        self.first_half_peak > 0
            && self.second_half_peak as f64 > self.first_half_peak as f64 * MAX_MEMORY_GROWTH
    }

    /// `first / last (peaks: first half / second half)`, in MiB.
    fn cell(&self) -> String {
        format!(
            "{} / {} (peaks {} / {})",
            mib(self.first),
            mib(self.last),
            mib(self.first_half_peak),
            mib(self.second_half_peak)
        )
    }
}

impl Memory {
    fn sample(&mut self, world: &World) {
        self.rss.push(resident_bytes());
        self.device.push(world.device_buffer_bytes());
    }

    fn bands(&self) -> [(&'static str, Band); 2] {
        [
            ("resident memory", Band::of(&self.rss)),
            ("GPU buffers", Band::of(&self.device)),
        ]
    }

    /// A failure for each of the two whose peaks grew past [`MAX_MEMORY_GROWTH`].
    fn failures(&self) -> Vec<String> {
        self.bands()
            .into_iter()
            .filter(|(_, band)| band.grew())
            .map(|(what, band)| {
                format!(
                    "{what}'s peak grew from {} to {} MiB",
                    mib(band.first_half_peak),
                    mib(band.second_half_peak)
                )
            })
            .collect()
    }
}

/// One run's figures.
struct Soaked {
    run: String,
    backend: SoakBackend,
    steps: u64,
    ms_per_step: f64,
    /// Largest energy gain over the start, as a fraction of the collapse energy (pyramid).
    energy_gain: Option<f64>,
    /// Largest distance the top box moved from its start (pyramid), m.
    top_drift: Option<f32>,
    memory: Memory,
    /// What failed, empty when the run is sound.
    failures: Vec<String>,
}

impl Soaked {
    fn new(run: String, backend: SoakBackend, steps: u64) -> Self {
        Self {
            run,
            backend,
            steps,
            ms_per_step: 0.0,
            energy_gain: None,
            top_drift: None,
            memory: Memory::default(),
            failures: Vec::new(),
        }
    }

    /// Checks that every pose and velocity is finite, then samples memory; false (with the
    /// failure recorded) when a body is not.
    fn check(&mut self, world: &World, step: u64) -> Result<bool, Error> {
        if let Some(h) = first_non_finite(world)? {
            self.failures
                .push(format!("step {step}: body {h:?} is not finite"));
            return Ok(false);
        }
        self.memory.sample(world);
        Ok(true)
    }
}

/// Resident set size of this process, bytes (0 where /proc is missing).
fn resident_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        })
        .map_or(0, |kib| kib * 1024)
}

/// Kinetic plus potential energy of the dynamic bodies (J), and the potential energy they
/// would release by falling to the lowest one's height (the collapse energy).
fn energies(world: &World, handles: &[BodyHandle], gravity: Vec3) -> Result<(f64, f64), Error> {
    let g = f64::from(gravity.norm());
    let up = if g > 0.0 {
        -gravity / gravity.norm()
    } else {
        Vec3::y()
    };
    let mut total = 0.0;
    let mut heights = Vec::new();
    for &h in handles {
        if world.kind(h)? != BodyKind::Dynamic {
            continue;
        }
        let m = f64::from(world.mass(h)?);
        let height = f64::from(world.pose(h)?.translation.vector.dot(&up));
        total += f64::from(world.kinetic_energy(h)?) + m * g * height;
        heights.push((m, height));
    }
    let lowest = heights
        .iter()
        .map(|&(_, y)| y)
        .fold(f64::INFINITY, f64::min);
    let collapse = heights.iter().map(|&(m, y)| m * g * (y - lowest)).sum();
    Ok((total, collapse))
}

/// The first body whose pose or velocity is not finite.
fn first_non_finite(world: &World) -> Result<Option<BodyHandle>, Error> {
    for &h in world.handles() {
        let p = world.pose(h)?;
        let v = world.linear_velocity(h)?;
        let w = world.angular_velocity(h)?;
        let finite = p.translation.vector.iter().all(|c| c.is_finite())
            && p.rotation.coords.iter().all(|c| c.is_finite())
            && v.iter().chain(w.iter()).all(|c| c.is_finite());
        if !finite {
            return Ok(Some(h));
        }
    }
    Ok(None)
}

fn soak_pyramid(args: &SoakArgs, backend: SoakBackend, steps: u64) -> Result<Soaked, String> {
    let scene = tumble::scenes::pyramid(args.pyramid);
    let config = WorldConfig {
        backend: backend.backend(),
        // A sleeping pyramid would soak nothing: every box is integrated every step.
        effects: EffectOverrides::NO_SLEEP,
        ..Default::default()
    };
    let (mut world, handles) = World::from_scene(&scene, config).map_err(|e| e.to_string())?;
    let gravity = world.config().gravity;
    let err = |e: Error| e.to_string();
    let (e0, collapse) = energies(&world, &handles, gravity).map_err(err)?;
    let top = *handles
        .iter()
        .filter(|&&h| world.kind(h).is_ok_and(|k| k == BodyKind::Dynamic))
        .max_by(|&&a, &&b| {
            let y = |h| world.pose(h).map_or(f32::MIN, |p| p.translation.vector.y);
            y(a).total_cmp(&y(b))
        })
        .ok_or("the pyramid has no dynamic body")?;
    let top_start = world.pose(top).map_err(err)?.translation.vector;
    let mut out = Soaked::new(format!("pyramid of {}", args.pyramid), backend, steps);
    out.energy_gain = Some(0.0);
    out.top_drift = Some(0.0);
    let start = Instant::now();
    let mut done = 0;
    while done < steps {
        let chunk = args.sample_every.min(steps - done);
        for _ in 0..chunk {
            if let Err(e) = world.step() {
                out.failures.push(format!("step {done}: {e}"));
                return Ok(out);
            }
            done += 1;
        }
        if !out.check(&world, done).map_err(err)? {
            break;
        }
        let (e, _) = energies(&world, &handles, gravity).map_err(err)?;
        let gain = (e - e0) / collapse.max(f64::MIN_POSITIVE);
        out.energy_gain = out.energy_gain.map(|g| g.max(gain));
        let drift = (world.pose(top).map_err(err)?.translation.vector - top_start).norm();
        out.top_drift = out.top_drift.map(|d| d.max(drift));
        // A run of hours shows where it is: each sample on one line, so a run that is
        // stopped still tells how far it went and what it had measured.
        eprintln!(
            "soak: step {done}: {:.1} s, {:.2} ms/step, energy gain {:.4}%, top box {:.1} mm, RSS {} MiB",
            start.elapsed().as_secs_f64(),
            start.elapsed().as_secs_f64() * 1e3 / done.max(1) as f64,
            gain * 100.0,
            drift * 1e3,
            mib(out.memory.rss.last().copied().unwrap_or(0)),
        );
    }
    out.ms_per_step = start.elapsed().as_secs_f64() * 1e3 / done.max(1) as f64;
    if out.energy_gain.is_some_and(|g| g > MAX_ENERGY_GAIN) {
        out.failures.push(format!(
            "energy grew by {:.3}% of the collapse energy",
            out.energy_gain.unwrap_or(0.0) * 100.0
        ));
    }
    if out.top_drift.is_some_and(|d| d > MAX_TOP_DRIFT) {
        out.failures.push(format!(
            "the top box moved {:.3} m",
            out.top_drift.unwrap_or(0.0)
        ));
    }
    out.failures.extend(out.memory.failures());
    Ok(out)
}

fn soak_pool(args: &SoakArgs, backend: SoakBackend) -> Result<Soaked, String> {
    let err = |e: Error| e.to_string();
    let mut world = World::new(WorldConfig {
        backend: backend.backend(),
        ..Default::default()
    })
    .map_err(err)?;
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(20.0, 0.5, 20.0))
                .translation(0.0, -0.5, 0.0),
        )
        .map_err(err)?;
    let mut live = std::collections::VecDeque::new();
    let mut out = Soaked::new(
        format!("pool of {POOL_BODIES}, one added and one removed per step"),
        backend,
        args.pool_steps,
    );
    let start = Instant::now();
    for step in 0..args.pool_steps {
        // Drop points on a 16 x 16 grid, 4 m up, turning through it step by step, with
        // sizes cycling through five values so shapes change as bodies come and go.
        let cell = (step % 256) as f32;
        let (x, z) = ((cell % 16.0) - 7.5, (cell / 16.0).floor() - 7.5);
        let half = 0.2 + 0.05 * (step % 5) as f32;
        let body = BodyDesc::dynamic()
            .cuboid(Vec3::new(half, half, half))
            .translation(x * 1.1, 4.0, z * 1.1);
        live.push_back(world.add_body(body).map_err(err)?);
        if live.len() > POOL_BODIES
            && let Some(oldest) = live.pop_front()
        {
            world.remove_body(oldest).map_err(err)?;
        }
        if let Err(e) = world.step() {
            out.failures.push(format!("step {step}: {e}"));
            return Ok(out);
        }
        if (step + 1) % args.sample_every == 0 && !out.check(&world, step + 1).map_err(err)? {
            break;
        }
    }
    out.ms_per_step = start.elapsed().as_secs_f64() * 1e3 / args.pool_steps.max(1) as f64;
    if world.body_count() != POOL_BODIES.min(args.pool_steps as usize) + 1 {
        out.failures.push(format!(
            "the pool holds {} bodies, expected {}",
            world.body_count(),
            POOL_BODIES.min(args.pool_steps as usize) + 1
        ));
    }
    out.failures.extend(out.memory.failures());
    Ok(out)
}

fn mib(bytes: u64) -> String {
    format!("{:.1}", bytes as f64 / 1048576.0)
}

fn table(rows: &[Soaked]) -> String {
    let mut t = String::from(
        "| run | backend | steps | ms per step | energy gain (of collapse) | top box moved | RSS first / last (peaks: first half / second half), MiB | GPU buffers, the same | result |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            t,
            "| {} | {:?} | {} | {:.2} | {} | {} | {} | {} | {} |",
            r.run,
            r.backend,
            r.steps,
            r.ms_per_step,
            r.energy_gain
                .map_or("—".into(), |g| format!("{:.4}%", g * 100.0)),
            r.top_drift
                .map_or("—".into(), |d| format!("{:.1} mm", d * 1e3)),
            Band::of(&r.memory.rss).cell(),
            Band::of(&r.memory.device).cell(),
            if r.failures.is_empty() {
                "sound".to_string()
            } else {
                r.failures.join("; ")
            }
        );
    }
    t
}

/// Caps glibc's malloc at two arenas unless the `MALLOC_ARENA_MAX` variable is present (glibc
/// then reads it itself), so that the resident memory sampled measures the engine's
/// allocations rather than how many of the allocator's per-thread arenas the pool's workers
/// have touched so far. Measured on a 16-core host (docs/reliability.md, "Soak"): with glibc's
/// default (up to eight arenas per core) the CPU pyramid's RSS rose in steps of about 8 MiB
/// from 86.9 to 135.5 MiB in 3,000 steps as workers moved between arenas; with two arenas it
/// stayed at 82.4 to 82.7 MiB. A leak grows either way. Elsewhere (another C library or OS)
/// this does nothing.
fn cap_malloc_arenas() -> &'static str {
    if std::env::var_os("MALLOC_ARENA_MAX").is_some() {
        return "as MALLOC_ARENA_MAX sets";
    }
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        unsafe extern "C" {
            /// glibc's `mallopt(3)`.
            fn mallopt(param: i32, value: i32) -> i32;
        }
        /// `M_ARENA_MAX` of glibc's `malloc.h`.
        const M_ARENA_MAX: i32 = -8;
        // SAFETY: the declaration matches glibc's `int mallopt(int param, int value)`, and
        // mallopt takes the allocator's own lock, so it is sound from any thread.
        if unsafe { mallopt(M_ARENA_MAX, 2) } == 1 {
            return "glibc capped at 2 arenas";
        }
    }
    "the allocator's default"
}

/// Runs the soak; `Ok(false)` when a run failed a check.
pub fn soak(args: &SoakArgs, workspace: &std::path::Path) -> Result<bool, String> {
    if args.sample_every == 0 {
        return Err("--sample-every 0: expected at least 1 step between samples".into());
    }
    eprintln!("soak: malloc arenas: {}", cap_malloc_arenas());
    let mut rows = Vec::new();
    for &backend in &args.backends {
        let steps = match backend {
            SoakBackend::Cpu => args.cpu_steps,
            SoakBackend::Gpu => args.gpu_steps,
        };
        eprintln!(
            "soak: pyramid of {} on {backend:?}, {steps} steps",
            args.pyramid
        );
        rows.push(soak_pyramid(args, backend, steps)?);
        eprintln!("soak: pool on {backend:?}, {} steps", args.pool_steps);
        rows.push(soak_pool(args, backend)?);
    }
    let report = table(&rows);
    print!("{report}");
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| workspace.join("target").join("soak"));
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let file = out.join("soak.md");
    std::fs::write(&file, &report).map_err(|e| format!("{}: {e}", file.display()))?;
    eprintln!("soak: wrote {}", file.display());
    Ok(rows.iter().all(|r| r.failures.is_empty()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mib_samples(values: &[f64]) -> Vec<u64> {
        values
            .iter()
            .map(|v| (v * 1024.0 * 1024.0) as u64)
            .collect()
    }

    #[test]
    fn a_band_without_trend_is_flat_and_a_steady_rise_is_not() {
        // The CPU pyramid's first samples on the 2-core build machine: up and down by 20 MiB
        // with no trend. First against last would call 82.7 to 96.6 a 17% growth.
        let wobble = Band::of(&mib_samples(&[82.7, 96.6, 83.6, 95.5, 94.6, 75.9, 96.0]));
        // Seven samples: the first half is the first four.
        let peaks = mib_samples(&[96.6, 96.0]);
        assert_eq!(
            (wobble.first_half_peak, wobble.second_half_peak),
            (peaks[0], peaks[1])
        );
        assert!(!wobble.grew(), "{wobble:?}");
        // A leak of 2 MiB per sample from 80 MiB: the second half's peak (98) is 1.11 times
        // the first's (88), past the 10% allowed.
        let leak: Vec<f64> = (0..10).map(|i| 80.0 + 2.0 * i as f64).collect();
        let leak = Band::of(&mib_samples(&leak));
        assert_eq!(leak.first_half_peak, mib_samples(&[88.0])[0]);
        assert_eq!(leak.second_half_peak, mib_samples(&[98.0])[0]);
        assert!(leak.grew(), "{leak:?}");
        // The same leak at half the rate stays within 10% over ten samples: the bound is
        // on the peaks, not on any growth at all.
        let slow: Vec<f64> = (0..10).map(|i| 80.0 + 1.0 * i as f64).collect();
        assert!(!Band::of(&mib_samples(&slow)).grew());
    }

    #[test]
    fn no_sample_or_one_sample_never_grows() {
        assert_eq!(Band::of(&[]), Band::default());
        assert!(!Band::of(&[]).grew());
        let one = Band::of(&[5 << 20]);
        assert_eq!(
            (one.first_half_peak, one.second_half_peak),
            (5 << 20, 5 << 20)
        );
        assert!(!one.grew());
    }
}
