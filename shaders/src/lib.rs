//! Tumble's WGSL compute shaders, embedded in the binary at compile time, and the order in
//! which a kernel's files are composed.
//!
//! Every `.wgsl` file of this package (the repository's `shaders/` folder) is embedded by the
//! build script into one table, [`FILES`], keyed by its path relative to `shaders/`. A file
//! names the files it needs in a directive among its leading comment lines:
//!
//! ```wgsl
//! // requires: common/indexing.wgsl common/layout.wgsl
//! ```
//!
//! [`compose_order`] follows these directives transitively, depth first in the order written,
//! and lists each file once, after everything it requires and before the file that required it
//! (so the order is fixed by the files alone). The build script checks every file's directives
//! with the same code, so a directive naming no file, or a cycle, fails the build. The
//! `tumble-gpu` crate composes the listed files into one module for naga and wgpu.
//!
//! ```
//! use tumble_shaders::{FILES, compose_order, file};
//!
//! let kernel = file("collide_cuboids.wgsl");
//! let order = compose_order(kernel).expect("every embedded file's requirements resolve");
//! // The kernel comes last, after every file it needs, each listed once.
//! assert_eq!(order.last().map(|f| f.path), Some("collide_cuboids.wgsl"));
//! assert!(order.iter().any(|f| f.path == "common/layout.wgsl"));
//! assert!(FILES.windows(2).all(|w| w[0].path < w[1].path), "sorted by path");
//! ```
#![warn(missing_docs)]

mod requires;

pub use requires::REQUIRES_DIRECTIVE;

/// One WGSL file of `shaders/`, embedded in the binary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WgslFile {
    /// Path relative to `shaders/`, e.g. `common/layout.wgsl`.
    pub path: &'static str,
    /// The file's text.
    pub source: &'static str,
}

impl WgslFile {
    /// The paths this file's `// requires:` directives name, in the order written.
    pub fn requires(&self) -> impl Iterator<Item = &'static str> + use<> {
        requires::requires(self.source)
    }
}

/// Every WGSL file under `shaders/`, sorted by path (written by `build.rs`).
pub const FILES: &[WgslFile] = include!(concat!(env!("OUT_DIR"), "/wgsl_files.rs"));

const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The embedded file at `path` (relative to `shaders/`), if there is one.
pub const fn find(path: &str) -> Option<WgslFile> {
    let mut i = 0;
    while i < FILES.len() {
        if same(FILES[i].path, path) {
            return Some(FILES[i]);
        }
        i += 1;
    }
    None
}

/// The embedded file at `path`; evaluated in a constant (as kernel specs are), a path with no
/// file under `shaders/` fails the build.
pub const fn file(path: &str) -> WgslFile {
    match find(path) {
        Some(file) => file,
        None => panic!("no WGSL file at this path under shaders/"),
    }
}

/// `root` with the files its `// requires:` directives name, transitively, each once, in
/// composition order: dependencies first, `root` last. Errs on a path with no embedded file or
/// on a cycle, naming the chain.
pub fn compose_order(root: WgslFile) -> Result<Vec<WgslFile>, String> {
    let source_of = |path: &str| find(path).map(|f| (f.path, f.source));
    // `root` need not be one of FILES (tests compose files of their own): look it up first.
    let lookup = |path: &str| {
        if path == root.path {
            Some((root.path, root.source))
        } else {
            source_of(path)
        }
    };
    let paths = requires::order(root.path, &lookup)?;
    Ok(paths
        .into_iter()
        .map(|path| {
            if path == root.path {
                root
            } else {
                find(path).expect("order lists embedded files only")
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requirements_come_first_once_in_the_order_written() {
        let files = compose_order(file("collide_cuboids.wgsl")).unwrap();
        let paths: Vec<&str> = files.iter().map(|f| f.path).collect();
        assert_eq!(paths.last(), Some(&"collide_cuboids.wgsl"));
        for (i, f) in files.iter().enumerate() {
            assert_eq!(paths.iter().filter(|p| **p == f.path).count(), 1);
            for needed in f.requires() {
                let at = paths.iter().position(|p| *p == needed).unwrap();
                assert!(at < i, "{needed} after {}", f.path);
            }
        }
    }

    #[test]
    fn every_requirement_names_an_embedded_file() {
        assert!(!FILES.is_empty(), "the build script found no WGSL file");
        for f in FILES {
            compose_order(*f).unwrap_or_else(|e| panic!("{e}"));
        }
        assert!(find("common/layout.wgsl").is_some());
        assert!(find("common/no_such_file.wgsl").is_none());
    }

    #[test]
    fn a_missing_requirement_or_a_cycle_errs_naming_the_chain() {
        // A file of its own, not embedded: its directive names a path with no file.
        let orphan = WgslFile {
            path: "test/orphan.wgsl",
            source: "// requires: common/no_such_file.wgsl\nfn f() {}\n",
        };
        let err = compose_order(orphan).unwrap_err();
        assert!(
            err.contains("test/orphan.wgsl requires common/no_such_file.wgsl"),
            "{err}"
        );
        // A file requiring itself is the shortest cycle.
        let selfish = WgslFile {
            path: "test/selfish.wgsl",
            source: "// requires: test/selfish.wgsl\n",
        };
        let err = compose_order(selfish).unwrap_err();
        assert_eq!(
            err,
            "requires cycle: test/selfish.wgsl -> test/selfish.wgsl"
        );
    }

    #[test]
    fn directives_count_only_in_the_leading_comment_lines() {
        let f = WgslFile {
            path: "test/late.wgsl",
            source: "// requires: common/quat.wgsl\nfn f() {}\n// requires: common/sat.wgsl\n",
        };
        assert_eq!(f.requires().collect::<Vec<_>>(), ["common/quat.wgsl"]);
    }
}

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
