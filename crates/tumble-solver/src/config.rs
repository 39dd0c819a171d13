//! Solver settings: which algorithm, how many iterations, and the soft-contact tuning.

use tumble_geometry::Real;

use crate::{InvalidParameter, Softness};

/// Which velocity solver runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SolverKind {
    /// The thesis's projected Gauss-Seidel: one step, `iterations` passes, position error fed
    /// back as a velocity bias `-beta / dt * max(depth - slop, 0)`.
    Baumgarte,
    /// Box2D v3's soft step: substeps, soft contacts (hertz, damping ratio), relax passes.
    SoftStep,
}

/// The order in which constraints are visited inside one pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SolveOrder {
    /// Reference Gauss-Seidel: constraints in manifold order, one at a time.
    Sequential,
    /// Graph colors one after another; the constraints of one color in parallel (they share no
    /// dynamic body), then the overflow set sequentially. The CPU colors greedily, top of a
    /// pile first ([`crate::stages::top_down_order`]).
    Colored,
    /// As [`SolveOrder::Colored`], with the colors of the GPU's algorithm: parallel rounds under
    /// hashed priorities ([`crate::color_in_rounds`], without the GPU's seeding by last step's
    /// colors). With one velocity pass per substep the visiting order moves the trajectory of
    /// an impact by millimetres, so this is the order to compare `Backend::Gpu` against; the
    /// top-down order holds piles better and stays the CPU's default.
    ColoredInRounds,
}

/// How the passes visit the constraints of a graph color.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SolveKernel {
    /// Blocks of [`crate::LANES`] constraints of a color solved side by side, one vector instruction
    /// per arithmetic step (`lanes/`), on AVX2 when detected at run time (the build's baseline
    /// instructions otherwise). The same bits as `Scalar`.
    #[default]
    Lanes,
    /// The lane kernels on the instructions the build targets only (no run-time detection).
    /// The same bits.
    PortableLanes,
    /// One constraint at a time (`contact_solver.rs`): the reference the lanes are tested
    /// against, and the kernel of the overflow set and of the sequential order in any case.
    Scalar,
}

/// Which velocity passes solve the friction rows.
///
/// A pass visits a manifold's normal rows, the tilt rows of a face patch, the friction rows,
/// and then, for a face patch unless every point slides, the normal and tilt rows once more
/// ([`crate::solve_contact`]). With [`FrictionPasses::RelaxOnly`] the biased passes stop
/// after the first normal and tilt rows: friction and the second visit run in the relax
/// passes only, as in rapier3d (`friction_in_bias_pass = false`, its default; Box2D v3 solves
/// friction in both passes, as `Every` does). docs/solver.md, "Friction in the relax passes
/// only", has the measurements.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum FrictionPasses {
    /// Friction rows in every biased and relax pass (the default).
    #[default]
    Every,
    /// Friction rows, and a face patch's second visit, in the relax passes only: fewer rows
    /// per substep, for a little more drift in tall piles. Needs at least one relax pass.
    RelaxOnly,
}

/// Everything the solver stage needs besides bodies and contacts.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SolverConfig {
    /// Baumgarte PGS or soft step.
    pub kind: SolverKind,
    /// Biased velocity passes per substep.
    pub iterations: u32,
    /// Substeps per step (the Baumgarte solver honours it too; its default is 1).
    pub substeps: u32,
    /// Unbiased (relax) passes per substep, soft step only.
    pub relax_iterations: u32,
    /// Start each substep from last step's impulses, matched by feature id.
    pub warm_start: bool,
    /// Sequential or colored visiting order.
    pub order: SolveOrder,
    /// Soft contact stiffness in Hz (capped at a quarter of the substep rate; contacts with a
    /// fixed or kinematic body get twice this, within the same cap).
    pub contact_hertz: Real,
    /// Soft contact damping ratio (dimensionless; > 1 is over-damped).
    pub damping_ratio: Real,
    /// Largest separation speed, m/s, the position correction may add (push-out cap).
    pub max_push_out: Real,
    /// Baumgarte factor `beta` in `[0, 1]`: the fraction of the penetration removed per step.
    pub baumgarte: Real,
    /// Penetration in m the Baumgarte bias tolerates, so resting contacts do not jitter.
    pub slop: Real,
    /// Approach speed in m/s below which restitution is ignored (resting contacts stay put).
    pub restitution_threshold: Real,
    /// Colors with at least this many constraints are solved on the rayon pool.
    pub parallel_threshold: u32,
    /// How a color's constraints are visited: side by side in vector lanes (the default) or
    /// one at a time. Every kernel gives the same bits; only the time differs.
    #[cfg_attr(feature = "serde", serde(default))]
    pub kernel: SolveKernel,
    /// Which passes solve the friction rows: every pass (the default) or the relax passes
    /// only.
    #[cfg_attr(feature = "serde", serde(default))]
    pub friction_passes: FrictionPasses,
}

/// Contact stiffness: 60 Hz, a sixth of the default substep rate (6 substeps of a 60 Hz step);
/// contacts with fixed bodies get twice this within the quarter-rate cap (90 Hz). Box2D v3
/// defaults to 30 Hz at 4 substeps (`b2DefaultWorldDef`). A soft contact settles
/// `load / (m_eff (2 pi hertz)^2)` deep, so the stiffness sets how far light bodies sink under a
/// heavy one: the 100:1 column of `mass_ratio` sinks 147 mm at 30 Hz, 39 mm here
/// (docs/solver.md, "Contacts under load").
pub const DEFAULT_CONTACT_HERTZ: Real = 60.0;
/// Substeps per step of the soft step. Box2D v3 recommends 4; 6 allows [`DEFAULT_CONTACT_HERTZ`]
/// well within the quarter-rate cap (at 4 substeps even the cap, 60 Hz, sinks the 100:1 column
/// 62 mm), for 1.2 to 1.4 times the step time of 4 substeps at 30 Hz.
pub const DEFAULT_SUBSTEPS: u32 = 6;
/// Box2D v3's contact damping ratio: `contactDampingRatio = 10` (heavily over-damped, so
/// contacts push out without bouncing).
pub const DEFAULT_DAMPING_RATIO: Real = 10.0;
/// Box2D v3's push-out speed cap: `maxContactPushSpeed = 3 m/s` (`contactPushMaxVelocity`
/// in earlier v3 releases).
pub const DEFAULT_MAX_PUSH_OUT: Real = 3.0;
/// Box2D v3's restitution threshold: `restitutionThreshold = 1 m/s`.
pub const DEFAULT_RESTITUTION_THRESHOLD: Real = 1.0;
/// The classic Baumgarte factor of Box2D v2 (`b2_baumgarte = 0.2`): removes a fifth of the
/// error per step, stiff enough to hold stacks, soft enough not to add visible energy.
pub const DEFAULT_BAUMGARTE: Real = 0.2;
/// Box2D v2's `b2_linearSlop = 0.005 m`: 5 mm of tolerated overlap keeps resting contacts
/// alive from step to step without correction jitter.
pub const DEFAULT_SLOP: Real = 0.005;
/// Velocity passes of the Baumgarte solver. The thesis ran 150 on the CPU without warm
/// starting. With warm starting and the patch tilt rows, 40 passes hold the 30-cube column and
/// the 650-cube pyramid, but the 100:1 mass ratio needs 60: at 40 the heavy cube knocks the
/// column over in the first second (docs/solver.md has the sweep).
pub const DEFAULT_BAUMGARTE_ITERATIONS: u32 = 60;
/// Two of the staged sweep's blocks of 32 constraints (`sweep.rs`): the workers start once per
/// pass and a color costs them an atomic claim per block and a wait for its last block, so a
/// color worth two blocks already spreads. It was 256 while each parallel color was a rayon
/// hand-off of its own (a few microseconds); with 64 the pyramid of 12 (colors of about 230
/// constraints) takes 3.20 to 3.23 ms per step on two threads instead of 3.53 to 3.57, the
/// same bits (docs/benchmarks.md, "CPU step: colors spread from two blocks on").
pub const DEFAULT_PARALLEL_THRESHOLD: u32 = 64;

impl Default for SolverConfig {
    /// Soft step, [`DEFAULT_SUBSTEPS`] substeps at [`DEFAULT_CONTACT_HERTZ`], 1 iteration, 1
    /// relax pass, warm starting, colored order.
    fn default() -> Self {
        Self {
            kind: SolverKind::SoftStep,
            iterations: 1,
            substeps: DEFAULT_SUBSTEPS,
            relax_iterations: 1,
            warm_start: true,
            order: SolveOrder::Colored,
            contact_hertz: DEFAULT_CONTACT_HERTZ,
            damping_ratio: DEFAULT_DAMPING_RATIO,
            max_push_out: DEFAULT_MAX_PUSH_OUT,
            baumgarte: DEFAULT_BAUMGARTE,
            slop: DEFAULT_SLOP,
            restitution_threshold: DEFAULT_RESTITUTION_THRESHOLD,
            parallel_threshold: DEFAULT_PARALLEL_THRESHOLD,
            kernel: SolveKernel::Lanes,
            friction_passes: FrictionPasses::Every,
        }
    }
}

/// Box2D v3 caps the contact stiffness at a quarter of the substep rate: a stiffer spring
/// would not be resolved by the substep and would ring.
const MAX_HERTZ_PER_SUBSTEP_RATE: Real = 0.25;

/// Box2D v3 makes contacts against fixed (and here kinematic) bodies twice as stiff, to keep
/// piles from sinking into the ground. Here they are held to the same quarter-rate cap as the
/// others: at half the substep rate the floor contacts under a loaded row of cubes ring (the
/// 100 kg plank on four 1 kg cubes jitters at 112 mm/s at 4 substeps, 60 Hz).
const STATIC_STIFFNESS_FACTOR: Real = 2.0;

impl SolverConfig {
    /// The softness of contacts between dynamic bodies and of contacts against fixed or
    /// kinematic ones, for substeps of `h` s: springs of `contact_hertz` (twice that against
    /// static bodies), both capped at a quarter of the substep rate, for the soft step; rigid
    /// rows with a Baumgarte bias of `baumgarte / h` for the Baumgarte solver.
    pub fn softness(&self, h: Real) -> (Softness, Softness) {
        let inv_h = 1.0 / h;
        match self.kind {
            SolverKind::SoftStep => {
                let max_hertz = MAX_HERTZ_PER_SUBSTEP_RATE * inv_h;
                let contact_hertz = self.contact_hertz.min(max_hertz);
                let static_hertz = (STATIC_STIFFNESS_FACTOR * contact_hertz).min(max_hertz);
                (
                    Softness::new(contact_hertz, self.damping_ratio, h),
                    Softness::new(static_hertz, self.damping_ratio, h),
                )
            }
            SolverKind::Baumgarte => {
                let rigid = Softness {
                    bias_rate: self.baumgarte * inv_h,
                    ..Softness::RIGID
                };
                (rigid, rigid)
            }
        }
    }

    /// The soft-step default (same as `Default`).
    pub fn soft_step() -> Self {
        Self::default()
    }

    /// The thesis's solver: Baumgarte PGS, one substep, [`DEFAULT_BAUMGARTE_ITERATIONS`]
    /// passes, warm starting on, colored order.
    pub fn baumgarte() -> Self {
        Self {
            kind: SolverKind::Baumgarte,
            iterations: DEFAULT_BAUMGARTE_ITERATIONS,
            substeps: 1,
            relax_iterations: 0,
            ..Self::default()
        }
    }

    /// Checks every field against its range in [`crate::bounds`]; the error names the first
    /// bad one, its value and the range.
    pub fn validate(&self) -> Result<(), InvalidParameter> {
        use crate::bounds::*;
        let passes = "solver.iterations";
        require_count(
            passes,
            self.iterations,
            1,
            MAX_ITERATIONS,
            EXPECTED_ITERATIONS,
        )?;
        let substeps = "solver.substeps";
        require_count(substeps, self.substeps, 1, MAX_SUBSTEPS, EXPECTED_SUBSTEPS)?;
        require_count(
            "solver.relax_iterations",
            self.relax_iterations,
            0,
            MAX_ITERATIONS,
            EXPECTED_RELAX_ITERATIONS,
        )?;
        require_positive_at_most(
            "solver.contact_hertz",
            self.contact_hertz,
            MAX_CONTACT_HERTZ,
            EXPECTED_CONTACT_HERTZ,
        )?;
        require_in_range(
            "solver.damping_ratio",
            self.damping_ratio,
            0.0,
            MAX_DAMPING_RATIO,
            EXPECTED_DAMPING_RATIO,
        )?;
        require_positive_at_most(
            "solver.max_push_out",
            self.max_push_out,
            MAX_SPEED,
            EXPECTED_PUSH_OUT,
        )?;
        require_in_range(
            "solver.baumgarte",
            self.baumgarte,
            0.0,
            1.0,
            "a number in [0, 1]",
        )?;
        require_in_range("solver.slop", self.slop, 0.0, MAX_SLOP, EXPECTED_SLOP)?;
        require_in_range(
            "solver.restitution_threshold",
            self.restitution_threshold,
            0.0,
            MAX_SPEED,
            EXPECTED_RESTITUTION_THRESHOLD,
        )?;
        if self.friction_passes == FrictionPasses::RelaxOnly && self.relax_iterations == 0 {
            // No pass would solve friction: every contact would be frictionless.
            return Err(InvalidParameter::new(
                "solver.friction_passes",
                self.friction_passes,
                "FrictionPasses::Every when solver.relax_iterations is 0 (RelaxOnly needs a relax pass)",
            ));
        }
        Ok(())
    }

    /// The context of a biased (`use_bias`) or relax pass at substep rate `inv_h`.
    pub fn pass_context(&self, inv_h: Real, use_bias: bool) -> crate::PassContext {
        crate::PassContext {
            inv_h,
            use_bias,
            max_push_out: self.max_push_out,
            friction: !use_bias || self.friction_passes == FrictionPasses::Every,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_fields_are_named() {
        SolverConfig::default().validate().unwrap();
        SolverConfig::baumgarte().validate().unwrap();
        // Each case: a valid config, the edit that makes it bad, and the field the error names.
        type Edit = fn(&mut SolverConfig);
        let soft = SolverConfig::default();
        let cases: [(SolverConfig, Edit, &str); 8] = [
            (soft, |c| c.substeps = 0, "solver.substeps"),
            (
                soft,
                |c| c.contact_hertz = Real::NAN,
                "solver.contact_hertz",
            ),
            (
                SolverConfig::baumgarte(),
                |c| c.baumgarte = 1.5,
                "solver.baumgarte",
            ),
            // Finite values past the bounds of crate::bounds are refused too.
            (soft, |c| c.substeps = 65, "solver.substeps"),
            (soft, |c| c.contact_hertz = 1e30, "solver.contact_hertz"),
            (soft, |c| c.slop = 1e30, "solver.slop"),
            // Friction in the relax passes only needs a relax pass; the thesis's solver has none.
            (
                SolverConfig::baumgarte(),
                |c| c.friction_passes = FrictionPasses::RelaxOnly,
                "solver.friction_passes",
            ),
            (
                soft,
                |c| {
                    c.friction_passes = FrictionPasses::RelaxOnly;
                    c.relax_iterations = 0;
                },
                "solver.friction_passes",
            ),
        ];
        for (valid, edit, field) in cases {
            let mut bad = valid;
            edit(&mut bad);
            assert_eq!(bad.validate().unwrap_err().field, field, "{bad:?}");
        }
    }
}
