//! The layer rule of docs/architecture.md: the engine's crates form a strict order and a crate
//! never imports one to its right.
//!
//! ```text
//! tumble-geometry <- tumble-broad  <- tumble-solver <- tumble-gpu <- tumble (facade) <- tumble-render
//!                 <- tumble-narrow <-'      |          |                |
//!                    tumble-scenes (scene data) <------+----------------'
//! tumble-shaders (the WGSL files) <--------------------'
//! ```

/// The arrows of the diagram: each engine crate and the crates directly below it. A crate
/// may import anything reachable along these arrows, and nothing else of the engine.
pub const ARROWS: [(&str, &[&str]); 9] = [
    ("tumble-geometry", &[]),
    ("tumble-shaders", &[]),
    ("tumble-broad", &["tumble-geometry"]),
    ("tumble-narrow", &["tumble-geometry"]),
    ("tumble-scenes", &["tumble-solver"]),
    ("tumble-solver", &["tumble-broad", "tumble-narrow"]),
    ("tumble-gpu", &["tumble-solver", "tumble-shaders"]),
    ("tumble", &["tumble-gpu", "tumble-scenes"]),
    ("tumble-render", &["tumble"]),
];

/// True for the engine's crates, the only ones the rule constrains (xtask, tests, benches
/// and external crates may import anything).
pub fn is_engine_crate(name: &str) -> bool {
    ARROWS.iter().any(|(n, _)| *n == name)
}

/// Whether `from` may import `to` (both engine crates): `to` is below `from` along the arrows.
pub fn may_import(from: &str, to: &str) -> bool {
    let below = |name: &str| -> &'static [&'static str] {
        ARROWS
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(&[], |(_, b)| *b)
    };
    let mut stack: Vec<&str> = below(from).to_vec();
    let mut seen: Vec<&str> = Vec::new();
    while let Some(next) = stack.pop() {
        if next == to {
            return true;
        }
        if !seen.contains(&next) {
            seen.push(next);
            stack.extend_from_slice(below(next));
        }
    }
    false
}

/// One dependency edge: `from` depends on `to` (`dev` for dev-dependencies).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edge {
    /// The depending package.
    pub from: String,
    /// The package depended on.
    pub to: String,
    /// True for a dev-dependency (tests and examples only).
    pub dev: bool,
}

/// The edges that break the rule, as human-readable lines. Dev-dependencies are held to the
/// same rule: a lower crate's tests that need a higher one belong in `tests/`.
pub fn violations(edges: &[Edge]) -> Vec<String> {
    edges
        .iter()
        .filter(|e| is_engine_crate(&e.from) && is_engine_crate(&e.to))
        .filter(|e| !may_import(&e.from, &e.to))
        .map(|e| {
            format!(
                "{} {}depends on {}, which is not below it in the layer diagram of docs/architecture.md",
                e.from,
                if e.dev { "dev-" } else { "" },
                e.to
            )
        })
        .collect()
}

/// Reads the edges out of `cargo metadata --no-deps --format-version 1` output.
pub fn edges_from_metadata(json: &serde_json::Value) -> Result<Vec<Edge>, String> {
    let packages = json["packages"]
        .as_array()
        .ok_or("cargo metadata: no `packages` array")?;
    let mut edges = Vec::new();
    for p in packages {
        let from = p["name"]
            .as_str()
            .ok_or("cargo metadata: package without a name")?;
        for d in p["dependencies"].as_array().into_iter().flatten() {
            let to = d["name"]
                .as_str()
                .ok_or("cargo metadata: dependency without a name")?;
            edges.push(Edge {
                from: from.to_string(),
                to: to.to_string(),
                dev: d["kind"].as_str() == Some("dev"),
            });
        }
    }
    Ok(edges)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge(from: &str, to: &str) -> Edge {
        Edge {
            from: from.into(),
            to: to.into(),
            dev: false,
        }
    }

    #[test]
    fn downward_imports_pass_and_rightward_or_sideways_ones_fail() {
        let ok = [
            edge("tumble-broad", "tumble-geometry"),
            edge("tumble-solver", "tumble-narrow"),
            edge("tumble", "tumble-scenes"),
            edge("tumble", "tumble-geometry"),
            edge("tumble-gpu", "tumble-narrow"),
            edge("tumble-gpu", "wgpu"),
            edge("xtask", "tumble"),
        ];
        assert!(violations(&ok).is_empty());
        let bad = [
            edge("tumble-geometry", "tumble-solver"),
            edge("tumble-broad", "tumble-narrow"),
            edge("tumble-gpu", "tumble-scenes"),
        ];
        let v = violations(&bad);
        assert_eq!(v.len(), 3, "{v:?}");
        assert!(
            v[0].starts_with("tumble-geometry depends on tumble-solver"),
            "{}",
            v[0]
        );
        // Scene data is the facade's input, not the GPU layer's.
        assert!(
            v[2].starts_with("tumble-gpu depends on tumble-scenes"),
            "{}",
            v[2]
        );
    }

    #[test]
    fn metadata_edges_keep_the_dependency_kind() {
        let json = serde_json::json!({"packages": [
            {"name": "tumble-narrow", "dependencies": [
                {"name": "tumble-geometry", "kind": null},
                {"name": "tumble", "kind": "dev"}
            ]}
        ]});
        let edges = edges_from_metadata(&json).unwrap();
        assert_eq!(edges.len(), 2);
        assert!(edges[1].dev);
        let v = violations(&edges);
        assert_eq!(v.len(), 1);
        assert!(
            v[0].starts_with("tumble-narrow dev-depends on tumble,"),
            "{}",
            v[0]
        );
    }
}
