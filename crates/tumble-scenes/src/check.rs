//! A scene's pass criterion, as data.
//!
//! Every check is measured on the dynamic bodies only (fixed and kinematic bodies are inputs,
//! not outcomes), over the scene's default run of `steps` steps, and also requires every pose
//! to stay finite.

use serde::{Deserialize, Serialize};
use tumble_geometry::Real;

/// What a scene must satisfy to pass.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", deny_unknown_fields)]
pub enum SceneCheck {
    /// No criterion beyond every pose staying finite.
    #[default]
    Finite,
    /// Resting structures (stacks, pyramids, walls): at every step, each dynamic body's centre
    /// stays within `meters` of its initial centre horizontally (the x-z plane). Vertical
    /// settling into contact is not counted; sideways creep and collapse are.
    MaxDrift {
        /// Largest allowed horizontal displacement, in meters.
        meters: Real,
    },
    /// Each dynamic body's centre stays within `meters` of its initial centre in 3D, at every
    /// step (bodies that must neither sink, slide nor tip).
    StaysPut {
        /// Largest allowed displacement, in meters.
        meters: Real,
    },
    /// Fast bodies must not pass through thin ones: each dynamic body's centre stays at or
    /// above height `min_y` at every step.
    NoTunneling {
        /// Lowest allowed centre height, in meters.
        min_y: Real,
    },
    /// A body released from rest slides down a ramp with constant acceleration: the mean
    /// acceleration along `direction` over the run, `2 d / t^2` from the displacement `d`
    /// along `direction` after time `t`, is within `tolerance` of `expected_acceleration`
    /// (for each dynamic body). An expected acceleration of zero means the body must stick.
    Slides {
        /// Unit vector pointing down the slope.
        direction: [Real; 3],
        /// Coulomb's prediction, `g (sin a - mu cos a)` when it is positive, else zero, in m/s^2.
        expected_acceleration: Real,
        /// Allowed absolute error, in m/s^2.
        tolerance: Real,
    },
    /// With no gravity and no contacts, the total angular momentum of the dynamic bodies
    /// (about their own centres, in world axes) stays within `rel_tol` of its initial value
    /// (relative to its initial magnitude), at every step.
    AngularMomentum {
        /// Allowed relative change of the angular momentum vector.
        rel_tol: Real,
    },
    /// Bodies created overlapping are pushed apart without exploding: at the end of the run no
    /// two dynamic bodies overlap by more than `max_depth` (the separating-axis penetration of
    /// the two boxes) and no dynamic body moves faster than `max_speed`.
    Separates {
        /// Largest allowed final penetration, in meters.
        max_depth: Real,
        /// Largest allowed final speed of any body centre, in m/s.
        max_speed: Real,
    },
    /// Each dynamic body's centre stays inside the box `[min, max]` at every step (pools,
    /// containers).
    Contained {
        /// Lower corner of the allowed region.
        min: [Real; 3],
        /// Upper corner of the allowed region.
        max: [Real; 3],
    },
    /// Every dynamic body ends the run tilted by at least `min_tilt_deg` from its initial
    /// orientation (its local up axis against its initial up axis): a domino chain fell all
    /// the way.
    Topples {
        /// Smallest final tilt, in degrees.
        min_tilt_deg: Real,
    },
    /// Every one of `checks` must pass.
    All {
        /// The checks, all required.
        checks: Vec<SceneCheck>,
    },
}
