//! `cargo xtask tidy`: formatting and the layer rule, the checks that need no build.

use std::path::Path;
use std::process::Command;

use crate::layers::{edges_from_metadata, violations};

/// Runs `cargo fmt --check` and the layer check; `Ok(false)` when either finds a problem.
pub fn tidy(root: &Path) -> Result<bool, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let fmt = Command::new(&cargo)
        .current_dir(root)
        .args(["fmt", "--all", "--", "--check"])
        .status()
        .map_err(|e| format!("starting cargo fmt: {e}"))?;
    if !fmt.success() {
        eprintln!("tidy: `cargo fmt --all` would change the files listed above");
    }

    let out = Command::new(&cargo)
        .current_dir(root)
        .args(["metadata", "--no-deps", "--format-version", "1"])
        .output()
        .map_err(|e| format!("starting cargo metadata: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "cargo metadata failed: {}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let json: serde_json::Value =
        serde_json::from_slice(&out.stdout).map_err(|e| format!("cargo metadata output: {e}"))?;
    let broken = violations(&edges_from_metadata(&json)?);
    for v in &broken {
        eprintln!("tidy: {v}");
    }
    if broken.is_empty() {
        println!("tidy: layer rule holds");
    }
    Ok(fmt.success() && broken.is_empty())
}
