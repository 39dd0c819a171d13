//! The device every kernel runs on: adapter choice, device limits and optional features.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

use crate::GpuError;

/// Environment variable naming the adapter to use: a case-insensitive substring of its name
/// (e.g. `llvmpipe` for lavapipe, `nvidia`). Unset: the best adapter wins.
pub const ADAPTER_ENV: &str = "TUMBLE_ADAPTER";

/// Environment variable that turns "no GPU adapter" from a skipped test into a failed one.
/// CI sets it to `1` (with lavapipe installed), so the GPU path can never silently not run.
/// `1` and `true` (any case, surrounding spaces ignored) turn it on; see [`require_gpu_value`].
pub const REQUIRE_GPU_ENV: &str = "TUMBLE_REQUIRE_GPU";

/// Whether a value of [`REQUIRE_GPU_ENV`] asks for a GPU: `1` or `true` (any case, surrounding
/// spaces ignored). Anything else (unset, empty, `0`, `false`, `yes`) leaves a missing adapter a
/// skip, so a typo never fails a run that has no GPU to offer.
pub fn require_gpu_value(value: Option<&str>) -> bool {
    value.is_some_and(|v| {
        let v = v.trim();
        v == "1" || v.eq_ignore_ascii_case("true")
    })
}

/// Storage buffers a single kernel may bind: as many as the widest kernel binds (the batch
/// solve, `solve_worlds_shared`: the fused solve's thirteen, velocities and solver bodies, and
/// three per-world ranges), checked by a test against every kernel's reflected bindings. A device
/// with fewer is refused when it opens, naming the limit, rather than failing later when that
/// pipeline is built; WebGPU's default of 8 is too few, and GL adapters often offer 16.
pub const REQUIRED_STORAGE_BUFFERS_PER_STAGE: u32 = 18;

/// Bytes of immediate data the wide solver path sets per dispatch (one `ColorPass`): a
/// device whose limit is smaller is opened without immediate data and binds a uniform per
/// color instead ([`GpuContext::has_immediates`]).
pub const REQUIRED_IMMEDIATE_BYTES: u32 =
    std::mem::size_of::<crate::solver::layout::ColorPass>() as u32;

/// The read timeout a context starts with ([`GpuContext::set_read_timeout`]): far beyond any
/// step, so reaching it means a hung or lost device, not a slow one.
pub const DEFAULT_READ_TIMEOUT: Duration = Duration::from_secs(60);

/// Options for [`GpuContext::with_options`].
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Case-insensitive substring of the adapter name to pick; `None` reads [`ADAPTER_ENV`].
    pub adapter_name: Option<String>,
    /// Request GPU timestamp queries when the adapter offers them (per-stage GPU timings).
    pub timestamps: bool,
    /// The limits to ask the device for instead of the adapter's own (each at most the
    /// adapter's, or opening fails with [`GpuError::DeviceRequest`]). Smaller limits make a
    /// device that behaves as a smaller GPU would: scenes over them are refused with
    /// [`GpuError::LimitExceeded`] before anything is uploaded.
    pub limits: Option<wgpu::Limits>,
}

/// What the device reported outside any error scope: its loss (sticky) and the first error
/// no scope caught since the last check (wgpu's default handler for those panics).
#[derive(Debug, Default)]
struct Health {
    lost: Mutex<Option<String>>,
    uncaptured: Mutex<Option<String>>,
}

impl Health {
    fn lost(&self) -> Option<String> {
        self.lost.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }
}

/// An opened GPU: device, queue and what they can do. Cheap to clone (handles are shared).
#[derive(Clone, Debug)]
pub struct GpuContext {
    /// The adapter the device was opened on.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's name, backend and kind, for reports.
    pub info: wgpu::AdapterInfo,
    /// True when per-pass timestamp queries were enabled.
    pub has_timestamps: bool,
    /// True when the device has immediate data ([`wgpu::Features::IMMEDIATES`]) for at least
    /// [`REQUIRED_IMMEDIATE_BYTES`]: the wide solver path then names each per-color
    /// dispatch's color with immediate data instead of a bind group per color (the same
    /// bits, less host time recording a step; docs/gpu-solver.md).
    pub has_immediates: bool,
    /// True when the device has `@coherent` storage buffers
    /// ([`wgpu::Features::MEMORY_DECORATION_COHERENT`]): the wide solver path can then run a
    /// step's substeps in one dispatch (`solve_step`, docs/gpu-solver.md).
    pub has_coherent: bool,
    /// The pipelines built on this device.
    pub(crate) pipelines: crate::kernel::PipelineCache,
    /// Device loss and uncaptured errors, as the device's callbacks reported them.
    health: Arc<Health>,
    /// The longest blocking wait, in nanoseconds, shared by every clone.
    read_timeout: Arc<AtomicU64>,
}

/// The instance settings: wgpu's defaults without indirect-call validation, then whatever the
/// `WGPU_*` environment variables say.
///
/// wgpu validates every indirect dispatch in release builds by default: each one becomes a
/// validation dispatch, a rebind and two more barriers. Every indirect argument buffer of the
/// step is written by `plan_dispatch` (or `color_plan`), which clamps the count to the list's
/// capacity and folds the workgroups past the per-dimension limit, so the check can never
/// fire; it only costs time. `WGPU_VALIDATION_INDIRECT_CALL=1` turns it back on.
fn instance_descriptor() -> wgpu::InstanceDescriptor {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.flags
        .remove(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL);
    desc.with_env()
}

/// Lower is better: discrete GPUs first, software rasterizers last.
fn device_rank(kind: wgpu::DeviceType) -> u8 {
    match kind {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

impl GpuContext {
    /// Opens the best adapter (or the one named by [`ADAPTER_ENV`]) with timestamps if offered.
    pub fn new() -> Result<Self, GpuError> {
        Self::with_options(&GpuOptions {
            timestamps: true,
            ..Default::default()
        })
    }

    /// Opens a device as `options` ask.
    pub fn with_options(options: &GpuOptions) -> Result<Self, GpuError> {
        let wanted = options
            .adapter_name
            .clone()
            .or_else(|| std::env::var(ADAPTER_ENV).ok())
            .filter(|s| !s.is_empty());
        let instance = wgpu::Instance::new(instance_descriptor());
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        let adapter = adapters
            .into_iter()
            .filter(|a| {
                a.get_downlevel_capabilities()
                    .flags
                    .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
            })
            .filter(|a| match &wanted {
                Some(name) => a
                    .get_info()
                    .name
                    .to_lowercase()
                    .contains(&name.to_lowercase()),
                None => true,
            })
            // Vulkan, Metal and DX12 before GL: the GL backend lacks indirect compute on some drivers.
            .min_by_key(|a| {
                let info = a.get_info();
                (
                    device_rank(info.device_type),
                    info.backend == wgpu::Backend::Gl,
                )
            })
            .ok_or(GpuError::NoAdapter {
                requested: wanted.clone(),
            })?;
        Self::open(adapter, options.timestamps, options.limits.clone())
    }

    /// Opens a device on `adapter` with `limits` (the adapter's own when `None`), checking the
    /// limits the kernels rely on.
    fn open(
        adapter: wgpu::Adapter,
        timestamps: bool,
        limits: Option<wgpu::Limits>,
    ) -> Result<Self, GpuError> {
        let info = adapter.get_info();
        let limits = limits.unwrap_or_else(|| adapter.limits());
        if limits.max_storage_buffers_per_shader_stage < REQUIRED_STORAGE_BUFFERS_PER_STAGE {
            return Err(GpuError::LimitExceeded {
                what: "kernels".into(),
                value: REQUIRED_STORAGE_BUFFERS_PER_STAGE.into(),
                limit_name: "max_storage_buffers_per_shader_stage",
                limit: limits.max_storage_buffers_per_shader_stage.into(),
            });
        }
        if limits.max_compute_invocations_per_workgroup < crate::WORKGROUP_SIZE {
            return Err(GpuError::LimitExceeded {
                what: "workgroup size".into(),
                value: crate::WORKGROUP_SIZE.into(),
                limit_name: "max_compute_invocations_per_workgroup",
                limit: limits.max_compute_invocations_per_workgroup.into(),
            });
        }
        let has_timestamps =
            timestamps && adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        // Immediate data where the adapter has it and the limits asked for leave room for
        // one `ColorPass` (limits with `max_immediate_size: 0` open a device without it).
        let has_immediates = adapter.features().contains(wgpu::Features::IMMEDIATES)
            && limits.max_immediate_size >= REQUIRED_IMMEDIATE_BYTES;
        let has_coherent = adapter
            .features()
            .contains(wgpu::Features::MEMORY_DECORATION_COHERENT);
        let mut required_features = wgpu::Features::empty();
        if has_coherent {
            required_features |= wgpu::Features::MEMORY_DECORATION_COHERENT;
        }
        if has_timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        if has_immediates {
            required_features |= wgpu::Features::IMMEDIATES;
        }
        // The adapter's own limits: large scenes need its full storage-binding size, not
        // WebGPU's portable 128 MiB default.
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("tumble"),
            required_features,
            required_limits: limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|e| {
                GpuError::DeviceRequest {
                    adapter: info.name.clone(),
                    reason: e.to_string(),
                }
            })?;
        // Errors outside an error scope and the device's loss are recorded, not panicked on
        // (wgpu's default): the next step or read returns them as an `Err` (`check_health`).
        let health = Arc::new(Health::default());
        let on_error = Arc::clone(&health);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            let mut first = on_error
                .uncaptured
                .lock()
                .unwrap_or_else(|p| p.into_inner());
            first.get_or_insert_with(|| e.to_string());
        }));
        let on_loss = Arc::clone(&health);
        device.set_device_lost_callback(move |reason, message| {
            let mut lost = on_loss.lost.lock().unwrap_or_else(|p| p.into_inner());
            lost.get_or_insert_with(|| format!("{reason:?}: {message}"));
        });
        Ok(Self {
            adapter,
            device,
            queue,
            info,
            has_timestamps,
            has_immediates,
            has_coherent,
            pipelines: Default::default(),
            health,
            read_timeout: Arc::new(AtomicU64::new(DEFAULT_READ_TIMEOUT.as_nanos() as u64)),
        })
    }

    /// `Err` when the device was lost ([`GpuError::DeviceLost`], every later call too) or
    /// reported an error that no error scope caught since the last check
    /// ([`GpuError::Device`], once). Every step checks before recording and after submitting.
    pub fn check_health(&self) -> Result<(), GpuError> {
        if let Some(reason) = self.health.lost() {
            return Err(GpuError::DeviceLost { reason });
        }
        let taken = self
            .health
            .uncaptured
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take();
        match taken {
            Some(message) => Err(GpuError::Device(message)),
            None => Ok(()),
        }
    }

    /// True once the device was lost: nothing on it can run again; open a new context.
    pub fn is_lost(&self) -> bool {
        self.health.lost().is_some()
    }

    /// Submits `encoder`'s commands, then [`check_health`](Self::check_health): a command
    /// buffer that failed validation, or a device lost meanwhile, is an `Err` here.
    pub fn submit(&self, encoder: wgpu::CommandEncoder) -> Result<wgpu::SubmissionIndex, GpuError> {
        self.check_health()?;
        let index = self.queue.submit([encoder.finish()]);
        self.check_health()?;
        Ok(index)
    }

    /// The device for tests: `None` (after a loud "skipped" on stderr) when there is no
    /// adapter, unless [`REQUIRE_GPU_ENV`] is `1` or `true` ([`require_gpu_value`]), where a
    /// missing adapter panics so CI fails. One device is opened per test process and shared.
    pub fn for_tests() -> Option<GpuContext> {
        static SHARED: OnceLock<Result<GpuContext, String>> = OnceLock::new();
        let opened = SHARED.get_or_init(|| GpuContext::new().map_err(|e| e.to_string()));
        match opened {
            Ok(ctx) => Some(ctx.clone()),
            Err(message) => {
                let value = std::env::var(REQUIRE_GPU_ENV).ok();
                assert!(
                    !require_gpu_value(value.as_deref()),
                    "{REQUIRE_GPU_ENV}={} but no usable GPU adapter: {message}",
                    value.as_deref().unwrap_or_default()
                );
                eprintln!(
                    "##### skipped: no GPU adapter ({message}); set {REQUIRE_GPU_ENV}=1 to fail instead #####"
                );
                None
            }
        }
    }

    /// The device's limits.
    pub fn limits(&self) -> wgpu::Limits {
        self.device.limits()
    }

    /// Errs when a buffer of `bytes` cannot be bound as one storage buffer on this device.
    pub fn check_storage_size(&self, what: &str, bytes: u64) -> Result<(), GpuError> {
        let limits = self.device.limits();
        let limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        if bytes > limit {
            return Err(GpuError::LimitExceeded {
                what: what.to_string(),
                value: bytes,
                limit_name: "max_storage_buffer_binding_size",
                limit,
            });
        }
        Ok(())
    }

    /// The longest any blocking wait on this device (a read, [`Self::wait_idle`]) lasts before
    /// it returns [`GpuError::TimedOut`].
    pub fn read_timeout(&self) -> Duration {
        Duration::from_nanos(self.read_timeout.load(Ordering::Relaxed))
    }

    /// Sets [`Self::read_timeout`] for this context and every clone of it (they share the
    /// device, and a world keeps clones). A hung device then fails a read instead of blocking
    /// it forever. Zero is refused: no wait could ever succeed.
    pub fn set_read_timeout(&self, timeout: Duration) -> Result<(), GpuError> {
        if timeout.is_zero() {
            return Err(crate::error::invalid("read_timeout", timeout));
        }
        let nanos = u64::try_from(timeout.as_nanos()).unwrap_or(u64::MAX);
        self.read_timeout.store(nanos, Ordering::Relaxed);
        Ok(())
    }

    /// Blocks until all submitted work is done, at most [`Self::read_timeout`].
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.wait_until(None, || true)
    }

    /// Waits for submission `index` (all submitted work when `None`), then polls until `done`
    /// holds, all within [`Self::read_timeout`]. `done` is what the caller waits on, typically
    /// a map callback having run: when another thread shares the device, its own poll may
    /// have collected the callback and not yet run it when ours returns.
    pub(crate) fn wait_until(
        &self,
        index: Option<wgpu::SubmissionIndex>,
        done: impl Fn() -> bool,
    ) -> Result<(), GpuError> {
        let timeout = self.read_timeout();
        let deadline = Instant::now() + timeout;
        loop {
            self.check_health()?;
            let left = deadline.saturating_duration_since(Instant::now());
            self.device
                .poll(wgpu::PollType::Wait {
                    submission_index: index.clone(),
                    timeout: Some(left),
                })
                .map_err(|e| match e {
                    wgpu::PollError::Timeout => GpuError::TimedOut { after: timeout },
                    e => GpuError::Device(e.to_string()),
                })?;
            self.check_health()?;
            if done() {
                return Ok(());
            }
            if Instant::now() >= deadline {
                return Err(GpuError::TimedOut { after: timeout });
            }
            std::thread::yield_now();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indirect_call_validation_is_off_unless_the_environment_asks() {
        let flags = instance_descriptor().flags;
        match std::env::var("WGPU_VALIDATION_INDIRECT_CALL") {
            Err(_) => assert!(!flags.contains(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL)),
            Ok(v) => assert_eq!(
                flags.contains(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL),
                v != "0"
            ),
        }
    }

    #[test]
    fn require_gpu_accepts_one_and_true_in_any_case() {
        for on in ["1", "true", "TRUE", "True", " true\n", " 1 "] {
            assert!(require_gpu_value(Some(on)), "{on:?} must require a GPU");
        }
        // Unset, empty, off values and near misses keep a missing adapter a skip.
        assert!(!require_gpu_value(None));
        for off in [
            "", "0", "false", "FALSE", "yes", "on", "2", "10", "truee", "t",
        ] {
            assert!(
                !require_gpu_value(Some(off)),
                "{off:?} must not require a GPU"
            );
        }
    }
}
