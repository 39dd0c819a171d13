//! A scene: bodies, gravity, time step, how long it runs, and what it must satisfy.

use serde::{Deserialize, Serialize};
use tumble_geometry::Real;

use crate::{BodySpec, SceneCheck, SceneError};

/// Standard gravity, m/s^2, along -y.
pub const STANDARD_GRAVITY: Real = 9.81;
/// Default time step: 60 Hz, the rate games and the thesis's demos step at.
pub const DEFAULT_DT: Real = 1.0 / 60.0;
/// Default run length: 10 s at 60 Hz, long enough for slow creep in stacks to show.
pub const DEFAULT_STEPS: u32 = 600;
/// The scene file format this crate reads and writes. A file without a `version` field is
/// read as version 1 (the format before the field existed, which it equals); any other
/// version is refused with [`SceneError::UnsupportedVersion`].
pub const FORMAT_VERSION: u32 = 1;

/// A complete simulation setup, loadable from and savable to JSON.
///
/// Conventions every engine running a scene follows: SI units, y up, quaternions `[x, y, z, w]`,
/// angular velocities in world axes; materials of a touching pair combine by the geometric
/// mean for friction (`sqrt(mu_a * mu_b)`, as Box2D) and the maximum for restitution; no
/// contact skin (boxes touch face to face), speculative contacts within the engine's margin.
///
/// Fields the schema does not know are refused (a misspelt `frcition` is an error naming it,
/// never a silent default).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// The file format, [`FORMAT_VERSION`] (1 when the file omits it).
    #[serde(default = "default_version")]
    pub version: u32,
    /// Short identifier, e.g. `pyramid_12`.
    pub name: String,
    /// What the scene exercises, one sentence.
    #[serde(default)]
    pub description: String,
    /// Gravity acceleration vector, m/s^2.
    #[serde(default = "default_gravity")]
    pub gravity: [Real; 3],
    /// Time step, seconds.
    #[serde(default = "default_dt")]
    pub dt: Real,
    /// How many steps the scene runs by default.
    #[serde(default = "default_steps")]
    pub steps: u32,
    /// The bodies, in a fixed order that results are reported in.
    pub bodies: Vec<BodySpec>,
    /// The pass criterion.
    #[serde(default)]
    pub check: SceneCheck,
}

fn default_version() -> u32 {
    FORMAT_VERSION
}

fn default_gravity() -> [Real; 3] {
    [0.0, -STANDARD_GRAVITY, 0.0]
}

fn default_dt() -> Real {
    DEFAULT_DT
}

fn default_steps() -> u32 {
    DEFAULT_STEPS
}

impl Scene {
    /// An empty scene with standard gravity, the default time step and run length.
    pub fn new(name: impl Into<String>, description: impl Into<String>) -> Self {
        Self {
            version: FORMAT_VERSION,
            name: name.into(),
            description: description.into(),
            gravity: default_gravity(),
            dt: DEFAULT_DT,
            steps: DEFAULT_STEPS,
            bodies: Vec::new(),
            check: SceneCheck::Finite,
        }
    }

    /// Parses a scene from JSON and validates it. A field the schema does not know, a
    /// version other than [`FORMAT_VERSION`], a missing or mistyped field are errors; those of
    /// a body name its index (`bodies[3]`).
    pub fn from_json(text: &str) -> Result<Scene, SceneError> {
        let scene: Scene = match serde_json::from_str(text) {
            Ok(scene) => scene,
            Err(e) => return Err(locate(text, e)),
        };
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as pretty-printed JSON.
    pub fn to_json(&self) -> String {
        // Serializing plain structs of numbers and strings cannot fail; a NaN becomes `null`,
        // which `from_json` then rejects.
        serde_json::to_string_pretty(self).expect("scene data always serializes")
    }

    /// Number of dynamic bodies.
    pub fn dynamic_count(&self) -> usize {
        self.bodies.iter().filter(|b| b.is_dynamic()).count()
    }

    /// Simulated time of the default run, in seconds.
    pub fn duration(&self) -> Real {
        self.steps as Real * self.dt
    }
}

/// The most precise error for a scene text serde refused with `e`: an unsupported version,
/// or the first body that does not parse on its own (by index); `e` itself otherwise.
fn locate(text: &str, e: serde_json::Error) -> SceneError {
    let Ok(serde_json::Value::Object(fields)) = serde_json::from_str::<serde_json::Value>(text)
    else {
        return e.into();
    };
    if let Some(v) = fields.get("version") {
        if v.as_u64() != Some(u64::from(FORMAT_VERSION)) {
            return SceneError::UnsupportedVersion(v.to_string());
        }
    }
    if let Some(serde_json::Value::Array(bodies)) = fields.get("bodies") {
        for (index, body) in bodies.iter().enumerate() {
            if let Err(source) = BodySpec::deserialize(body) {
                return SceneError::Body { index, source };
            }
        }
    }
    e.into()
}
