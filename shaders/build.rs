//! Embeds every WGSL file of this package (the repository's `shaders/` folder) and checks
//! their `// requires:` directives: writes `$OUT_DIR/wgsl_files.rs`, a table of `WgslFile`s
//! (path relative to `shaders/`, text by `include_str!`) sorted by path, which `src/lib.rs`
//! includes. A directive naming no file, or a cycle of them, fails the build with the chain.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[path = "src/requires.rs"]
mod requires;

fn collect(dir: &Path, root: &Path, out: &mut Vec<(String, PathBuf)>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
        .map(|entry| entry.expect("directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            // A build directory is no source of shaders.
            if path.file_name().is_some_and(|n| n == "target") {
                continue;
            }
            collect(&path, root, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            let relative = path.strip_prefix(root).expect("under shaders/");
            let relative = relative.to_string_lossy().replace('\\', "/");
            out.push((relative, path));
        }
    }
}

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let root = root
        .canonicalize()
        .unwrap_or_else(|e| panic!("shaders folder at {}: {e}", root.display()));
    println!("cargo:rerun-if-changed={}", root.display());
    let mut files = Vec::new();
    collect(&root, &root, &mut files);
    files.sort();

    let texts: BTreeMap<&str, String> = files
        .iter()
        .map(|(relative, path)| {
            let text = std::fs::read_to_string(path)
                .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
            (relative.as_str(), text)
        })
        .collect();
    let source_of = |path: &str| {
        texts
            .get_key_value(path)
            .map(|(path, text)| (*path, text.as_str()))
    };
    for relative in texts.keys() {
        if let Err(message) = requires::order(relative, &source_of) {
            panic!("shaders/{relative}: {message}");
        }
    }

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
