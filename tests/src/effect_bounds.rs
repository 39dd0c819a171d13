//! What an effect forced off must change, judged the same way through the facade
//! (`tests/tests/effects`) and on the GPU wide solver (`tests/tests/gpu_wide_effects.rs`):
//! the same scenes against the same bounds.

use tumble_geometry::Real;

/// Asserts that friction stopped a unit cube thrown at 3 m/s along the rough floor (`on`, its
/// speed along the throw after 0.6 s with friction) and that without friction it slid on
/// (`off`, the same without).
pub fn assert_friction_stops_the_slide(on: Real, off: Real) {
    // mu g = 5.9 m/s^2 stops the 3 m/s cube in 0.51 s, inside the 0.6 s run; without friction
    // rows nothing acts along the floor and it keeps its speed up to round-off.
    assert!(
        on.abs() < 0.05,
        "with friction the cube still slides at {on} m/s"
    );
    assert!(
        (off - 3.0).abs() < 1e-3,
        "without friction the cube slides at {off} m/s"
    );
}

/// Drop height of the bouncing cube's bottom face, m, and its restitution.
pub const DROP: Real = 1.0;
pub const BOUNCE: Real = 0.5;

/// The highest the bouncing cube's bottom face rises after it lands, from its height and
/// vertical velocity after each step (run the drop for 0.75 s: the fall takes 0.45 s and the
/// rise to the apex 0.23 s).
pub struct Apex {
    landed: bool,
    /// The apex so far, m above the floor; `-inf` until the cube lands.
    pub height: Real,
}

impl Default for Apex {
    fn default() -> Self {
        Self {
            landed: false,
            height: Real::NEG_INFINITY,
        }
    }
}

impl Apex {
    /// Takes the bottom face's `height` and the vertical velocity `vy` after a step.
    pub fn watch(&mut self, height: Real, vy: Real) {
        // The impact is the first step that ends low and no longer falling fast.
        self.landed |= vy > -0.5 && height < 0.5 * DROP;
        if self.landed {
            self.height = self.height.max(height);
        }
    }
}

/// Asserts that the cube dropped with restitution `BOUNCE` bounced back up to `on` (its apex
/// with restitution) as restitution must, and stopped dead without it (`off`).
pub fn assert_restitution_bounces(on: Real, off: Real) {
    // Restitution e sends the cube back up at e times its impact speed, to e^2 times its drop
    // height (0.25 m) at most; the soft contact absorbs part of the impact first (measured
    // 0.21 m), hence the lower bound of 70%.
    let ideal = BOUNCE * BOUNCE * DROP;
    assert!(
        on > 0.7 * ideal && on <= ideal,
        "bounced {on} m, ideal {ideal} m"
    );
    // Without it the contact only stops the fall: what rises is the soft contact pushing out
    // its last step's overlap (measured 0.6 mm).
    assert!(off < 0.01, "without restitution the cube bounced {off} m");
}

/// Asserts that a cube let go at rest fell `dropped` m in `steps` steps of `dt` s of
/// `substeps` substeps each under gravity `g` (m/s^2, along y).
pub fn assert_free_fall(dropped: Real, g: Real, dt: Real, substeps: u32, steps: usize) {
    // Semi-implicit Euler over n substeps of h drops the cube by g h^2 n (n + 1) / 2 (1.23 m
    // in 0.5 s, still in the air); f32 round-off stays far below the 1 mm bound.
    let substeps = substeps as Real;
    let (n, h) = (steps as Real * substeps, dt / substeps);
    let expected = -g * h * h * n * (n + 1.0) / 2.0;
    assert!(
        (dropped - expected).abs() < 1e-3,
        "fell {dropped} m, expected {expected} m"
    );
}

/// Tilt of the tipped cube about z, rad: under 45 degrees its centre lies beside the edge it
/// stands on, over the face it was tipped from, so gravity turns it back onto that face.
pub const TILT: Real = 0.6;

/// Height of the tipped cube's centre: stood on one edge, that edge 1 mm above the floor,
/// the centre is 0.5 (cos + sin) above the edge.
pub fn tipped_height() -> Real {
    0.5 * (TILT.cos() + TILT.sin()) + 0.001
}

/// Asserts that the tipped cube turned back flat with rotation (`on`, the most it turned from
/// its tilt, rad) and did not turn at all without it (`off`).
pub fn assert_tipped_cube_turns(on: Real, off: Real) {
    // With rotation it turns through its whole tilt (and rocks a little past flat:
    // measured 0.637 rad); 90% of it leaves room for the landing.
    assert!(on > 0.9 * TILT, "turned {on} rad, tilt {TILT} rad");
    // Without it the body's inverse inertia is zero for the step: it cannot turn at all.
    assert!(off < 1e-6, "rotation off: the cube turned {off} rad");
}
