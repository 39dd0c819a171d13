//! The contact kernels on [`LANES`] constraints at once: the constraints of one graph color
//! packed into blocks whose every field holds one value per lane (structure of arrays), so the
//! compiler turns each arithmetic step into one vector instruction.
//!
//! Each lane does exactly what [`crate::contact_solver`] does for one constraint, operation for
//! operation and in the same order (the dot product `(x x' + y y') + z z'` as nalgebra forms
//! it, a quaternion turning a vector as nalgebra does, the clamps as a compare and a select,
//! as the scalar kernel's `max_of` and `min_of` do), and a branch of the scalar code becomes a
//! mask that selects, lane by lane, the new value or the old one. Skipped work is never
//! computed as "add zero": adding `0.0` to `-0.0` changes a bit. So a lane ends with the bits the scalar kernel gives, and the solve's result
//! does not depend on the kernel width (the tests compare the two bit for bit).
//!
//! A color's constraints share no dynamic body, which is what lets them run side by side:
//! every lane reads its bodies' velocities at the start of the block, none reads a body that
//! another lane writes, and each dynamic body is written back by one lane only.
//!
//! `wide.rs` holds the lane arithmetic, `block.rs` the block and its bodies (gathered,
//! scattered, stored), `prepare.rs` the block's constraints prepared lane by lane, `kernels.rs`
//! the passes.

mod block;
mod kernels;
mod prepare;
mod wide;

pub(crate) use block::{LaneBlock, LaneBodies};
pub(crate) use kernels::{restitution, solve, warm_start};
pub(crate) use prepare::{PrepareSource, prefetch, prefetch_block};

/// Constraints per block: 8 lanes of `f32` fill one 256-bit AVX register (x86-64 processors
/// with AVX2 run the kernels so, detected at run time); elsewhere each step takes two 128-bit
/// instructions, which every x86-64 and aarch64 processor has.
pub const LANES: usize = 8;
