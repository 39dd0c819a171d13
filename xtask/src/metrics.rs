//! Accuracy metrics of one run, accumulated step by step from body states alone, so that
//! every engine is measured the same way. docs/validation.md defines each one.

use crate::energy::{energy_scale, total_energy};
use crate::engine::BodyState;
use crate::penetration::measure_penetration;
use crate::scene_info::SceneInfo;

/// Speed below which a body counts as resting, in m/s. It is the point speed (centre speed
/// plus spin times bounding radius); 5 cm/s is the order of the sleep thresholds engines use
/// (Box2D v3's default sleep threshold is 0.05 m/s), so "at rest" here means "would sleep".
pub const REST_SPEED: f32 = 0.05;

/// How long every body must stay below `REST_SPEED` to count as resting, in seconds: Box2D
/// v3 puts a body to sleep after 0.5 s below its threshold (`b2_timeToSleep`), and a body
/// that only passes through zero speed (a bounce, a rocking box) must not count.
pub const REST_HOLD_S: f32 = 0.5;

/// Length of the window at the end of a run over which jitter is measured, in seconds: long
/// enough to hold many solver periods at 60 Hz, short enough to leave the settling out.
pub const JITTER_WINDOW_S: f32 = 1.0;

/// The accuracy of one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunMetrics {
    /// Steps taken.
    pub steps: usize,
    /// Deepest overlap of any pair at any step, in meters.
    pub max_penetration: f32,
    /// Mean overlap over every (step, touching pair), in meters.
    pub mean_penetration: f64,
    /// Largest horizontal displacement of any dynamic body from its rest pose at any step, m.
    pub max_drift: f32,
    /// RMS point speed of the bodies that should rest, over the last `JITTER_WINDOW_S`, m/s;
    /// `None` when the scene has no body that should rest.
    pub jitter_rms: Option<f64>,
    /// `(E_end - E_start) / scale`, signed: negative is dissipation, positive is energy gain.
    pub energy_drift: Option<f64>,
    /// Largest `(E(t) - E_start) / scale` over the run: energy the solver created.
    pub energy_gain_max: Option<f64>,
    /// Time after which every dynamic body stays below `REST_SPEED` until the end, in
    /// seconds; `None` when that quiet end is shorter than `REST_HOLD_S`.
    pub time_to_rest: Option<f32>,
    /// Number of bodies whose state became non-finite (NaN or infinite) at some step.
    pub nan_bodies: usize,
}

/// Accumulates `RunMetrics` over a run, one `record` per step.
pub struct MetricsRecorder<'a> {
    scene: &'a SceneInfo,
    should_rest: Vec<bool>,
    jitter_from_step: usize,
    step: usize,
    energy_start: f64,
    energy_last: f64,
    energy_gain_max: f64,
    scale: Option<f64>,
    penetration_sum: f64,
    penetration_samples: usize,
    jitter_sum_sq: f64,
    jitter_samples: usize,
    last_moving_step: Option<usize>,
    went_non_finite: Vec<bool>,
    metrics: RunMetrics,
}

impl<'a> MetricsRecorder<'a> {
    /// Starts a run of `total_steps` steps from `initial` states; `should_rest[i]` marks the
    /// bodies whose speed counts as jitter (bodies a correct engine keeps still at the end).
    pub fn new(
        scene: &'a SceneInfo,
        initial: &[BodyState],
        should_rest: Vec<bool>,
        total_steps: usize,
    ) -> Self {
        let window_steps = (JITTER_WINDOW_S / scene.dt).round() as usize;
        let energy_start = total_energy(scene, initial);
        Self {
            scene,
            should_rest,
            jitter_from_step: total_steps.saturating_sub(window_steps),
            step: 0,
            energy_start,
            energy_last: energy_start,
            energy_gain_max: 0.0,
            scale: energy_scale(scene, initial),
            penetration_sum: 0.0,
            penetration_samples: 0,
            jitter_sum_sq: 0.0,
            jitter_samples: 0,
            last_moving_step: None,
            went_non_finite: vec![false; scene.bodies.len()],
            metrics: RunMetrics::default(),
        }
    }

    /// Takes in the states after one more step.
    pub fn record(&mut self, states: &[BodyState]) {
        let scene = self.scene;
        let up = scene.up();
        let mut fastest = 0.0_f32;
        for (i, (body, s)) in scene.bodies.iter().zip(states).enumerate() {
            if !body.dynamic {
                continue;
            }
            if !s.is_finite() {
                self.went_non_finite[i] = true;
                continue;
            }
            let offset = s.pose.translation.vector - body.rest_pose.translation.vector;
            let horizontal = (offset - up * offset.dot(&up)).norm();
            self.metrics.max_drift = self.metrics.max_drift.max(horizontal);
            let speed =
                s.linear_velocity.norm() + s.angular_velocity.norm() * body.bounding_radius();
            fastest = fastest.max(speed);
            if self.step >= self.jitter_from_step
                && self.should_rest.get(i).copied().unwrap_or(false)
            {
                self.jitter_sum_sq += f64::from(speed * speed);
                self.jitter_samples += 1;
            }
        }
        if fastest > REST_SPEED {
            self.last_moving_step = Some(self.step);
        }

        let penetration = measure_penetration(scene, states);
        self.metrics.max_penetration = self.metrics.max_penetration.max(penetration.max);
        self.penetration_sum += penetration.sum;
        self.penetration_samples += penetration.touching;

        // Energy is only meaningful while every body is finite.
        if states.iter().all(BodyState::is_finite) {
            self.energy_last = total_energy(scene, states);
            self.energy_gain_max = self
                .energy_gain_max
                .max(self.energy_last - self.energy_start);
        }
        self.step += 1;
    }

    /// The metrics of the run so far.
    pub fn finish(mut self) -> RunMetrics {
        let m = &mut self.metrics;
        m.steps = self.step;
        m.mean_penetration = if self.penetration_samples > 0 {
            self.penetration_sum / self.penetration_samples as f64
        } else {
            0.0
        };
        m.jitter_rms = (self.jitter_samples > 0)
            .then(|| (self.jitter_sum_sq / self.jitter_samples as f64).sqrt());
        m.energy_drift = self
            .scale
            .map(|s| (self.energy_last - self.energy_start) / s);
        m.energy_gain_max = self.scale.map(|s| self.energy_gain_max / s);
        let dt = self.scene.dt;
        let rest_from = self.last_moving_step.map_or(0, |last| last + 1);
        let quiet = (self.step - rest_from) as f32 * dt;
        m.time_to_rest = (self.step > 0 && quiet >= REST_HOLD_S).then_some(rest_from as f32 * dt);
        m.nan_bodies = self.went_non_finite.iter().filter(|&&b| b).count();
        self.metrics
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_info::BodyInfo;
    use tumble_geometry::{Pose, Vec3};

    const DT: f32 = 1.0 / 60.0;

    /// One unit cube resting on a fixed floor whose top is at y = 0.
    fn cube_on_floor() -> SceneInfo {
        SceneInfo {
            name: "cube".into(),
            bodies: vec![
                BodyInfo::cuboid(
                    false,
                    Vec3::new(5.0, 0.5, 5.0),
                    0.0,
                    Pose::translation(0.0, -0.5, 0.0),
                ),
                BodyInfo::cuboid(
                    true,
                    Vec3::new(0.5, 0.5, 0.5),
                    1.0,
                    Pose::translation(0.0, 0.5, 0.0),
                ),
            ],
            gravity: Vec3::new(0.0, -10.0, 0.0),
            dt: DT,
        }
    }

    fn states(pose: Pose, v: Vec3) -> Vec<BodyState> {
        vec![
            BodyState {
                pose: Pose::translation(0.0, -0.5, 0.0),
                linear_velocity: Vec3::zeros(),
                angular_velocity: Vec3::zeros(),
            },
            BodyState {
                pose,
                linear_velocity: v,
                angular_velocity: Vec3::zeros(),
            },
        ]
    }

    /// The metrics of `steps` steps of the cube on the floor, starting at rest, where step `i`
    /// (from 0) ends in `state_after(i)`.
    fn record(steps: usize, mut state_after: impl FnMut(usize) -> Vec<BodyState>) -> RunMetrics {
        let scene = cube_on_floor();
        let start = states(Pose::translation(0.0, 0.5, 0.0), Vec3::zeros());
        let mut rec = MetricsRecorder::new(&scene, &start, vec![false, true], steps);
        for i in 0..steps {
            rec.record(&state_after(i));
        }
        rec.finish()
    }

    #[test]
    fn a_cube_that_never_moves_scores_zero_everywhere() {
        let rest = states(Pose::translation(0.0, 0.5, 0.0), Vec3::zeros());
        let m = record(120, |_| rest.clone());
        assert_eq!(m.steps, 120);
        assert_eq!(m.max_penetration, 0.0);
        assert_eq!(m.max_drift, 0.0);
        assert_eq!(m.jitter_rms, Some(0.0));
        assert_eq!(m.time_to_rest, Some(0.0));
        assert_eq!(m.energy_drift, Some(0.0));
        assert_eq!(m.nan_bodies, 0);
    }

    #[test]
    fn sinking_sliding_cube_reports_depth_drift_energy_loss_and_rest_time() {
        // The cube slides 1 cm/step sideways for 30 steps while sinking 2 mm in, then stops.
        // Drift is the 30 cm slide; penetration the 2 mm; it rests after 30 steps = 0.5 s; its
        // potential energy fell by m g 0.002 = 0.02 J out of a scale of m g 0.5 = 5 J.
        let m = record(120, |i| {
            let step = i + 1;
            let x = 0.01 * step.min(30) as f32;
            let v = if step <= 30 {
                Vec3::new(0.6, 0.0, 0.0)
            } else {
                Vec3::zeros()
            };
            states(Pose::translation(x, 0.498, 0.0), v)
        });
        // f32 positions near 0.5 m round at about 3e-8 m; 1e-6 is far above that.
        assert!((m.max_drift - 0.30).abs() < 1e-6, "{}", m.max_drift);
        assert!(
            (m.max_penetration - 0.002).abs() < 1e-6,
            "{}",
            m.max_penetration
        );
        assert_eq!(m.time_to_rest, Some(30.0 * DT));
        let drift = m.energy_drift.expect("gravity gives a scale");
        assert!((drift + 0.02 / 5.0).abs() < 1e-5, "{drift}");
        // The slide happened before the last second, so there is no jitter.
        assert_eq!(m.jitter_rms, Some(0.0));
    }

    #[test]
    fn jitter_is_the_rms_speed_over_the_last_second_only() {
        // A cube buzzing at 0.1 m/s on every other step of the final 60 steps has an RMS speed
        // of 0.1 / sqrt(2); a fast shake before the window must not count.
        let rest_pose = Pose::translation(0.0, 0.5, 0.0);
        let m = record(120, |step| {
            let v = if step < 60 {
                Vec3::new(3.0, 0.0, 0.0)
            } else if step % 2 == 0 {
                Vec3::new(0.0, 0.1, 0.0)
            } else {
                Vec3::zeros()
            };
            states(rest_pose, v)
        });
        let expected = 0.1 / 2f64.sqrt();
        let jitter = m.jitter_rms.expect("the cube should rest");
        assert!((jitter - expected).abs() < 1e-6, "{jitter}");
        // It buzzes above REST_SPEED until the end; a single still step is no rest.
        assert_eq!(m.time_to_rest, None);
    }

    #[test]
    fn a_body_that_turns_nan_is_counted_once() {
        let nan = Pose::translation(f32::NAN, 0.5, 0.0);
        assert_eq!(record(10, |_| states(nan, Vec3::zeros())).nan_bodies, 1);
    }
}
