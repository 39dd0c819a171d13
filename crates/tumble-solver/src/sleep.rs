//! Sleep thresholds shared by every backend: the CPU step's islands and the GPU's sleep
//! kernels read the same values, so a scene falls asleep after the same number of steps on
//! both. The values are Box2D's (`b2_timeToSleep`, `b2_linearSleepTolerance`,
//! `b2_angularSleepTolerance` in Box2D v2.4's `b2_settings.h`).

use tumble_geometry::Real;

/// Box2D's `b2_timeToSleep`: an island sleeps after half a second at rest.
pub const TIME_TO_SLEEP: Real = 0.5;

/// Box2D's `b2_linearSleepTolerance`: below 5 cm/s a body counts as resting.
pub const LINEAR_SLEEP_TOLERANCE: Real = 0.05;

/// Box2D's `b2_angularSleepTolerance`: below 2 degrees per second a body counts as resting.
pub const ANGULAR_SLEEP_TOLERANCE: Real = 2.0 / 180.0 * std::f32::consts::PI;

/// True when a body moving at `linear_speed` and `angular_speed` (m/s, rad/s) counts as resting:
/// strictly below both tolerances, the test the CPU step and the GPU kernels both make.
pub fn is_resting(linear_speed: Real, angular_speed: Real) -> bool {
    linear_speed < LINEAR_SLEEP_TOLERANCE && angular_speed < ANGULAR_SLEEP_TOLERANCE
}
