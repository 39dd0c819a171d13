//! Writes the embedded scene files under `crates/tumble-scenes/scenes/` from their builders.
//!
//! `cargo run -p tumble-scenes --example write_scene_json`

use std::path::Path;

use tumble_scenes::{EMBEDDED_SCENES, embedded_sources};

fn main() -> std::io::Result<()> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    std::fs::create_dir_all(&dir)?;
    for ((file, _), scene) in EMBEDDED_SCENES.iter().zip(embedded_sources()) {
        let path = dir.join(file);
        std::fs::write(&path, scene.to_json() + "\n")?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
