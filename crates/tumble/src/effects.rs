//! The effects a world's step runs: derived from its bodies at every step (so a body added,
//! removed or changed is accounted for at once) and open to the user, who may force any of
//! them on or off through [`WorldConfig::effects`](crate::WorldConfig::effects).

use tumble_solver::Effects;

use crate::World;

/// How one effect is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum EffectSwitch {
    /// On when the scene needs it. For sleep: on whenever the world has a dynamic body, as in
    /// rapier, Box2D, PhysX and Jolt (a resting island stops being stepped until something
    /// touches or changes it); `Off` keeps every body integrating.
    #[default]
    Auto,
    /// Always run, needed or not (the general step).
    On,
    /// Never run, even when the scene would need it.
    Off,
}

impl EffectSwitch {
    fn resolve(self, derived: bool) -> bool {
        match self {
            Self::Auto => derived,
            Self::On => true,
            Self::Off => false,
        }
    }
}

/// The user's choice per effect; `Auto` everywhere by default.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EffectOverrides {
    /// Gravity.
    pub gravity: EffectSwitch,
    /// Friction rows.
    pub friction: EffectSwitch,
    /// The restitution pass.
    pub restitution: EffectSwitch,
    /// Angular motion.
    pub rotation: EffectSwitch,
    /// Kinematic-body handling.
    pub kinematic: EffectSwitch,
    /// Islands and sleep (`Auto` means on when the world has a dynamic body; `Off` turns
    /// sleep off, so that every body is integrated every step).
    pub sleep: EffectSwitch,
    /// What a GPU step copies back for the host; see [`ReadbackOverrides`].
    pub readback: ReadbackOverrides,
}

/// Which results a `Backend::Gpu` step copies back to the host in its own command stream,
/// to be read without a second round trip.
///
/// `Auto` copies what the caller read after the previous step (a program that reads every
/// pose each frame gets the poses copied with every step; one that never reads contacts never
/// pays for them). `On` copies it after every step. `Off` never copies it with the step:
/// reading it then costs a separate read of the GPU buffers. Whatever the setting, every
/// getter returns the state after the last step: these switches change only the time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ReadbackOverrides {
    /// Every body's pose.
    pub poses: EffectSwitch,
    /// Every body's linear and angular velocity.
    pub velocities: EffectSwitch,
    /// The step's manifolds with their impulses (contact pairs, contact reports).
    pub contacts: EffectSwitch,
    /// Which bodies sleep (only copied when the sleep effect runs).
    pub sleeping: EffectSwitch,
    /// The step's contact counts behind [`crate::World::stats`] (pairs, manifolds, points,
    /// the deepest overlap): 16 bytes reduced on the GPU, so that reading the counts does not
    /// read the manifolds.
    #[cfg_attr(feature = "serde", serde(default))]
    pub stats: EffectSwitch,
}

impl ReadbackOverrides {
    /// Everything copied after every step.
    pub const ALL_ON: Self = Self {
        poses: EffectSwitch::On,
        velocities: EffectSwitch::On,
        contacts: EffectSwitch::On,
        sleeping: EffectSwitch::On,
        stats: EffectSwitch::On,
    };

    /// The reads a step records, given what the caller read after the previous one.
    #[cfg(feature = "gpu")]
    pub(crate) fn resolve(&self, read: crate::gpu_reads::Reads) -> crate::gpu_reads::Reads {
        crate::gpu_reads::Reads {
            poses: self.poses.resolve(read.poses),
            velocities: self.velocities.resolve(read.velocities),
            contacts: self.contacts.resolve(read.contacts),
            sleeping: self.sleeping.resolve(read.sleeping),
            summary: self.stats.resolve(read.summary),
        }
    }
}

impl EffectOverrides {
    /// The defaults (`Auto` everywhere) with sleep off: every body is integrated every step.
    /// What measurements of the solver use (drift, energy, step time against engines whose
    /// bodies all stay awake), and the setting of the committed golden hashes.
    pub const NO_SLEEP: Self = Self {
        gravity: EffectSwitch::Auto,
        friction: EffectSwitch::Auto,
        restitution: EffectSwitch::Auto,
        rotation: EffectSwitch::Auto,
        kinematic: EffectSwitch::Auto,
        sleep: EffectSwitch::Off,
        readback: ReadbackOverrides {
            poses: EffectSwitch::Auto,
            velocities: EffectSwitch::Auto,
            contacts: EffectSwitch::Auto,
            sleeping: EffectSwitch::Auto,
            stats: EffectSwitch::Auto,
        },
    };

    /// Every effect forced on: the general step, whatever the scene.
    pub const ALL_ON: Self = Self {
        gravity: EffectSwitch::On,
        friction: EffectSwitch::On,
        restitution: EffectSwitch::On,
        rotation: EffectSwitch::On,
        kinematic: EffectSwitch::On,
        sleep: EffectSwitch::On,
        readback: ReadbackOverrides::ALL_ON,
    };

    /// The effects that run, given the ones the scene needs.
    pub fn resolve(&self, derived: Effects) -> Effects {
        Effects {
            gravity: self.gravity.resolve(derived.gravity),
            friction: self.friction.resolve(derived.friction),
            restitution: self.restitution.resolve(derived.restitution),
            rotation: self.rotation.resolve(derived.rotation),
            kinematic: self.kinematic.resolve(derived.kinematic),
            sleep: self.sleep.resolve(derived.sleep),
        }
    }
}

impl World {
    /// The effects the next step runs: what the bodies need, with the config's overrides.
    /// Sleep, which the solver layer never derives (it changes results), is on by default
    /// here wherever a body can come to rest.
    pub fn effects(&self) -> Effects {
        let mut derived = Effects::of_bodies(&self.host.bodies, &self.config.gravity);
        derived.sleep = self
            .host
            .bodies
            .iter()
            .any(|b| b.kind == tumble_solver::BodyKind::Dynamic);
        self.config.effects.resolve(derived)
    }
}
