//! Project tasks, run as `cargo xtask <task>`:
//! - `validate`: every scene under every solver configuration and backend, beside rapier3d,
//!   measured (docs/validation.md), tabled and plotted, with each scene's last frame;
//! - `bench`: the criterion benches;
//! - `bench-gpu`: Tumble's GPU step beside rapier3d (and nexus, from its peer script's CSV);
//! - `render`: a scene's frames as PNG pictures and a GIF animation (tumble-render);
//! - `soak`: long runs of the pyramid of 24 and of a pool with bodies added and removed,
//!   checked for finite state, bounded energy and flat memory (docs/reliability.md);
//! - `tidy`: formatting and the layer rule of docs/architecture.md.
#![warn(missing_docs)]

mod backends;
mod batch;
mod bench;
mod bench_gpu;
mod bench_gpu_report;
mod energy;
mod engine;
mod engine_rapier;
mod engine_tumble;
mod fonts;
mod grid;
mod last_frames;
mod layers;
mod metrics;
mod penetration;
mod plot;
mod render;
mod report;
mod results;
mod run;
mod scene_info;
mod scene_set;
mod soak;
mod table;
mod tidy;
mod timing;
mod validate;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

use crate::grid::{BackendChoice, GridSize};
use crate::validate::{ValidateArgs, validate};

/// Exit code when the validation ran but a scene failed its check in the default
/// configuration (or a tidy check failed).
const EXIT_FAILED_CHECK: u8 = 1;
/// Exit code when a task could not run at all (bad arguments, unwritable folder, ...).
const EXIT_ERROR: u8 = 2;

#[derive(Parser)]
#[command(name = "cargo xtask", about = "Tumble's project tasks")]
struct Cli {
    #[command(subcommand)]
    task: Task,
}

#[derive(Subcommand)]
enum Task {
    /// Runs every scene under every solver configuration and backend, and rapier3d, and writes
    /// a report; fails when a scene fails its check in the default configuration.
    Validate(ValidateCli),
    /// Runs the criterion benches of the `tumble-benches` package (extra arguments go to
    /// `cargo bench`).
    Bench {
        /// Passed to `cargo bench -p tumble-benches` (e.g. `--bench broad_phase`).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// Times Tumble's GPU step beside rapier3d on all cores on the large scenes, with per-pass
    /// GPU times, memory per body and the traffic model; joins nexus's rows from the CSV of
    /// benches/peers/nexus_scenes.py.
    BenchGpu(bench_gpu::BenchGpuArgs),
    /// Steps a scene and draws each frame with tumble-render: PNG frames and an animated GIF
    /// (on any adapter, lavapipe included).
    Render(render::RenderArgs),
    /// Long runs that must stay sound: the pyramid of 24 for 100,000 steps on the CPU and
    /// 20,000 on the GPU, and a pool with a body added and one removed every step; fails when
    /// a state turns non-finite, energy grows, the pyramid falls or memory grows.
    Soak(soak::SoakArgs),
    /// Checks formatting (`cargo fmt --check`) and that no crate imports one to its right in
    /// the layer order of docs/architecture.md.
    Tidy,
}

#[derive(Args)]
struct ValidateCli {
    /// The reduced grid on shortened scenes (the default): a few minutes on two cores.
    #[arg(long, conflicts_with = "full")]
    quick: bool,
    /// The whole grid on full-length scenes, plus the large pyramid.
    #[arg(long)]
    full: bool,
    /// Scene files (JSON, the `tumble-scenes` schema) to run instead of the built-in set.
    #[arg(long = "scene", value_name = "FILE.json", num_args = 1..)]
    scenes: Vec<PathBuf>,
    /// Report folder [default: target/validation in the workspace].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Backends to run, comma-separated: cpu, gpu, hybrid [default: cpu, plus gpu and hybrid
    /// where a hardware GPU adapter exists].
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    backends: Option<Vec<String>>,
    /// Keep only scenes whose name contains this text.
    #[arg(long, value_name = "NAME")]
    filter: Option<String>,
    /// Also run each scene's Tumble grid runs as one `WorldBatch` per backend (one world per
    /// configuration): report the speed-up over the runs one by one and check every world
    /// ends bit for bit as its run alone (written to batch.md in the report folder).
    #[arg(long)]
    batch: bool,
}

/// The workspace root (this crate lives in `xtask/` under it).
fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

fn run_validate(cli: ValidateCli) -> Result<bool, String> {
    let backends = cli
        .backends
        .map(|list| {
            list.iter()
                .map(|b| BackendChoice::parse(b))
                .collect::<Result<Vec<_>, _>>()
        })
        .transpose()?;
    let args = ValidateArgs {
        size: if cli.full {
            GridSize::Full
        } else {
            GridSize::Quick
        },
        scene_files: cli.scenes,
        out: cli
            .out
            .unwrap_or_else(|| workspace_root().join("target").join("validation")),
        backends,
        filter: cli.filter,
        batch: cli.batch,
    };
    validate(&args)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.task {
        Task::Validate(v) => run_validate(v),
        Task::Bench { args } => bench::run_benches(&workspace_root(), &args),
        Task::BenchGpu(args) => bench_gpu::bench_gpu(&args),
        Task::Render(args) => render::render(&args, &workspace_root()),
        Task::Soak(args) => soak::soak(&args, &workspace_root()),
        Task::Tidy => tidy::tidy(&workspace_root()),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(EXIT_FAILED_CHECK),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(EXIT_ERROR)
        }
    }
}
