//! The layer rule of DESIGN.md: the engine's crates form a strict order and a crate never
//! imports one to its right.
//!
//! ```text
//! tumble-geometry <- tumble-broad  <- tumble-solver <- tumble-gpu <- tumble (facade)
//!                 <- tumble-narrow <-'                                  |
//!                 <- tumble-scenes (scene data) <-----------------------'
//! ```

/// Each engine crate with its layer: a crate may depend only on crates of a lower layer
/// (siblings of one layer, such as the broad and narrow phases, stay independent).
pub const LAYERS: [(&str, u32); 7] = [
    ("tumble-geometry", 0),
    ("tumble-broad", 1),
    ("tumble-narrow", 1),
    ("tumble-scenes", 1),
    ("tumble-solver", 2),
    ("tumble-gpu", 3),
    ("tumble", 4),
];

/// The layer of an engine crate, `None` for anything else (xtask, tests, benches, external
/// crates), which the rule does not constrain.
pub fn layer_of(name: &str) -> Option<u32> {
    LAYERS.iter().find(|(n, _)| *n == name).map(|&(_, l)| l)
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
        .filter_map(|e| {
            let (from, to) = (layer_of(&e.from)?, layer_of(&e.to)?);
            (to >= from).then(|| {
                format!(
                    "{} (layer {from}) {}depends on {} (layer {to}): a crate may only import crates of a lower layer",
                    e.from,
                    if e.dev { "dev-" } else { "" },
                    e.to
                )
            })
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
        assert!(v[0].contains("tumble-geometry") && v[0].contains("tumble-solver"));
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
        assert!(v[0].contains("dev-depends on tumble "), "{}", v[0]);
    }
}
