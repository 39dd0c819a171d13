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

/// A complete simulation setup, loadable from and savable to JSON.
///
/// Conventions every engine running a scene follows: SI units, y up, quaternions `[x, y, z, w]`,
/// angular velocities in world axes; materials of a touching pair combine by the geometric
/// mean for friction (`sqrt(mu_a * mu_b)`, as Box2D) and the maximum for restitution; no
/// contact skin (boxes touch face to face), speculative contacts within the engine's margin.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scene {
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
            name: name.into(),
            description: description.into(),
            gravity: default_gravity(),
            dt: DEFAULT_DT,
            steps: DEFAULT_STEPS,
            bodies: Vec::new(),
            check: SceneCheck::Finite,
        }
    }

    /// Parses a scene from JSON and validates it.
    pub fn from_json(text: &str) -> Result<Scene, SceneError> {
        let scene: Scene = serde_json::from_str(text)?;
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
