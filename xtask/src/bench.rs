//! `cargo xtask bench`: the criterion benches of `tumble-benches`, through cargo.

use std::path::Path;
use std::process::Command;

/// Runs `cargo bench -p tumble-benches <args>` in the workspace; `Ok(false)` when it fails.
pub fn run_benches(root: &Path, args: &[String]) -> Result<bool, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(root)
        .args(["bench", "-p", "tumble-benches"])
        .args(args)
        .status()
        .map_err(|e| format!("starting cargo bench: {e}"))?;
    Ok(status.success())
}
