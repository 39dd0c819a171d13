//! Judging a run against its scene's check: feed the body states after every step to a
//! `CheckTracker`, then read its `CheckReport`.
//!
//! The tracker only sees plain arrays, so the same code judges Tumble (any backend) and
//! rapier3d runs of a scene.

use std::fmt;

use tumble_geometry::nalgebra::Matrix3;
use tumble_geometry::{Aabb, Real, Vec3};

use crate::penetration::cuboid_penetration;
use crate::{BodySpec, BodyState, Scene, SceneCheck, SceneError};

/// The outcome of one check (and of its sub-checks, for `All`).
#[derive(Clone, Debug, PartialEq)]
pub struct CheckReport {
    /// The check's variant name, e.g. `MaxDrift`.
    pub check: &'static str,
    /// Whether the run satisfied it.
    pub passed: bool,
    /// The measured quantity the check bounds (see `SceneCheck` for each variant's meaning).
    pub measured: Real,
    /// The bound it was compared with.
    pub limit: Real,
    /// A one-line human reading of the numbers.
    pub detail: String,
    /// Reports of the sub-checks of an `All`.
    pub children: Vec<CheckReport>,
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let verdict = if self.passed { "pass" } else { "FAIL" };
        write!(f, "{verdict} {}: {}", self.check, self.detail)?;
        for child in &self.children {
            write!(f, "\n  {child}")?;
        }
        Ok(())
    }
}

/// The running worst value of one check over the steps seen so far.
#[derive(Clone, Debug)]
struct Node {
    check: SceneCheck,
    worst: Real,
    children: Vec<Node>,
}

impl Node {
    fn new(check: &SceneCheck) -> Self {
        let children = match check {
            SceneCheck::All { checks } => checks.iter().map(Node::new).collect(),
            _ => Vec::new(),
        };
        // Checks bounding a minimum start at +inf, the others at 0; both are replaced by the
        // first observation.
        let worst = match check {
            SceneCheck::NoTunneling { .. } => Real::INFINITY,
            _ => 0.0,
        };
        Self {
            check: check.clone(),
            worst,
            children,
        }
    }
}

/// Accumulates what a scene's check needs while the scene runs.
#[derive(Clone, Debug)]
pub struct CheckTracker {
    bodies: Vec<BodySpec>,
    dynamic: Vec<usize>,
    dt: Real,
    initial: Vec<BodyState>,
    last: Vec<BodyState>,
    steps: u32,
    non_finite: usize,
    root: Node,
    initial_momentum: Vec3,
}

impl CheckTracker {
    /// A tracker for `scene`, its initial states taken from the scene itself.
    pub fn new(scene: &Scene) -> Self {
        let initial: Vec<BodyState> = scene.bodies.iter().map(BodyState::initial).collect();
        let dynamic: Vec<usize> = (0..scene.bodies.len())
            .filter(|&i| scene.bodies[i].is_dynamic())
            .collect();
        let initial_momentum = angular_momentum(&scene.bodies, &dynamic, &initial);
        Self {
            bodies: scene.bodies.clone(),
            dynamic,
            dt: scene.dt,
            last: initial.clone(),
            initial,
            steps: 0,
            non_finite: 0,
            root: Node::new(&scene.check),
            initial_momentum,
        }
    }

    /// Records the states after one step, one per scene body in scene order.
    pub fn observe(&mut self, states: &[BodyState]) -> Result<(), SceneError> {
        if states.len() != self.bodies.len() {
            return Err(SceneError::invalid(
                "states.len()",
                states.len(),
                "must equal the scene's body count",
            ));
        }
        self.steps += 1;
        self.non_finite += states.iter().filter(|s| !s.is_finite()).count();
        let momentum = angular_momentum(&self.bodies, &self.dynamic, states);
        let mut root = std::mem::replace(&mut self.root, Node::new(&SceneCheck::Finite));
        self.update(&mut root, states, &momentum);
        self.root = root;
        self.last.clear();
        self.last.extend_from_slice(states);
        Ok(())
    }

    /// Number of steps observed.
    pub fn steps(&self) -> u32 {
        self.steps
    }

    fn update(&self, node: &mut Node, states: &[BodyState], momentum: &Vec3) {
        let dynamic = self.dynamic.iter().map(|&i| (&self.initial[i], &states[i]));
        match &node.check {
            SceneCheck::MaxDrift { .. } => {
                for (s0, s) in dynamic {
                    let dx = s.position[0] - s0.position[0];
                    let dz = s.position[2] - s0.position[2];
                    node.worst = node.worst.max(dx.hypot(dz));
                }
            }
            SceneCheck::StaysPut { .. } => {
                for (s0, s) in dynamic {
                    let d = Vec3::from(s.position) - Vec3::from(s0.position);
                    node.worst = node.worst.max(d.norm());
                }
            }
            SceneCheck::NoTunneling { .. } => {
                for (_, s) in dynamic {
                    node.worst = node.worst.min(s.position[1]);
                }
            }
            SceneCheck::AngularMomentum { .. } => {
                let scale = self.initial_momentum.norm().max(Real::MIN_POSITIVE);
                let rel = (momentum - self.initial_momentum).norm() / scale;
                node.worst = node.worst.max(rel);
            }
            SceneCheck::Contained { min, max } => {
                for (_, s) in dynamic {
                    for k in 0..3 {
                        let out = (min[k] - s.position[k]).max(s.position[k] - max[k]);
                        node.worst = node.worst.max(out);
                    }
                }
            }
            SceneCheck::All { .. } => {
                for child in &mut node.children {
                    self.update(child, states, momentum);
                }
            }
            // Judged on the final states only.
            SceneCheck::Finite
            | SceneCheck::Slides { .. }
            | SceneCheck::Separates { .. }
            | SceneCheck::Topples { .. } => {}
        }
    }

    /// The verdict on everything observed so far. Any non-finite state fails the run,
    /// whatever the check.
    pub fn finish(&self) -> CheckReport {
        let mut report = self.judge(&self.root);
        if self.non_finite > 0 {
            report.passed = false;
            report.detail = format!(
                "{} non-finite body states; {}",
                self.non_finite, report.detail
            );
        }
        report
    }

    fn judge(&self, node: &Node) -> CheckReport {
        let leaf = |check, passed, measured, limit, detail| CheckReport {
            check,
            passed,
            measured,
            limit,
            detail,
            children: Vec::new(),
        };
        let w = node.worst;
        match &node.check {
            SceneCheck::Finite => leaf(
                "Finite",
                true,
                self.non_finite as Real,
                0.0,
                format!("{} steps observed", self.steps),
            ),
            SceneCheck::MaxDrift { meters } => leaf(
                "MaxDrift",
                w <= *meters,
                w,
                *meters,
                format!("largest horizontal drift {w:.4} m (limit {meters} m)"),
            ),
            SceneCheck::StaysPut { meters } => leaf(
                "StaysPut",
                w <= *meters,
                w,
                *meters,
                format!("largest displacement {w:.4} m (limit {meters} m)"),
            ),
            SceneCheck::NoTunneling { min_y } => leaf(
                "NoTunneling",
                w >= *min_y,
                w,
                *min_y,
                format!("lowest centre y {w:.4} m (floor {min_y} m)"),
            ),
            SceneCheck::Slides {
                direction,
                expected_acceleration,
                tolerance,
            } => {
                let (a, err) = self.slide_acceleration(direction, *expected_acceleration);
                leaf(
                    "Slides",
                    err <= *tolerance,
                    a,
                    *tolerance,
                    format!(
                        "acceleration {a:.4} m/s^2, expected {expected_acceleration:.4} \
                         (tolerance {tolerance})"
                    ),
                )
            }
            SceneCheck::AngularMomentum { rel_tol } => leaf(
                "AngularMomentum",
                w <= *rel_tol,
                w,
                *rel_tol,
                format!("largest relative change {w:.5} (limit {rel_tol})"),
            ),
            SceneCheck::Separates {
                max_depth,
                max_speed,
            } => {
                let (depth, speed) = self.final_depth_and_speed();
                leaf(
                    "Separates",
                    depth <= *max_depth && speed <= *max_speed,
                    depth,
                    *max_depth,
                    format!(
                        "final penetration {depth:.4} m (limit {max_depth}), \
                         final speed {speed:.4} m/s (limit {max_speed})"
                    ),
                )
            }
            SceneCheck::Contained { .. } => leaf(
                "Contained",
                w <= 0.0,
                w,
                0.0,
                format!("largest excursion outside the region {w:.4} m"),
            ),
            SceneCheck::Topples { min_tilt_deg } => {
                let tilt = self.smallest_final_tilt_deg();
                leaf(
                    "Topples",
                    tilt >= *min_tilt_deg,
                    tilt,
                    *min_tilt_deg,
                    format!("least tilted body {tilt:.2} deg (needs {min_tilt_deg})"),
                )
            }
            SceneCheck::All { .. } => {
                let children: Vec<CheckReport> =
                    node.children.iter().map(|c| self.judge(c)).collect();
                let failed = children.iter().filter(|c| !c.passed).count();
                CheckReport {
                    check: "All",
                    passed: failed == 0,
                    measured: failed as Real,
                    limit: 0.0,
                    detail: format!("{failed} of {} sub-checks failed", children.len()),
                    children,
                }
            }
        }
    }

    /// Mean acceleration `2 d / t^2` along `direction` of the dynamic body farthest from
    /// `expected`, with its error. NaN when no step was observed.
    fn slide_acceleration(&self, direction: &[Real; 3], expected: Real) -> (Real, Real) {
        let t = self.steps as Real * self.dt;
        let dir = Vec3::from(*direction);
        let mut worst = (Real::NAN, Real::NAN);
        for &i in &self.dynamic {
            let d = (Vec3::from(self.last[i].position) - Vec3::from(self.initial[i].position))
                .dot(&dir);
            let a = 2.0 * d / (t * t);
            let err = (a - expected).abs();
            // A NaN error (no steps) must still be reported, so NaN never counts as better.
            if worst.1.is_nan() || err > worst.1 {
                worst = (a, err);
            }
        }
        worst
    }

    /// Deepest overlap between any two dynamic bodies, and the fastest dynamic body's speed,
    /// in the last observed states.
    fn final_depth_and_speed(&self) -> (Real, Real) {
        let shapes: Vec<_> = self
            .dynamic
            .iter()
            .map(|&i| {
                let pose = self.last[i].pose();
                let cuboid = self.bodies[i].cuboid();
                (cuboid, pose, Aabb::from_cuboid(&cuboid, &pose, 0.0))
            })
            .collect();
        let mut depth: Real = 0.0;
        for (k, (ca, pa, aa)) in shapes.iter().enumerate() {
            for (cb, pb, ab) in &shapes[k + 1..] {
                if aa.intersects(ab) {
                    depth = depth.max(cuboid_penetration(ca, pa, cb, pb));
                }
            }
        }
        let speed = self
            .dynamic
            .iter()
            .map(|&i| Vec3::from(self.last[i].linear_velocity).norm())
            .fold(0.0, Real::max);
        (depth, speed)
    }

    /// The smallest angle, in degrees, between a dynamic body's local up axis now and at the
    /// start (infinite when there are no dynamic bodies, so the check holds vacuously).
    fn smallest_final_tilt_deg(&self) -> Real {
        self.dynamic
            .iter()
            .map(|&i| {
                let up0 = self.initial[i].rot() * Vec3::y();
                let up = self.last[i].rot() * Vec3::y();
                up0.dot(&up).clamp(-1.0, 1.0).acos().to_degrees()
            })
            .fold(Real::INFINITY, Real::min)
    }
}

/// Total spin angular momentum `sum R I R^T w` of the dynamic bodies, each about its own
/// centre (the orbital part is left out: the check is for free bodies in zero gravity).
fn angular_momentum(bodies: &[BodySpec], dynamic: &[usize], states: &[BodyState]) -> Vec3 {
    dynamic
        .iter()
        .map(|&i| {
            let h = Vec3::from(bodies[i].half_extents);
            let m = bodies[i].mass();
            // Solid box about its centre: I_x = m (h_y^2 + h_z^2) / 3 in half extents.
            let inertia = Vec3::new(
                h.y * h.y + h.z * h.z,
                h.x * h.x + h.z * h.z,
                h.x * h.x + h.y * h.y,
            ) * (m / 3.0);
            let r = states[i].rot().to_rotation_matrix().into_inner();
            let world: Matrix3<Real> = r * Matrix3::from_diagonal(&inertia) * r.transpose();
            world * Vec3::from(states[i].angular_velocity)
        })
        .fold(Vec3::zeros(), |acc, l| acc + l)
}
