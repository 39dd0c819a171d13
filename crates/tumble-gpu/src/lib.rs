//! Tumble's GPU runtime: device setup, buffers, kernels (each declared once, its pipeline
//! built once per device and override values: [`kernel`]), and the collision stages
//! (`update_aabbs`, `broad_phase`, `narrow_phase`) recorded into one command stream, with the
//! solver stages ([`solver`]) and sleeping islands ([`sleep`]) after them.
//!
//! Shaders are WGSL files in the repository's `shaders/` folder, embedded at compile time and
//! composed from their `// requires:` directives ([`shader`]); constants shared with them are
//! defined in [`constants`] and reach them as `override` values. Every kernel has a CPU twin
//! in its module under [`kernels`].
//!
//! A kernel's source is composed and checked without a device; a [`GpuContext`] opens one:
//!
//! ```
//! use tumble_gpu::GpuContext;
//! use tumble_gpu::shader::{Binding, ShaderSource, reflect_bindings};
//!
//! let source = ShaderSource::of_path("collide_cuboids.wgsl")?;
//! let module = source.parse("collide_cuboids")?;
//! let bindings = reflect_bindings(&module);
//! assert!(bindings.iter().any(|b| b.kind == Binding::StorageReadWrite), "it writes manifolds");
//!
//! match GpuContext::new() {
//!     Ok(ctx) => println!("device: {} ({:?})", ctx.info.name, ctx.info.backend),
//!     // No adapter here: every GPU entry point returns this error instead of panicking.
//!     Err(e) if std::env::var("TUMBLE_REQUIRE_GPU").as_deref() != Ok("1") => {
//!         println!("no GPU: {e}")
//!     }
//!     Err(e) => panic!("TUMBLE_REQUIRE_GPU=1 and no GPU: {e}"),
//! }
//! # Ok::<(), tumble_gpu::GpuError>(())
//! ```
#![warn(missing_docs)]

pub mod buffer_pool;
pub mod collision;
pub mod constants;
pub mod context;
pub mod error;
pub mod kernel;
pub mod kernels;
pub mod layout;
pub mod readback;
pub mod registry;
pub mod shader;
pub mod sleep;
pub mod solver;
pub mod stage_timer;
pub mod step;
mod transfer;

pub use buffer_pool::BufferPool;
pub use collision::{CollisionConfig, CollisionSnapshot, GpuCollision, ReadbackRequest};
pub use constants::{MAX_BODIES, MAX_MANIFOLD_POINTS, RADIX, RADIX_BITS, WORKGROUP_SIZE};
pub use context::{GpuContext, GpuOptions};
pub use error::GpuError;
pub use kernel::{Kernel, KernelSpec};
pub use readback::Readback;
pub use stage_timer::StageTimer;

/// Re-export of the WGSL front end and validator, for shader checks in tests and tools.
pub use naga;
/// Re-export of the GPU API.
pub use wgpu;

/// The capabilities wgpu's own validator uses for our pipelines: naga's defaults, immediate
/// data and `@coherent` storage, the shader-affecting features a device may enable
/// (timestamps are a pass-level feature). Only `solve_color_immediate` uses immediate data and
/// only `solve_step` `@coherent`, and each is built only on devices that have it
/// ([`GpuContext::has_immediates`], [`GpuContext::has_coherent`]).
pub fn validation_capabilities() -> naga::valid::Capabilities {
    naga::valid::Capabilities::default()
        | naga::valid::Capabilities::IMMEDIATES
        | naga::valid::Capabilities::MEMORY_DECORATION_COHERENT
}

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
