//! Contact events on the GPU: after the solver, `contact_begins` (one thread per pair of this
//! step) lists the pairs that touch and the begins, and marks last step's slots still touching;
//! `contact_ends` (one thread per pair of last step) lists the ends. Both read the two pair
//! sets the collision stages keep (this step's parity and the last one's, whose manifolds and
//! impulses are intact until the next step) and append with atomic counters; the host sorts
//! the short lists by body pair, so their order is deterministic.

use crate::kernel::KernelSpec;
use crate::layout::GpuContactEvent;
use crate::shader::file;

/// [`GpuContactEvent::kind`] of a begin.
pub const EVENT_BEGIN: u32 = 0;
/// [`GpuContactEvent::kind`] of an end.
pub const EVENT_END: u32 = 1;
/// [`GpuContactEvent::kind`] of a touching pair.
pub const EVENT_TOUCHING: u32 = 2;

/// Kernel: one thread per pair of this step.
pub static CONTACT_BEGINS: KernelSpec = KernelSpec::new(file("contact_begins.wgsl"));

/// Kernel: one thread per pair of last step.
pub static CONTACT_ENDS: KernelSpec = KernelSpec::new(file("contact_ends.wgsl"));

/// What a step's event kernels found, read back: events and touching pairs in the order the
/// threads appended them (sort them by pair).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactEventList {
    /// Begins and ends.
    pub events: Vec<GpuContactEvent>,
    /// The pairs touching.
    pub touching: Vec<GpuContactEvent>,
}
