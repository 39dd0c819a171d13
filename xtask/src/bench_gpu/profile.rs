//! The timestamped GPU run of a scene, in a process of its own: per-pass GPU times, the
//! counts of the traffic model and the world's buffer bytes.

use super::*;

/// Steps of the timestamped GPU run before its profiled steps, and the profiled steps.
pub(super) const PROFILE_SETTLE_STEPS: usize = 10;
pub(super) const PROFILE_STEPS: usize = 10;
/// The fewest profiled steps, whatever the budget.
pub(super) const MIN_PROFILED_STEPS: usize = 3;
/// What the timestamped GPU run adds to the GPU row.
pub(super) struct GpuProfile {
    /// GPU time per step of each pass name, ms, and how many passes of that name a step has.
    pub(super) passes: Vec<(&'static str, f64, usize)>,
    pub(super) traffic: TrafficCounts,
    pub(super) buffer_bytes: u64,
}

/// Steps `scene` on a [`GpuWorld`] with timestamps, as the facade's GPU backend does, and
/// returns the per-pass times (empty without timestamp queries), the counts of the traffic
/// model and the world's buffer bytes.
pub(super) fn profile_gpu(
    ctx: &GpuContext,
    scene: &Scene,
    substeps: u32,
    budget: Duration,
) -> Result<GpuProfile, String> {
    let err = |e: tumble_gpu::GpuError| e.to_string();
    let (bodies, states) = tumble_tests::scene_support::bodies_of(scene);
    let defaults = WorldConfig::default();
    let mut world = GpuWorld::new(
        ctx,
        GpuWorldConfig {
            gravity: Vec3::from(scene.gravity),
            dt: scene.dt,
            margin: defaults.margin,
            solver: SolverConfig {
                substeps,
                ..defaults.solver
            },
            timestamps: true,
            ..Default::default()
        },
    )
    .map_err(err)?;
    world.set_bodies(&bodies, &states).map_err(err)?;
    // Settling and profiled steps, fewer where a step is slow (as `timed_steps` does).
    let start = Instant::now();
    let mut last = Duration::ZERO;
    let mut settled = 0;
    while settled < PROFILE_SETTLE_STEPS && (settled < 2 || start.elapsed() < budget / 4) {
        let t0 = Instant::now();
        world.step().map_err(err)?;
        // Each step's timestamps are read, as in the profiled steps.
        world.timings().map_err(err)?;
        last = t0.elapsed();
        settled += 1;
    }
    let left = budget.saturating_sub(start.elapsed());
    let affordable = (left.as_secs_f64() / last.as_secs_f64().max(1e-6)) as usize;
    let profiled = PROFILE_STEPS.min(affordable.max(MIN_PROFILED_STEPS));
    let mut sums: BTreeMap<&'static str, (f64, usize)> = BTreeMap::new();
    for _ in 0..profiled {
        world.step().map_err(err)?;
        for (name, seconds) in world.timings().map_err(err)? {
            let e = sums.entry(name).or_default();
            e.0 += seconds;
            e.1 += 1;
        }
    }
    let snapshot = world
        .read_now(ReadRequest {
            contacts: true,
            ..Default::default()
        })
        .map_err(err)?;
    let (manifolds, points) = snapshot.contacts.as_ref().map_or((0, 0), |c| {
        let live = c.manifolds.iter().filter(|m| m.len > 0);
        (
            live.clone().count() as u64,
            live.map(|m| u64::from(m.len)).sum::<u64>(),
        )
    });
    let mut passes: Vec<_> = sums
        .into_iter()
        .map(|(name, (seconds, count))| (name, seconds * 1e3 / profiled as f64, count / profiled))
        .collect();
    passes.sort_by(|a, b| b.1.total_cmp(&a.1));
    Ok(GpuProfile {
        passes,
        traffic: TrafficCounts {
            bodies: bodies.len() as u64,
            manifolds,
            points,
            substeps: u64::from(substeps),
        },
        buffer_bytes: world.buffer_bytes(),
    })
}

/// The line a profile process prints its result on.
pub(super) const PROFILE_PREFIX: &str = "bench-gpu profile: ";

/// Runs [`profile_gpu`] on `name` in this process (a fresh device) and prints the result.
pub(super) fn print_profile(name: &str, substeps: u32, budget: Duration) -> Result<bool, String> {
    let scene = scene_named(name)?;
    let ctx = GpuContext::new().map_err(|e| format!("no GPU adapter: {e}"))?;
    let p = profile_gpu(&ctx, &scene, substeps, budget)?;
    let passes: Vec<_> = p
        .passes
        .iter()
        .map(|(name, ms, count)| serde_json::json!([name, ms, count]))
        .collect();
    let value = serde_json::json!({
        "passes": passes,
        "bodies": p.traffic.bodies,
        "manifolds": p.traffic.manifolds,
        "points": p.traffic.points,
        "substeps": p.traffic.substeps,
        "buffer_bytes": p.buffer_bytes,
    });
    println!("{PROFILE_PREFIX}{value}");
    Ok(true)
}

/// What a profile process of the same binary measured on `name`.
pub(super) fn profile_in_child(
    name: &str,
    substeps: u32,
    budget_s: f64,
) -> Result<ChildProfile, String> {
    let exe = std::env::current_exe().map_err(|e| format!("finding this binary: {e}"))?;
    let output = std::process::Command::new(exe)
        .args(["bench-gpu", "--profile-scene", name, "--substeps"])
        .arg(substeps.to_string())
        .arg("--budget-s")
        .arg(budget_s.to_string())
        .output()
        .map_err(|e| format!("starting the profile process: {e}"))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let Some(line) = stdout.lines().find_map(|l| l.strip_prefix(PROFILE_PREFIX)) else {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        return Err(format!(
            "the profile process failed ({}): {last}",
            output.status
        ));
    };
    let v: serde_json::Value = serde_json::from_str(line).map_err(|e| e.to_string())?;
    let count = |key: &str| v[key].as_u64().unwrap_or(0);
    let passes = v["passes"]
        .as_array()
        .map(|list| {
            list.iter()
                .map(|p| {
                    (
                        p[0].as_str().unwrap_or("?").to_owned(),
                        p[1].as_f64().unwrap_or(0.0),
                        p[2].as_u64().unwrap_or(0) as usize,
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    Ok(ChildProfile {
        passes,
        traffic: TrafficCounts {
            bodies: count("bodies"),
            manifolds: count("manifolds"),
            points: count("points"),
            substeps: count("substeps"),
        },
        buffer_bytes: count("buffer_bytes"),
    })
}

/// [`GpuProfile`] as read back from a profile process.
pub(super) struct ChildProfile {
    pub(super) passes: Vec<(String, f64, usize)>,
    pub(super) traffic: TrafficCounts,
    pub(super) buffer_bytes: u64,
}
