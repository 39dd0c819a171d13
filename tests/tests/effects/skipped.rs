//! Effects a scene does not use are skipped, and skipping changes only the time: each row
//! below is a scene without one effect, stepped to the same bits with that effect left to
//! Auto, forced on and forced off. The CPU tests are here; `gpu.rs` runs the same rows.

use super::*;

/// A scene that does not need one effect, and how to switch and read that effect.
pub struct Unused {
    /// The effect, for messages.
    name: &'static str,
    /// Sets the effect's switch.
    set: fn(&mut EffectOverrides, EffectSwitch),
    /// Whether a world ran the effect.
    get: fn(&tumble::Effects) -> bool,
    /// Builds the scene.
    build: fn(&mut World),
}

impl Unused {
    /// Asserts that the scene does not need the effect (Auto leaves it out) and that forcing
    /// it on gives the same bits as leaving it out.
    pub fn same_bits_on_and_off(&self, base: WorldConfig) {
        let name = match base.backend {
            Backend::Cpu => self.name.to_string(),
            _ => format!("gpu {}", self.name),
        };
        let (auto, auto_effects) = run(base, self.set, EffectSwitch::Auto, self.build);
        assert!(
            !(self.get)(&auto_effects),
            "{name}: the scene should not need it"
        );
        let (on, on_effects) = run(base, self.set, EffectSwitch::On, self.build);
        assert!((self.get)(&on_effects), "{name}: forced on");
        let (off, _) = run(base, self.set, EffectSwitch::Off, self.build);
        assert!(!on.is_empty());
        assert_eq!(on, off, "{name}: forced on and skipped differ");
        assert_eq!(auto, off, "{name}: auto and skipped differ");
    }
}

/// The row of the effect named by its [`EffectOverrides`] field `$effect`, on the scene
/// `$build` makes.
macro_rules! unused {
    ($effect:ident, $build:expr) => {
        Unused {
            name: stringify!($effect),
            set: |e, s| e.$effect = s,
            get: |e| e.$effect,
            build: $build,
        }
    };
}

/// Friction in a frictionless pool.
pub const FRICTION: Unused = unused!(friction, |w| pile(w, 0.0, false));
/// Restitution where nothing bounces.
pub const RESTITUTION: Unused = unused!(restitution, |w| pile(w, 0.6, false));
/// Gravity, in a world whose base config has zero gravity.
pub const GRAVITY: Unused = unused!(gravity, |w| pile(w, 0.6, false));
/// Rotation when every rotation is locked.
pub const ROTATION: Unused = unused!(rotation, |w| pile(w, 0.6, true));

#[test]
fn friction_skipped_in_a_frictionless_pool() {
    FRICTION.same_bits_on_and_off(WorldConfig::default());
}

#[test]
fn restitution_skipped_when_nothing_bounces() {
    RESTITUTION.same_bits_on_and_off(WorldConfig::default());
}

#[test]
fn gravity_skipped_in_zero_gravity() {
    let base = WorldConfig {
        gravity: Vec3::zeros(),
        ..Default::default()
    };
    GRAVITY.same_bits_on_and_off(base);
}

#[test]
fn rotation_skipped_when_every_rotation_is_locked() {
    ROTATION.same_bits_on_and_off(WorldConfig::default());
}

#[test]
fn kinematic_handling_skipped_without_kinematic_bodies() {
    // With sleep on, kinematic bodies are what the kinematic effect checks.
    let mut base = WorldConfig::default();
    base.effects.sleep = EffectSwitch::On;
    unused!(kinematic, |w| pile(w, 0.6, false)).same_bits_on_and_off(base);
}

#[test]
fn sleep_forced_on_changes_nothing_while_nothing_rests() {
    // Boxes gliding on a frictionless floor never slow down, so no island ever sleeps; the
    // islands are still built each step when sleep is on. Unlike the other effects, sleep is
    // on by default wherever a body is dynamic (Auto runs it), so the row checks Auto, On and
    // Off against each other rather than Auto against "not needed".
    let build: fn(&mut World) = |w| {
        pile(w, 0.0, false);
        for &h in &w.handles().to_vec()[1..] {
            w.set_linear_velocity(h, Vec3::new(2.0, 0.0, 0.0)).unwrap();
        }
    };
    let set: fn(&mut EffectOverrides, EffectSwitch) = |e, s| e.sleep = s;
    let base = WorldConfig::default();
    let (auto, auto_effects) = run(base, set, EffectSwitch::Auto, build);
    assert!(
        auto_effects.sleep,
        "sleep: on by default with dynamic bodies"
    );
    let (on, on_effects) = run(base, set, EffectSwitch::On, build);
    assert!(on_effects.sleep, "sleep: forced on");
    let (off, off_effects) = run(base, set, EffectSwitch::Off, build);
    assert!(!off_effects.sleep, "sleep: forced off");
    assert!(!on.is_empty());
    assert_eq!(
        on, off,
        "sleep: forced on and off differ while nothing rests"
    );
    assert_eq!(auto, off, "sleep: auto and off differ while nothing rests");
}
