//! Saving a world and restoring it: [`WorldSnapshot`] holds everything that decides the next
//! steps (settings, step count, handles and their slots, bodies, velocities, last step's
//! manifolds with their impulses, the warm-start cache, sleep timers and islands, contact
//! events), so that a world restored from it continues bit for bit as the one it was taken
//! from, on the same backend.
//!
//! On `Backend::Gpu` and `Backend::Hybrid` the snapshot also holds the device state the next
//! steps read, copied back from the GPU buffers (`tumble_gpu::step::GpuWorldState`,
//! `tumble_gpu::step::SavedHybrid`: both pair parities with their manifolds and impulses, the
//! solver's colors and tilt impulses, the sleep stage's rest times and islands, the lagged
//! step statistics), which a restore writes back into a new device world; the restored world
//! then continues bit for bit on the same kind of adapter. With the crate's `serde` feature a
//! snapshot is `Serialize` and `Deserialize` (floats round-trip exactly through JSON's
//! shortest representation).

use tumble_solver::{Body, BodyState, CachedManifold, Contact, PairKey, SleepState, bounds};

use crate::backend::{Host, new_backend};
use crate::events::EventState;
use crate::handle::HandleMap;
use crate::{Backend, BodyHandle, Error, StepStats, World, WorldConfig};

/// The layout of [`WorldSnapshot`]: a snapshot of another layout is refused. Format 2 added
/// each body's collision groups, force, torque, gravity scale and user data; format 3 the
/// GPU backends' device state; format 4 the wider per-pair record of the GPU's contact
/// recycling (`GpuLocalManifold`, 80 to 112 bytes), which a format-3 device state would be
/// read at the wrong stride.
const FORMAT: u32 = 4;

/// What a snapshot expects of its contents.
const EXPECTED: &str = "a snapshot as World::snapshot took it";

/// A world's whole state at the end of a step (see the module documentation).
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WorldSnapshot {
    format: u32,
    config: WorldConfig,
    steps: u64,
    handles: HandleMap,
    bodies: Vec<Body>,
    states: Vec<BodyState>,
    user_data: Vec<u128>,
    contacts: Vec<Contact>,
    contact_handles: Vec<(BodyHandle, BodyHandle)>,
    sleep: SleepState,
    events: EventState,
    backend: BackendSnapshot,
}

/// What a backend keeps between steps besides the host arrays.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) enum BackendSnapshot {
    /// `Backend::Cpu`: the contact cache, sorted by pair key.
    Cpu {
        /// Last step's impulses by body pair.
        cache: Vec<(PairKey, CachedManifold)>,
    },
    /// `Backend::Gpu`: the device world's state and what the backend knows of it.
    #[cfg(feature = "gpu")]
    Gpu {
        /// The device world's buffers and counters.
        state: Box<tumble_gpu::step::GpuWorldState>,
        /// The handles of the bodies on the GPU, in dense order.
        uploaded: Vec<BodyHandle>,
        /// Pose and velocities of each body as the GPU holds them.
        synced: Vec<(tumble_geometry::Pose, BodyState)>,
        /// Dense indices of bodies whose properties are to be written before the next step.
        changed: Vec<usize>,
    },
    /// `Backend::Hybrid`: the GPU collision stages' state.
    #[cfg(feature = "gpu")]
    Hybrid {
        /// The collision stages' buffers and counters, and the tilt impulses kept by slot.
        collision: Box<tumble_gpu::step::SavedHybrid>,
        /// The handles of the bodies on the GPU, in dense order.
        uploaded: Vec<BodyHandle>,
    },
}

impl BackendSnapshot {
    /// The backend the state belongs to.
    pub(crate) fn backend(&self) -> Backend {
        match self {
            Self::Cpu { .. } => Backend::Cpu,
            #[cfg(feature = "gpu")]
            Self::Gpu { .. } => Backend::Gpu,
            #[cfg(feature = "gpu")]
            Self::Hybrid { .. } => Backend::Hybrid,
        }
    }
}

/// The error for `saved` given to a backend `to` of another kind.
pub(crate) fn wrong_backend(saved: &BackendSnapshot, to: Backend) -> Error {
    corrupt(
        "snapshot.backend",
        format!("{:?} state for a {to:?} world", saved.backend()),
    )
}

/// The error for a snapshot whose device state does not fit (`why`).
#[cfg(feature = "gpu")]
pub(crate) fn corrupt_device(why: impl std::fmt::Display) -> Error {
    corrupt("snapshot.device", why)
}

impl WorldSnapshot {
    /// The settings of the saved world (its backend included).
    pub fn config(&self) -> &WorldConfig {
        &self.config
    }

    /// Steps the saved world had taken.
    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// Bodies of the saved world.
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Checks every part against the others and against the engine's bounds, so that a
    /// snapshot altered after it was taken (by hand, or corrupted on disk) is refused rather
    /// than stepped.
    #[cfg_attr(not(feature = "gpu"), allow(irrefutable_let_patterns))]
    fn check(&self) -> Result<(), Error> {
        if self.format != FORMAT {
            return Err(corrupt("snapshot.format", self.format));
        }
        self.config.validate()?;
        if self.backend.backend() != self.config.backend {
            return Err(corrupt(
                "snapshot.backend",
                format!(
                    "{:?} state for config.backend {:?}",
                    self.backend.backend(),
                    self.config.backend
                ),
            ));
        }
        let n = self.bodies.len();
        if self.states.len() != n {
            return Err(corrupt(
                "snapshot.states",
                format!("{} states for {n} bodies", self.states.len()),
            ));
        }
        if self.user_data.len() != n {
            return Err(corrupt(
                "snapshot.user_data",
                format!("{} values for {n} bodies", self.user_data.len()),
            ));
        }
        self.handles
            .check(n)
            .map_err(|e| corrupt("snapshot.handles", e))?;
        self.sleep
            .check(n)
            .map_err(|e| corrupt("snapshot.sleep", e))?;
        let (dt, substeps) = (self.config.dt, self.config.solver.substeps);
        for (d, (b, s)) in self.bodies.iter().zip(&self.states).enumerate() {
            check_body(b, s, dt, substeps)
                .map_err(|e| corrupt("snapshot.bodies", format!("body {d}: {e}")))?;
        }
        if self.contact_handles.len() != self.contacts.len() {
            return Err(corrupt(
                "snapshot.contacts",
                format!(
                    "{} manifolds, {} handle pairs",
                    self.contacts.len(),
                    self.contact_handles.len()
                ),
            ));
        }
        let max_points = tumble_geometry::MAX_MANIFOLD_POINTS;
        for (k, c) in self.contacts.iter().enumerate() {
            let len = c.manifold.len as usize;
            if c.body_a as usize >= n || c.body_b as usize >= n || len == 0 || len > max_points {
                return Err(corrupt(
                    "snapshot.contacts",
                    format!(
                        "manifold {k}: bodies {} and {} of {n}, {len} points",
                        c.body_a, c.body_b
                    ),
                ));
            }
        }
        if let BackendSnapshot::Cpu { cache } = &self.backend
            && let Some((key, m)) = cache.iter().find(|(_, m)| m.len as usize > max_points)
        {
            return Err(corrupt(
                "snapshot.cache",
                format!("pair {key:?}: {} points", m.len),
            ));
        }
        Ok(())
    }
}

/// The error for a snapshot whose `field` holds `value`, which no snapshot taken holds.
fn corrupt(field: &'static str, value: impl std::fmt::Display) -> Error {
    Error::InvalidValue {
        field,
        value: value.to_string(),
        expected: EXPECTED,
    }
}

/// Why body `b` with state `s` cannot be stepped with steps of `dt` in `substeps`, if it
/// cannot.
fn check_body(b: &Body, s: &BodyState, dt: f32, substeps: u32) -> Result<(), String> {
    if let Some(v) = bounds::check_motion(&b.pose, &s.linear_velocity, &s.angular_velocity) {
        return Err(format!("{} = {} ({})", v.quantity, v.value, v.expected));
    }
    bounds::require_half_extents(&b.shape.half_extents).map_err(|e| e.to_string())?;
    let finite_non_negative = |x: f32| x.is_finite() && x >= 0.0;
    let inertia = &b.inverse_inertia_local;
    if !finite_non_negative(b.inverse_mass) || !inertia.iter().all(|&x| finite_non_negative(x)) {
        return Err(format!(
            "inverse mass {} and inverse inertia {inertia:?}",
            b.inverse_mass
        ));
    }
    if !finite_non_negative(b.linear_damping) || !finite_non_negative(b.angular_damping) {
        return Err(format!(
            "damping {} and {}",
            b.linear_damping, b.angular_damping
        ));
    }
    let mut deltas = s
        .delta_position
        .iter()
        .chain(s.delta_rotation.coords.iter());
    if !deltas.all(|x| x.is_finite()) {
        return Err("non-finite in-step delta".to_string());
    }
    bounds::require_force(b, &b.force, dt).map_err(|e| e.to_string())?;
    bounds::require_torque(b, &b.torque, dt, substeps).map_err(|e| e.to_string())?;
    bounds::require_gravity_scale(b.gravity_scale).map_err(|e| e.to_string())?;
    Ok(())
}

impl World {
    /// Everything that decides the world's next steps, as a value: restored with
    /// [`World::restore`] or [`World::from_snapshot`], the world continues bit for bit as this
    /// one would, on the same backend (on the GPU backends, on the same kind of adapter). On
    /// `Backend::Gpu` and `Backend::Hybrid` the device state is read back, which waits for the
    /// steps submitted so far. Errs when that read fails, or when the last step left a state
    /// out of bounds (`Error::InvalidGpuState`).
    pub fn snapshot(&self) -> Result<WorldSnapshot, Error> {
        let host = &self.host;
        // The GPU backend's host arrays may be behind its last step: the current motion and
        // manifolds come from the backend's own reads.
        let mut bodies = host.bodies.clone();
        let mut states = host.states.clone();
        for (d, (body, state)) in bodies.iter_mut().zip(&mut states).enumerate() {
            body.pose = self.backend.pose(host, d)?;
            *state = self.backend.state(host, d)?;
        }
        let (contacts, contact_handles) = self.backend.contacts(host);
        let (contacts, contact_handles) = (contacts.to_vec(), contact_handles.to_vec());
        let backend = self.backend.save()?;
        Ok(WorldSnapshot {
            format: FORMAT,
            config: self.config,
            steps: self.steps,
            handles: self.handles.clone(),
            bodies,
            states,
            user_data: host.user_data.clone(),
            contacts,
            contact_handles,
            sleep: host.sleep.clone(),
            events: self.events.clone(),
            backend,
        })
    }

    /// Puts the world in the state `snapshot` holds: its settings, bodies and handles (a
    /// handle of the saved world names the same body here), step count, contacts and events.
    /// Last step's statistics are not saved and read as empty until the next step.
    ///
    /// Errs, leaving the world unchanged, when the snapshot was taken on another backend
    /// (field `backend`) or fails its checks (a field `snapshot.*` naming the part).
    pub fn restore(&mut self, snapshot: &WorldSnapshot) -> Result<(), Error> {
        if snapshot.config.backend != self.config.backend {
            return Err(Error::InvalidValue {
                field: "backend",
                value: format!(
                    "{:?} (snapshot) into {:?} (world)",
                    snapshot.config.backend, self.config.backend
                ),
                expected: "a snapshot taken on the world's backend",
            });
        }
        snapshot.check()?;
        let host = Host {
            bodies: snapshot.bodies.clone(),
            states: snapshot.states.clone(),
            user_data: snapshot.user_data.clone(),
            contacts: snapshot.contacts.clone(),
            contact_handles: snapshot.contact_handles.clone(),
            contact_colors: Vec::new(),
            sleep: snapshot.sleep.clone(),
            stats: StepStats {
                bodies: snapshot.bodies.len(),
                ..Default::default()
            },
        };
        let mut backend = new_backend(&snapshot.config)?;
        backend.load(&snapshot.backend, &host)?;
        if snapshot.events.enabled {
            backend.set_contact_events(true)?;
        }
        self.config = snapshot.config;
        self.steps = snapshot.steps;
        self.handles = snapshot.handles.clone();
        self.host = host;
        self.events = snapshot.events.clone();
        self.backend = backend;
        self.query.invalidate();
        Ok(())
    }

    /// A new world in the state `snapshot` holds (see [`World::restore`]).
    pub fn from_snapshot(snapshot: &WorldSnapshot) -> Result<Self, Error> {
        let mut world = World::new(snapshot.config)?;
        world.restore(snapshot)?;
        Ok(world)
    }
}
