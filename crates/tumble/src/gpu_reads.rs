//! What a `Backend::Gpu` step left on the GPU and the host has not read yet.
//!
//! A GPU step is submitted and not waited for. The results the caller is expected to read
//! (see [`crate::ReadbackOverrides`]) are copied to a staging buffer in the step's own
//! command stream; the first getter that needs one waits for that copy (the GPU's two staging
//! slots let the next step run while this one is read) and decodes only the part it needs.
//! A part the step did not copy is read from the GPU buffers on demand, which is still
//! correct, since nothing touches them before the next step. Parts are decoded once and kept
//! until the next step, so reading 40,000 poses one handle at a time costs one copy.
//!
//! Getters take `&self`, so the decoded parts live in `OnceLock`s and the GPU world behind a
//! mutex that only reads lock (a step has `&mut` access and never locks).

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use tumble_geometry::Pose;
use tumble_gpu::GpuError;
use tumble_gpu::kernels::contact_summary::ContactSummary;
use tumble_gpu::step::{GpuWorld, ReadRequest, Snapshot};
use tumble_solver::{BodyState, Contact, Stage};

use crate::backend::pipeline::max_penetration;
use crate::{BodyHandle, StageTimings, StepStats};

/// Which parts of a step's results are read (or to be copied).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Reads {
    /// Every body's pose.
    pub poses: bool,
    /// Every body's velocities.
    pub velocities: bool,
    /// The manifolds with their impulses.
    pub contacts: bool,
    /// Which bodies sleep.
    pub sleeping: bool,
    /// The contact counts (`ContactSummary`).
    pub summary: bool,
}

impl Reads {
    const POSES: u8 = 1;
    const VELOCITIES: u8 = 2;
    const CONTACTS: u8 = 4;
    const SLEEPING: u8 = 8;
    const SUMMARY: u8 = 16;

    fn bits(self) -> u8 {
        (u8::from(self.poses) * Self::POSES)
            | (u8::from(self.velocities) * Self::VELOCITIES)
            | (u8::from(self.contacts) * Self::CONTACTS)
            | (u8::from(self.sleeping) * Self::SLEEPING)
            | (u8::from(self.summary) * Self::SUMMARY)
    }

    fn from_bits(bits: u8) -> Self {
        Self {
            poses: bits & Self::POSES != 0,
            velocities: bits & Self::VELOCITIES != 0,
            contacts: bits & Self::CONTACTS != 0,
            sleeping: bits & Self::SLEEPING != 0,
            summary: bits & Self::SUMMARY != 0,
        }
    }

    /// The GPU world's request for these parts.
    pub(crate) fn request(self) -> ReadRequest {
        ReadRequest {
            poses: self.poses,
            velocities: self.velocities,
            contacts: self.contacts,
            sleeping: self.sleeping,
            summary: self.summary,
        }
    }
}

/// The step's manifolds as the facade reports them.
#[derive(Debug, Default)]
pub(crate) struct ContactView {
    /// Manifolds with points, dense body indices at the time of the step.
    pub contacts: Vec<Contact>,
    /// The body handles of each manifold.
    pub handles: Vec<(BodyHandle, BodyHandle)>,
    /// Candidate pairs the GPU examined.
    pub pairs: usize,
}

/// The staging copy of the step, taken apart as getters need its parts.
#[derive(Debug)]
enum Copy {
    /// Recorded with the step, not waited for yet.
    InFlight,
    /// Arrived; parts already decoded are taken out.
    Arrived(Box<Snapshot>),
    /// Nothing copied with the step.
    None,
}

/// Results of the last GPU step not yet read by the host.
#[derive(Debug)]
pub(crate) struct Unread {
    /// The GPU world's step count after the step, to recognize its copy.
    step: u64,
    /// The body handles at the time of the step, in dense order.
    handles: Vec<BodyHandle>,
    copy: Mutex<Copy>,
    /// Parts some getter asked for ([`Reads`] bits): the next step copies these.
    asked: AtomicU8,
    poses: OnceLock<Result<Vec<Pose>, String>>,
    velocities: OnceLock<Result<Vec<BodyState>, String>>,
    contacts: OnceLock<Result<ContactView, String>>,
    sleeping: OnceLock<Result<Vec<bool>, String>>,
    summary: OnceLock<Result<ContactSummary, String>>,
    stats: OnceLock<StepStats>,
    /// What the step copied with it.
    recorded: Reads,
    /// True once a mutating call copied poses and velocities into the world's host arrays,
    /// which are then the state to report (and to upload changes from).
    pub motion_in_host: bool,
}

fn failed(e: GpuError) -> String {
    format!("reading the GPU step's results failed: {e}")
}

impl Unread {
    /// The step just submitted, which copied `recorded` with it.
    pub(crate) fn new(step: u64, handles: Vec<BodyHandle>, recorded: Reads) -> Self {
        let nothing = recorded == Reads::default();
        Self {
            step,
            handles,
            copy: Mutex::new(if nothing { Copy::None } else { Copy::InFlight }),
            asked: AtomicU8::new(0),
            poses: OnceLock::new(),
            velocities: OnceLock::new(),
            contacts: OnceLock::new(),
            sleeping: OnceLock::new(),
            summary: OnceLock::new(),
            stats: OnceLock::new(),
            recorded,
            motion_in_host: false,
        }
    }

    /// The parts getters asked for since the step.
    pub(crate) fn asked(&self) -> Reads {
        Reads::from_bits(self.asked.load(Ordering::Relaxed))
    }

    /// The first read failure, if any: reported by the next fallible call.
    pub(crate) fn error(&self) -> Option<String> {
        fn err<T>(r: Option<&Result<T, String>>) -> Option<String> {
            r.and_then(|r| r.as_ref().err().cloned())
        }
        err(self.poses.get())
            .or_else(|| err(self.velocities.get()))
            .or_else(|| err(self.contacts.get()))
            .or_else(|| err(self.sleeping.get()))
            .or_else(|| err(self.summary.get()))
    }

    /// Reads `want` from the step's copy where it holds it, from the GPU buffers otherwise.
    fn fetch(&self, gpu: &Mutex<GpuWorld>, want: Reads) -> Result<Snapshot, GpuError> {
        self.asked.fetch_or(want.bits(), Ordering::Relaxed);
        let mut gpu = gpu
            .lock()
            .map_err(|_| GpuError::Device("the GPU world's lock was poisoned".into()))?;
        let mut copy = self
            .copy
            .lock()
            .map_err(|_| GpuError::Device("the readback's lock was poisoned".into()))?;
        if matches!(*copy, Copy::InFlight) {
            *copy = match gpu.wait_snapshot()? {
                Some(s) if s.step == self.step => Copy::Arrived(Box::new(s)),
                _ => Copy::None,
            };
        }
        let mut out = Snapshot {
            step: self.step,
            ..Default::default()
        };
        if let Copy::Arrived(s) = &mut *copy {
            if want.poses {
                out.poses = std::mem::take(&mut s.poses);
            }
            if want.velocities {
                out.velocities = std::mem::take(&mut s.velocities);
            }
            if want.sleeping {
                out.sleeping = std::mem::take(&mut s.sleeping);
            }
            if want.contacts {
                // A copy sized from an older count may have missed manifolds: read them all.
                out.contacts = s
                    .contacts
                    .take()
                    .filter(|c| c.work.count as usize <= c.manifolds.len());
            }
            if want.summary {
                out.summary = s.summary.take();
            }
        }
        let missing = ReadRequest {
            poses: want.poses && out.poses.is_empty(),
            velocities: want.velocities && out.velocities.is_empty(),
            contacts: want.contacts && out.contacts.is_none(),
            sleeping: want.sleeping && out.sleeping.is_empty(),
            summary: want.summary && out.summary.is_none(),
        };
        if missing != ReadRequest::default() {
            let direct = gpu.read_now(missing)?;
            if missing.poses {
                out.poses = direct.poses;
            }
            if missing.velocities {
                out.velocities = direct.velocities;
            }
            if missing.contacts {
                out.contacts = direct.contacts;
            }
            if missing.sleeping {
                out.sleeping = direct.sleeping;
            }
            if missing.summary {
                out.summary = direct.summary;
            }
        }
        Ok(out)
    }

    /// The value of `cell`, made by `decode` from a fetch of `bits` the first time it is asked
    /// for; a failed fetch is kept as its message.
    fn decoded<'a, T>(
        &self,
        cell: &'a OnceLock<Result<T, String>>,
        gpu: &Mutex<GpuWorld>,
        bits: u8,
        decode: impl FnOnce(Snapshot) -> T,
    ) -> Result<&'a T, String> {
        let value = cell.get_or_init(|| {
            let s = self.fetch(gpu, Reads::from_bits(bits)).map_err(failed)?;
            Ok(decode(s))
        });
        value.as_ref().map_err(Clone::clone)
    }

    /// Every body's pose after the step.
    pub(crate) fn poses(&self, gpu: &Mutex<GpuWorld>) -> Result<&[Pose], String> {
        let poses = self.decoded(&self.poses, gpu, Reads::POSES, |s| {
            (0..s.poses.len()).map(|i| s.pose(i)).collect()
        });
        poses.map(Vec::as_slice)
    }

    /// Every body's velocities after the step.
    pub(crate) fn velocities(&self, gpu: &Mutex<GpuWorld>) -> Result<&[BodyState], String> {
        let velocities = self.decoded(&self.velocities, gpu, Reads::VELOCITIES, |s| {
            (0..s.velocities.len()).map(|i| s.state(i)).collect()
        });
        velocities.map(Vec::as_slice)
    }

    /// Which bodies sleep after the step.
    pub(crate) fn sleeping(&self, gpu: &Mutex<GpuWorld>) -> Result<&[bool], String> {
        let flags = self.decoded(&self.sleeping, gpu, Reads::SLEEPING, |s| s.sleeping);
        flags.map(Vec::as_slice)
    }

    /// The step's manifolds with their impulses.
    pub(crate) fn contacts(&self, gpu: &Mutex<GpuWorld>) -> Result<&ContactView, String> {
        self.decoded(&self.contacts, gpu, Reads::CONTACTS, |s| {
            let set = s.contacts.unwrap_or_default();
            let contacts = set.contacts();
            let handles = contacts
                .iter()
                .map(|c| {
                    (
                        self.handles[c.body_a as usize],
                        self.handles[c.body_b as usize],
                    )
                })
                .collect();
            ContactView {
                contacts,
                handles,
                pairs: set.work.count as usize,
            }
        })
    }

    /// The step's statistics: counts from its manifolds where the host has them already,
    /// else from the GPU's 32-byte summary of them (`contact_summary`, the same numbers), and
    /// stage times from its timestamps.
    pub(crate) fn stats(&self, gpu: &Mutex<GpuWorld>) -> &StepStats {
        self.stats.get_or_init(|| {
            let timings = gpu
                .lock()
                .ok()
                .and_then(|mut g| g.timings().ok())
                .map(|stages| stage_timings(&stages))
                .unwrap_or_default();
            let stats = StepStats {
                bodies: self.handles.len(),
                timings,
                ..Default::default()
            };
            // The manifolds where the host has them or the step copied them (and not the
            // summary): the counts cost no other read then.
            let copied = self.recorded.contacts && !self.recorded.summary;
            if self.contacts.get().is_some() || copied {
                let Ok(view) = self.contacts(gpu) else {
                    return stats;
                };
                let contacts = view.contacts.as_slice();
                return StepStats {
                    pairs: view.pairs,
                    manifolds: contacts.len(),
                    recycled_manifolds: contacts.iter().filter(|c| c.recycled).count(),
                    contact_points: contacts.iter().map(|c| c.manifold.len as usize).sum(),
                    max_penetration: max_penetration(contacts),
                    ..stats
                };
            }
            match self.decoded(&self.summary, gpu, Reads::SUMMARY, |s| {
                s.summary.unwrap_or_default()
            }) {
                Ok(summary) => StepStats {
                    pairs: summary.pairs as usize,
                    manifolds: summary.manifolds as usize,
                    recycled_manifolds: summary.recycled as usize,
                    contact_points: summary.points as usize,
                    max_penetration: summary.max_depth,
                    ..stats
                },
                // Kept in its cell: the next fallible call reports it.
                Err(_) => stats,
            }
        })
    }
}

/// GPU stage times (timestamps) folded into the facade's stages: a timestamp named after a
/// [`Stage`] (or `"stage: part"`, as the sleep stage's kernels are) counts for that stage; the
/// rest (prepare, the substeps, the fused kernel, queued impulses) for the solve.
pub(crate) fn stage_timings(stages: &[(&'static str, f64)]) -> StageTimings {
    let mut t = StageTimings::default();
    for &(name, seconds) in stages {
        let stage = name
            .split(':')
            .next()
            .and_then(|n| Stage::from_name(n.trim()))
            .unwrap_or(Stage::Solve);
        t[stage] += Duration::from_secs_f64(seconds);
    }
    t
}
