//! Embeds every WGSL file under the repository's `shaders/` folder: writes
//! `$OUT_DIR/wgsl_files.rs`, a table of `WgslFile`s (path relative to `shaders/`, text by
//! `include_str!`) sorted by path, which `src/shader.rs` includes.

use std::path::{Path, PathBuf};

fn collect(dir: &Path, root: &Path, out: &mut Vec<(String, PathBuf)>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
        .map(|entry| entry.expect("directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            collect(&path, root, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            let relative = path.strip_prefix(root).expect("under shaders/");
            let relative = relative.to_string_lossy().replace('\\', "/");
            out.push((relative, path));
        }
    }
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let root = manifest.join("../../shaders");
    let root = root
        .canonicalize()
        .unwrap_or_else(|e| panic!("shaders folder at {}: {e}", root.display()));
    println!("cargo:rerun-if-changed={}", root.display());
    let mut files = Vec::new();
    collect(&root, &root, &mut files);
    files.sort();
    let mut table = String::from("&[\n");
    for (relative, path) in &files {
        table.push_str(&format!(
            "    WgslFile {{ path: {relative:?}, source: include_str!({:?}) }},\n",
            path.display().to_string()
        ));
    }
    table.push(']');
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("set by cargo"));
    std::fs::write(out.join("wgsl_files.rs"), table).expect("OUT_DIR writable");
}
