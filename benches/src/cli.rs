//! Command-line pieces shared by the table binaries (`src/bin/`): the scene-name parser, the
//! count parser, the pool's size flags and the median of timed steps. Every binary parses
//! with clap, so `--help`
//! lists its flags with their defaults, and an unknown flag or value is an error naming it
//! (a typo never falls back to a default).

use std::fmt;
use std::str::FromStr;
use std::time::Duration;

use clap::Args;
use clap::builder::RangedU64ValueParser;
use tumble_scenes::{Scene, builders};

/// A scene of `tumble_scenes::builders`, named by its family and size: `stack20` (a column of
/// 20 cubes), `pyramid24` (a pyramid 24 cubes high), `pool1000` (1,000 cubes dropped in a
/// walled pool).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneName {
    /// `stackN`: a column of `N` unit cubes.
    Stack(usize),
    /// `pyramidH`: a pyramid `H` cubes high.
    Pyramid(usize),
    /// `poolN`: `N` cubes dropped into a walled pool.
    Pool(usize),
}

/// The scene families [`SceneName`] knows, as `--help` shows them.
pub const SCENE_FAMILIES: &str = "stackN, pyramidH or poolN (e.g. stack20, pyramid24, pool1000)";

impl SceneName {
    /// The scene.
    pub fn build(self) -> Scene {
        match self {
            SceneName::Stack(n) => builders::stack(n),
            SceneName::Pyramid(h) => builders::pyramid(h),
            SceneName::Pool(n) => builders::pool(n),
        }
    }
}

impl FromStr for SceneName {
    type Err = String;

    /// `stackN`, `pyramidH` or `poolN` with a size of at least 1; anything else is an error
    /// naming the value and the families.
    fn from_str(name: &str) -> Result<Self, String> {
        type Family = (&'static str, fn(usize) -> SceneName);
        let families: [Family; 3] = [
            ("stack", SceneName::Stack),
            ("pyramid", SceneName::Pyramid),
            ("pool", SceneName::Pool),
        ];
        for (prefix, make) in families {
            if let Some(size) = name.strip_prefix(prefix) {
                return match size.parse::<usize>() {
                    Ok(n) if n >= 1 => Ok(make(n)),
                    _ => Err(format!(
                        "unknown scene {name:?}: {prefix} takes a size of at least 1, as in \
                         {prefix}20"
                    )),
                };
            }
        }
        Err(format!("unknown scene {name:?}: expected {SCENE_FAMILIES}"))
    }
}

impl fmt::Display for SceneName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneName::Stack(n) => write!(f, "stack{n}"),
            SceneName::Pyramid(h) => write!(f, "pyramid{h}"),
            SceneName::Pool(n) => write!(f, "pool{n}"),
        }
    }
}

/// A count of at least 1 (cubes, steps, seconds, sizes): 0 is an error, not an empty table.
pub fn count() -> RangedU64ValueParser<usize> {
    RangedU64ValueParser::<usize>::new().range(1..)
}

/// The size of a pool run: how many cubes, and how many timed steps.
#[derive(Args, Clone, Copy, Debug)]
pub struct PoolSize {
    /// Cubes in the pool.
    #[arg(long, default_value_t = 1000, value_parser = count())]
    pub cubes: usize,
    /// Timed steps per world (after the warm-up steps, or once the pool sleeps).
    #[arg(long, default_value_t = 40, value_parser = count())]
    pub steps: usize,
}

/// The median of step times `t` (the upper one of an even count).
pub fn median(mut t: Vec<Duration>) -> Duration {
    t.sort();
    t[t.len() / 2]
}

/// `d` in milliseconds.
pub fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_names_parse_to_their_family_and_size_and_print_back() {
        for (text, name) in [
            ("stack20", SceneName::Stack(20)),
            ("pyramid24", SceneName::Pyramid(24)),
            ("pool1000", SceneName::Pool(1000)),
        ] {
            assert_eq!(text.parse::<SceneName>(), Ok(name));
            assert_eq!(name.to_string(), text);
        }
        // The built scene is the one named: a floor and 20 cubes.
        assert_eq!(SceneName::Stack(20).build().dynamic_count(), 20);
    }

    #[test]
    fn misspelt_or_sizeless_scene_names_are_errors_naming_the_value() {
        for bad in [
            "stak20", "pyramid", "pyramid0", "stack-3", "pool1k", "", "Stack20",
        ] {
            let err = bad.parse::<SceneName>().unwrap_err();
            assert!(err.contains(&format!("{bad:?}")), "{bad}: {err}");
        }
    }
}
