//! Where the step runs: one [`StepBackend`] per world, chosen by [`Backend`].
//!
//! A backend owns the step and every read and write of the bodies' state that may depend on
//! where the state lives. The world keeps the host copy of the bodies ([`Host`]) and calls
//! its backend without asking which one it is:
//!
//! - [`cpu::CpuBackend`] runs [`pipeline::step`] with the CPU collision stages;
//! - [`hybrid::HybridBackend`] runs the same [`pipeline::step`] with the collision stages on
//!   the GPU, so color, solve, finish and sleep are the CPU's, written once;
//! - [`gpu::GpuBackend`] runs the whole step on the GPU and reads its results lazily
//!   (`crate::gpu_reads`); its reads and writes bring the host copy up to date first.
//!
//! The GPU backends exist with the crate's `gpu` feature (the default). Without it,
//! [`new_backend`] answers `Backend::Gpu` and `Backend::Hybrid` with
//! [`Error::BackendUnavailable`], and nothing of wgpu is compiled.

pub(crate) mod cpu;
#[cfg(feature = "gpu")]
pub(crate) mod gpu;
#[cfg(feature = "gpu")]
pub(crate) mod group;
#[cfg(feature = "gpu")]
pub(crate) mod hybrid;
#[cfg(feature = "gpu")]
pub(crate) mod member;
pub(crate) mod pipeline;

use std::fmt;

use tumble_geometry::Pose;
use tumble_solver::{Body, BodyState, Contact, Effects, SleepState};

use crate::handle::HandleMap;
use crate::snapshot::BackendSnapshot;
use crate::{Backend, BodyHandle, ContactEvent, Error, StepStats, TouchingPair, WorldConfig};

/// The world's host copy of its bodies and of the last step's results, in dense order.
#[derive(Clone, Debug, Default)]
pub(crate) struct Host {
    /// Cold body data.
    pub bodies: Vec<Body>,
    /// Hot body state.
    pub states: Vec<BodyState>,
    /// Last step's manifolds (dense body indices at the time of the step).
    pub contacts: Vec<Contact>,
    /// The body handles of each of last step's manifolds.
    pub contact_handles: Vec<(BodyHandle, BodyHandle)>,
    /// The solver's graph color of each of last step's manifolds (`tumble_solver::Coloring`
    /// values; `NO_COLOR` for the sleeping islands' kept ones), empty when the step colored
    /// nothing (sequential order) or ran on the GPU.
    pub contact_colors: Vec<u32>,
    /// Rest timers, sleeping islands and their contacts (the CPU sleep stage's state).
    pub sleep: SleepState,
    /// Last step's counts and times.
    pub stats: StepStats,
    /// Each body's user data (`BodyDesc::user_data`), never read by the step.
    pub user_data: Vec<u128>,
}

/// Last step's manifolds and the handles of their bodies.
pub(crate) type ContactsView<'a> = (&'a [Contact], &'a [(BodyHandle, BodyHandle)]);

/// Last step's touching pairs, and the events when a backend compared the steps itself.
pub(crate) type TouchingAndEvents = (Vec<TouchingPair>, Option<Vec<ContactEvent>>);

/// What a step runs with besides the host copy: the world's handles, settings and effects.
#[derive(Clone, Copy)]
pub(crate) struct StepArgs<'a> {
    /// The bodies' handles, in dense order.
    pub handles: &'a HandleMap,
    /// The world's settings (`config.dt` is the step).
    pub config: &'a WorldConfig,
    /// The effects the step runs.
    pub effects: &'a Effects,
}

/// One of the three ways to run a step, with the reads and writes that depend on it. Every
/// method but [`StepBackend::step`] has the host-side default: a backend whose state lives on
/// the host ([`cpu::CpuBackend`], [`hybrid::HybridBackend`]) overrides nothing else.
pub(crate) trait StepBackend: fmt::Debug + Send + Sync {
    /// Advances `host` by one step of `config.dt` running `effects`.
    fn step(&mut self, host: &mut Host, args: StepArgs<'_>) -> Result<(), Error>;

    /// The pose of the body at dense index `d` now.
    fn pose(&self, host: &Host, d: usize) -> Result<Pose, Error> {
        Ok(host.bodies[d].pose)
    }

    /// The velocities of the body at dense index `d` now.
    fn state(&self, host: &Host, d: usize) -> Result<BodyState, Error> {
        Ok(host.states[d])
    }

    /// Last step's manifolds and their handles. A failed read reports no contacts here and
    /// its error from the next step.
    fn contacts<'a>(&'a self, host: &'a Host) -> ContactsView<'a> {
        (&host.contacts, &host.contact_handles)
    }

    /// Turns the backend's own contact events on or off (see `crate::events`).
    fn set_contact_events(&mut self, on: bool) -> Result<(), Error> {
        let _ = on;
        Ok(())
    }

    /// Last step's touching pairs, sorted by pair, and the begin and end events when the
    /// backend compared the step with the one before itself (`None`: the caller compares the
    /// touching pairs with its own list). `previous` is the caller's list of the step before
    /// and `sleep` whether the sleep effect ran. The default reads the pairs from
    /// [`StepBackend::contacts`] (which hold the sleeping islands' kept manifolds) and compares
    /// nothing.
    fn touching_and_events(
        &self,
        host: &Host,
        previous: &[TouchingPair],
        sleep: bool,
    ) -> Result<TouchingAndEvents, Error> {
        let _ = (previous, sleep);
        let (contacts, handles) = self.contacts(host);
        Ok((crate::events::touching_pairs(contacts, handles), None))
    }

    /// Every body's pose and velocities after the last step, as the device gave them, and
    /// the index of this world's first body among them, when the host copy is behind and the
    /// backend holds them apart from it (a GPU batch's worlds: reads of whole worlds take them
    /// from there). `None`: read body by body.
    #[cfg(feature = "gpu")]
    fn fetched_motion(
        &self,
        host: &Host,
    ) -> Result<Option<(std::sync::Arc<tumble_gpu::step::Snapshot>, usize)>, Error> {
        let _ = host;
        Ok(None)
    }

    /// Last step's candidate pairs from the broad phase, by handle (see
    /// [`crate::World::broad_phase_pairs`]). The default has none: a backend whose pairs stay
    /// on the device.
    fn broad_phase_pairs(&self) -> &[(BodyHandle, BodyHandle)] {
        &[]
    }

    /// Last step's statistics.
    fn stats<'a>(&'a self, host: &'a Host) -> &'a StepStats {
        &host.stats
    }

    /// True when the body at dense index `d` sleeps; `sleep` is whether the sleep effect
    /// runs.
    fn is_sleeping(&self, host: &Host, d: usize, sleep: bool) -> Result<bool, Error> {
        let _ = sleep;
        Ok(host.sleep.is_asleep(d))
    }

    /// Bodies asleep (a failed read counts none and reports its error from the next step).
    fn sleeping_count(&self, host: &Host, sleep: bool) -> usize {
        let _ = sleep;
        host.sleep.asleep_count()
    }

    /// Wakes the island of the body at dense index `d` before the next step.
    fn wake(&mut self, host: &mut Host, d: usize) -> Result<(), Error> {
        host.sleep.wake(d);
        Ok(())
    }

    /// Brings the host's poses and velocities up to date before a call changes them, so that
    /// the change is made to the current state and the next step sees it.
    fn sync_motion(&mut self, host: &mut Host) -> Result<(), Error> {
        let _ = host;
        Ok(())
    }

    /// Brings every host array up to date (before bodies are added or removed, which
    /// renumbers them).
    fn sync_all(&mut self, host: &mut Host) -> Result<(), Error> {
        self.sync_motion(host)
    }

    /// The body at dense index `d` has new cold data in `host.bodies[d]` that the step reads
    /// (collision groups, force, torque, gravity scale): the next step must use it.
    fn body_changed(&mut self, host: &Host, d: usize) -> Result<(), Error> {
        let _ = (host, d);
        Ok(())
    }

    /// Forgets whatever the backend keeps of the removed body with id `id` (its cached
    /// contacts).
    fn forget_body(&mut self, id: u64) {
        let _ = id;
    }

    /// What the backend keeps between steps besides the host arrays, for a snapshot (on the
    /// GPU backends read back from the device: blocking). Errs when the state cannot be read
    /// (a failed device, or a step that left a state out of bounds).
    fn save(&self) -> Result<BackendSnapshot, Error>;

    /// Takes the state `save` gave, on a backend just made for the snapshot's config, beside
    /// `host`, the host arrays restored with it. Errs when the state does not fit them.
    fn load(&mut self, saved: &BackendSnapshot, host: &Host) -> Result<(), Error>;

    /// Which backend this is.
    fn kind(&self) -> Backend;

    /// Bytes of results copied from the GPU to the host so far (0 when results live on the
    /// host).
    fn readback_bytes(&self) -> u64 {
        0
    }

    /// Bytes of the device buffers the backend's GPU stages hold (0 without any).
    fn device_buffer_bytes(&self) -> u64 {
        0
    }

    /// The device buffers behind [`Self::device_buffer_bytes`] as (pool, buffer, bytes);
    /// empty unless the whole step is on the GPU.
    fn device_buffer_sizes(&self) -> Vec<(&'static str, &'static str, u64)> {
        Vec::new()
    }

    /// The device and buffers holding the bodies' state, when it lives on a GPU (see
    /// [`crate::World::gpu_draw_buffers`]).
    #[cfg(feature = "gpu")]
    fn draw_buffers(&self) -> Option<(tumble_gpu::GpuContext, tumble_gpu::step::DrawBuffers)> {
        None
    }

    /// The device holding the bodies' state, when it lives on a GPU.
    #[cfg(feature = "gpu")]
    fn gpu_context(&self) -> Option<tumble_gpu::GpuContext> {
        None
    }

    /// The buffer of last step's graph colors on the GPU (see
    /// [`crate::World::gpu_contact_colors`]).
    #[cfg(feature = "gpu")]
    fn color_buffer(&self) -> Option<tumble_gpu::wgpu::Buffer> {
        None
    }
}

/// The backend `config.backend` asks for. Errs when the GPU it needs is unavailable, or when
/// the crate was built without its `gpu` feature.
pub(crate) fn new_backend(config: &WorldConfig) -> Result<Box<dyn StepBackend>, Error> {
    match config.backend {
        Backend::Cpu => Ok(Box::new(cpu::CpuBackend::default())),
        Backend::Gpu => device::gpu(config),
        Backend::Hybrid => device::hybrid(config),
    }
}

#[cfg(feature = "gpu")]
pub(crate) use device::shared_context;

/// The GPU backends, opened on the process's one device.
#[cfg(feature = "gpu")]
mod device {
    use std::sync::Mutex;

    use tumble_gpu::GpuContext;

    use super::{StepBackend, gpu::GpuBackend, hybrid::HybridBackend};
    use crate::{Error, WorldConfig};

    /// `Backend::Gpu`.
    pub(super) fn gpu(config: &WorldConfig) -> Result<Box<dyn StepBackend>, Error> {
        Ok(Box::new(GpuBackend::new(config)?))
    }

    /// `Backend::Hybrid`.
    pub(super) fn hybrid(config: &WorldConfig) -> Result<Box<dyn StepBackend>, Error> {
        Ok(Box::new(HybridBackend::new(config)?))
    }

    /// One device for every GPU world of the process: opening a device and compiling
    /// pipelines is the slow part of starting a world, and pipelines are shared per device.
    /// A device that was lost is replaced for the worlds made after (the worlds on the lost
    /// one return `Err` from every step); a failure to open one is kept, as retrying every
    /// world would only repeat it.
    pub(crate) fn shared_context() -> Result<GpuContext, String> {
        static SHARED: Mutex<Option<Result<GpuContext, String>>> = Mutex::new(None);
        let mut shared = SHARED.lock().unwrap_or_else(|p| p.into_inner());
        if matches!(&*shared, Some(Ok(ctx)) if ctx.is_lost()) {
            *shared = None;
        }
        shared
            .get_or_insert_with(|| GpuContext::new().map_err(|e| e.to_string()))
            .clone()
    }
}

/// Without the `gpu` feature: the GPU backends are errors naming the missing feature.
#[cfg(not(feature = "gpu"))]
mod device {
    use super::{StepBackend, unavailable};
    use crate::{Backend, Error, WorldConfig};

    /// Why a GPU backend cannot run in this build.
    pub(super) const WITHOUT_GPU: &str = "the tumble crate was built without its `gpu` \
        feature (enabled by default), so it has no GPU backend; build it with the `gpu` \
        feature, or use Backend::Cpu";

    /// `Backend::Gpu`: unavailable.
    pub(super) fn gpu(config: &WorldConfig) -> Result<Box<dyn StepBackend>, Error> {
        let _ = config;
        Err(unavailable(Backend::Gpu, WITHOUT_GPU))
    }

    /// `Backend::Hybrid`: unavailable.
    pub(super) fn hybrid(config: &WorldConfig) -> Result<Box<dyn StepBackend>, Error> {
        let _ = config;
        Err(unavailable(Backend::Hybrid, WITHOUT_GPU))
    }
}

/// The error of a backend that cannot run, or whose device failed.
pub(crate) fn unavailable(backend: Backend, e: impl fmt::Display) -> Error {
    Error::BackendUnavailable {
        backend,
        reason: e.to_string(),
    }
}
