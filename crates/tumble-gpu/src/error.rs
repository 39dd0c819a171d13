//! Errors of the GPU runtime: no adapter, limits exceeded, bad input, shader or device failures.

/// Everything that can go wrong between the host and the GPU.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter with compute shaders was found (or none matched the requested name).
    #[error("no GPU adapter with compute shaders found{}", requested.as_deref().map(|n| format!(" matching {}={n:?}", crate::context::ADAPTER_ENV)).unwrap_or_default())]
    NoAdapter {
        /// The adapter name filter that was asked for, if any.
        requested: Option<String>,
    },
    /// The adapter refused to create a device.
    #[error("the adapter {adapter:?} refused to create a device: {reason}")]
    DeviceRequest {
        /// Name of the adapter.
        adapter: String,
        /// The driver's message.
        reason: String,
    },
    /// A scene or buffer needs more than a device limit allows.
    #[error("{what} needs {value}, over the device limit {limit_name} = {limit}")]
    LimitExceeded {
        /// What needed the resource (e.g. "pairs buffer").
        what: String,
        /// The value asked for.
        value: u64,
        /// The wgpu limit (or the engine's own cap) that was exceeded.
        limit_name: &'static str,
        /// The limit's value.
        limit: u64,
    },
    /// Input data the GPU path cannot take (the field and value are named).
    #[error("invalid {field}: {value}")]
    InvalidInput {
        /// Which field was wrong, e.g. `poses[3].rotation`.
        field: String,
        /// The offending value, printed.
        value: String,
    },
    /// More candidate pairs than the pair buffer holds: the list was truncated on the GPU.
    #[error(
        "broad phase found {requested} pairs but the pair buffer holds {capacity}; raise the pair capacity"
    )]
    PairOverflow {
        /// Pairs the sweep tried to append.
        requested: u32,
        /// Slots in the pair buffer.
        capacity: u32,
    },
    /// A shader failed to parse, validate, or build a pipeline.
    #[error("shader {shader}: {message}")]
    Shader {
        /// The kernel's name.
        shader: &'static str,
        /// What naga or wgpu reported.
        message: String,
    },
    /// The device was lost (driver reset, removal, or `Device::destroy`): nothing can run on
    /// it again; a new `GpuContext` must be opened.
    #[error("the GPU device was lost ({reason}); open a new device to continue")]
    DeviceLost {
        /// The reason wgpu gave, with its message.
        reason: String,
    },
    /// A blocking wait (a read, `GpuContext::wait_idle`) passed the context's read timeout
    /// (`GpuContext::set_read_timeout`): the device is hung, or runs work far longer than a
    /// step. The work may still finish; a later read can succeed.
    #[error("the GPU did not finish within the read timeout: timed out after {after:?}")]
    TimedOut {
        /// The read timeout that passed.
        after: std::time::Duration,
    },
    /// Mapping a readback buffer or waiting on the device failed, or the device reported an
    /// error that no error scope caught (a validation or out-of-memory error).
    #[error("GPU device error: {0}")]
    Device(String),
}

/// [`GpuError::InvalidInput`] naming `field`, with `value` printed by `Debug`.
pub(crate) fn invalid(field: impl Into<String>, value: impl std::fmt::Debug) -> GpuError {
    GpuError::InvalidInput {
        field: field.into(),
        value: format!("{value:?}"),
    }
}
