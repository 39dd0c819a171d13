//! Runs one engine through one scene: steps it, times every step, and measures the states.

use std::collections::BTreeMap;
use std::time::Instant;

use crate::engine::{BodyState, Engine};
use crate::metrics::{MetricsRecorder, RunMetrics};
use crate::scene_info::SceneInfo;
use crate::timing::{StepTiming, median};

/// What one run produced.
#[derive(Clone, Debug, Default)]
pub struct RunOutcome {
    /// Accuracy, measured from the states after every step.
    pub metrics: RunMetrics,
    /// Wall time of `step()` alone (measuring is not counted).
    pub timing: StepTiming,
    /// Median wall time per named stage, in milliseconds, when the engine reports stages.
    pub stage_ms: BTreeMap<String, f64>,
    /// Deepest penetration the engine itself reported over the run, if it reports any.
    pub reported_max_penetration: Option<f32>,
    /// Why the run stopped early, if it did.
    pub error: Option<String>,
}

/// Steps `engine` `steps` times over `scene`, measuring after every step. `should_rest` marks
/// the bodies whose motion counts as jitter; `observe` sees the states after every step (the
/// scene's pass check listens there).
pub fn run_engine(
    engine: &mut dyn Engine,
    scene: &SceneInfo,
    should_rest: Vec<bool>,
    steps: usize,
    observe: &mut dyn FnMut(&[BodyState]),
) -> RunOutcome {
    let mut states = Vec::with_capacity(scene.bodies.len());
    engine.read_states(&mut states);
    let mut recorder = MetricsRecorder::new(scene, &states, should_rest, steps);
    let mut step_ms = Vec::with_capacity(steps);
    let mut stages: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let mut reported: Option<f32> = None;
    let mut error = None;
    for _ in 0..steps {
        let start = Instant::now();
        let result = engine.step();
        step_ms.push(start.elapsed().as_secs_f64() * 1e3);
        if let Err(e) = result {
            error = Some(e);
            break;
        }
        for stage in engine.stage_times() {
            stages.entry(stage.name).or_default().push(stage.ms);
        }
        if let Some(p) = engine.reported_max_penetration() {
            reported = Some(reported.map_or(p, |r| r.max(p)));
        }
        engine.read_states(&mut states);
        recorder.record(&states);
        observe(&states);
        // Once every body is lost to NaN nothing more can be learned, and NaN arithmetic can
        // be very slow; stop.
        if !states.is_empty() && states.iter().all(|s| !s.is_finite()) {
            error = Some("every body became non-finite".into());
            break;
        }
    }
    RunOutcome {
        metrics: recorder.finish(),
        timing: StepTiming::from_samples(&step_ms),
        stage_ms: stages.into_iter().map(|(k, v)| (k, median(&v))).collect(),
        reported_max_penetration: reported,
        error,
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::engine::StageTime;
    use crate::scene_info::BodyInfo;
    use tumble_geometry::{Pose, Vec3};

    /// A contact-free engine: bodies fall ballistically with symplectic Euler. Enough to check
    /// that the runner times, measures and reports what happened.
    pub(crate) struct Ballistic {
        pub gravity: Vec3,
        pub dt: f32,
        pub states: Vec<BodyState>,
        pub dynamic: Vec<bool>,
    }

    impl Engine for Ballistic {
        fn step(&mut self) -> Result<(), String> {
            for (s, &d) in self.states.iter_mut().zip(&self.dynamic) {
                if d {
                    s.linear_velocity += self.gravity * self.dt;
                    s.pose.translation.vector += s.linear_velocity * self.dt;
                }
            }
            Ok(())
        }

        fn read_states(&self, out: &mut Vec<BodyState>) {
            out.clear();
            out.extend_from_slice(&self.states);
        }

        fn stage_times(&self) -> Vec<StageTime> {
            vec![StageTime {
                name: "solve".into(),
                ms: 0.25,
            }]
        }
    }

    #[test]
    fn a_free_falling_box_never_rests_and_loses_no_energy() {
        let start = Pose::translation(0.0, 100.0, 0.0);
        let scene = SceneInfo {
            name: "drop".into(),
            bodies: vec![BodyInfo::cuboid(true, Vec3::new(0.5, 0.5, 0.5), 1.0, start)],
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: 1.0 / 60.0,
        };
        let mut engine = Ballistic {
            gravity: scene.gravity,
            dt: scene.dt,
            states: vec![BodyState {
                pose: start,
                linear_velocity: Vec3::zeros(),
                angular_velocity: Vec3::zeros(),
            }],
            dynamic: vec![true],
        };
        let mut observed = 0;
        let out = run_engine(&mut engine, &scene, vec![true], 60, &mut |_| observed += 1);
        assert_eq!(observed, 60);
        assert!(out.error.is_none());
        assert_eq!(out.metrics.steps, 60);
        assert_eq!(out.stage_ms.get("solve"), Some(&0.25));
        // After 1 s of fall it moves at about 9.8 m/s: never at rest, and all of the last
        // second's speed is jitter for a body that should have rested.
        assert_eq!(out.metrics.time_to_rest, None);
        let jitter = out.metrics.jitter_rms.expect("the box should rest");
        assert!(jitter > 4.0, "{jitter}");
        // Symplectic Euler loses exactly m g^2 dt^2 n / 2 of energy over n steps (it falls
        // g dt^2 / 2 per step further than its speed accounts for). The scale of a lone box
        // is m g h with h = 0.5 m, its centre's height above its own underside, so the
        // relative drift is -g dt^2 n / (2 h) = -0.1635. 1e-4 is f64 summation of f32 states.
        let g = 9.81_f64;
        let dt = f64::from(scene.dt);
        let expected = -g * dt * dt * 60.0 / (2.0 * 0.5);
        let drift = out.metrics.energy_drift.expect("gravity gives a scale");
        assert!((drift - expected).abs() < 1e-4, "{drift} vs {expected}");
        assert_eq!(out.metrics.max_drift, 0.0);
        assert!(out.timing.median_ms >= 0.0);
        let y = engine.states[0].pose.translation.y;
        assert!((y - (100.0 - 0.5 * 9.81)).abs() < 0.1, "{y}");
    }
}
