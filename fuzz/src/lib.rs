//! What the fuzz targets share: how numbers are decoded from the fuzzer's bytes.
//!
//! A number is either an arbitrary `f32` bit pattern (NaN, infinities, subnormals, the extremes)
//! or a small fixed-point value, optionally scaled by a power of two: raw bits alone would almost
//! never give two boxes that touch or a body that lands on another, so the fuzzer could not
//! reach the contact code; the scaled form reaches tiny, huge and subnormal values that still
//! have structure (a 1e-30 m box resting on a 1e-30 m box).

use arbitrary::Arbitrary;

/// One `f32` as the fuzzer chose it.
#[derive(Arbitrary, Clone, Copy, Debug)]
pub enum Num {
    /// Any bit pattern.
    Raw(f32),
    /// `v / 64`: -512 to 512 in steps of 1/64, so exact ties and touching boxes occur.
    Small(i16),
    /// `v / 64 * 2^(e mod 288 - 160)`: from subnormal (and zero) to beyond `f32::MAX`.
    Scaled(i16, i16),
}

impl Num {
    /// The value.
    pub fn get(self) -> f32 {
        match self {
            Num::Raw(x) => x,
            Num::Small(v) => f32::from(v) / 64.0,
            Num::Scaled(v, e) => {
                // In f64, so that the scale itself neither overflows nor flushes early.
                let e = i32::from(e).rem_euclid(288) - 160;
                (f64::from(v) / 64.0 * 2f64.powi(e)) as f32
            }
        }
    }
}

/// Three numbers.
pub fn vec3(v: [Num; 3]) -> [f32; 3] {
    v.map(Num::get)
}

/// Four numbers.
pub fn vec4(v: [Num; 4]) -> [f32; 4] {
    v.map(Num::get)
}

/// Whether the known finding `name` is to be let through: `TUMBLE_FUZZ_SKIP` holds a comma-
/// separated list of them (e.g. `nonfinite,scene-refused`). A finding that is recorded in
/// docs/reliability.md but not yet fixed would otherwise stop every run within seconds, and
/// nothing past it would be fuzzed; by default nothing is skipped.
pub fn skipped(name: &str) -> bool {
    static SKIP: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    SKIP.get_or_init(|| {
        std::env::var("TUMBLE_FUZZ_SKIP")
            .unwrap_or_default()
            .split(',')
            .map(|s| s.trim().to_owned())
            .filter(|s| !s.is_empty())
            .collect()
    })
    .iter()
    .any(|s| s == name)
}
