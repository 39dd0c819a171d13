//! [`WorldBatch`]: many independent worlds stepped together, with per-world actions given as
//! one array, reads into the caller's buffers and resets of any subset of worlds.
//!
//! Each world is a whole [`World`] of its own (its own bodies, config and handles); the batch
//! adds the loop over them and the bookkeeping a reset needs. On `Backend::Cpu` the worlds
//! step in parallel on the rayon pool, one task per world, and a reset replays the world's
//! log ([`history`]). On `Backend::Gpu` the worlds of one config share one device world: one
//! set of buffers and one set of dispatches steps them all (`crate::backend::member`), and a
//! reset writes the saved bodies back and drops the world's contact history, so the world
//! restarts as one built from that state. On `Backend::Hybrid` they step one after another.

mod action;
mod build;
mod error;
#[cfg(feature = "gpu")]
mod gpu;
mod history;
mod read;

use rayon::prelude::*;
use tumble_scenes::Scene;

pub use action::{Action, ActionKind};
pub use build::WorldSpec;
use build::{build, build_all, build_error, world_error};
pub use error::{BatchError, WorldId};
pub use read::{POSE_FLOATS, VELOCITY_FLOATS};

#[cfg(feature = "gpu")]
use crate::backend::group::Group;
use crate::{Backend, BodyDesc, BodyHandle, Error, World, WorldConfig};
use history::History;

/// One world of the batch and its log.
#[derive(Debug)]
struct Entry {
    world: World,
    history: History,
    /// On `Backend::Gpu`: the device world the world is part of, and its saved state.
    #[cfg(feature = "gpu")]
    gpu: Option<GpuEntry>,
}

/// A GPU batch world's group and the state [`WorldBatch::reset`] returns it to.
#[cfg(feature = "gpu")]
#[derive(Debug)]
struct GpuEntry {
    group: std::sync::Arc<Group>,
    saved: Saved,
}

/// A GPU batch world's saved state: its host copy, handles and step count.
#[cfg(feature = "gpu")]
#[derive(Debug)]
struct Saved {
    host: crate::backend::Host,
    handles: crate::handle::HandleMap,
    steps: u64,
}

#[cfg(feature = "gpu")]
impl Saved {
    fn of(world: &World) -> Self {
        Self {
            host: world.host.clone(),
            handles: world.handles.clone(),
            steps: world.steps,
        }
    }
}

/// A slot of the batch: its generation and, while a world lives there, the world.
#[derive(Debug)]
struct Slot {
    generation: u32,
    entry: Option<Entry>,
}

/// Independent worlds stepped together; every world runs on the batch's backend.
///
/// ```
/// use tumble::prelude::*;
/// use tumble::{Action, WorldBatch, WorldSpec};
///
/// let floor = BodyDesc::fixed().cuboid(Vec3::new(5.0, 0.5, 5.0)).translation(0.0, -0.5, 0.0);
/// let specs: Vec<WorldSpec> = (0..4)
///     .map(|i| {
///         WorldSpec::new(WorldConfig::default())
///             .body(floor)
///             .body(BodyDesc::dynamic().translation(0.0, 1.0 + i as f32, 0.0))
///     })
///     .collect();
/// let mut batch = WorldBatch::from_specs(Backend::Cpu, specs)?;
/// let ids = batch.ids();
/// let cube = batch.handles(ids[2])?[1];
/// batch.apply_actions(&[Action::set_velocity(ids[2], cube, Vec3::x(), Vec3::zeros())])?;
/// for _ in 0..60 {
///     batch.step()?;
/// }
/// let mut poses = vec![0.0; batch.all_poses_len()];
/// batch.read_all_poses(&mut poses)?;
/// batch.reset(&[ids[2]])?; // back to its state when it was added
/// assert_eq!(batch.step_count(ids[2])?, 0);
/// # Ok::<(), tumble::Error>(())
/// ```
#[derive(Debug)]
pub struct WorldBatch {
    backend: Backend,
    slots: Vec<Slot>,
    free: Vec<u32>,
    /// On `Backend::Gpu`: one device world per distinct config.
    #[cfg(feature = "gpu")]
    groups: Vec<std::sync::Arc<Group>>,
}

impl WorldBatch {
    /// An empty batch whose worlds will run on `backend`.
    pub fn new(backend: Backend) -> Self {
        Self {
            backend,
            slots: Vec::new(),
            free: Vec::new(),
            #[cfg(feature = "gpu")]
            groups: Vec::new(),
        }
    }

    /// A batch of the worlds `specs`, numbered in order (the ids of [`WorldBatch::ids`]).
    /// Errs, naming the world and body, on any bad config or body.
    pub fn from_specs(backend: Backend, specs: Vec<WorldSpec>) -> Result<Self, Error> {
        let mut batch = Self::new(backend);
        #[cfg(feature = "gpu")]
        if backend == Backend::Gpu {
            for (i, spec) in specs.into_iter().enumerate() {
                let entry = batch.build_gpu(i, spec)?;
                batch.insert(entry);
            }
            return Ok(batch);
        }
        let built = build_all(backend, specs)?;
        for entry in built {
            batch.insert(entry);
        }
        Ok(batch)
    }

    /// A batch of one world per scene, each built as [`World::from_scene`] builds it with
    /// `config` (whose backend is the batch's).
    pub fn from_scenes(scenes: &[Scene], config: WorldConfig) -> Result<Self, Error> {
        let specs = scenes
            .iter()
            .enumerate()
            .map(|(i, s)| WorldSpec::from_scene(s, config).map_err(|e| build_error(i, None, e)))
            .collect::<Result<Vec<_>, _>>()?;
        Self::from_specs(config.backend, specs)
    }

    /// Adds a world; its id and the handles of its bodies, in the spec's order.
    pub fn add_world(&mut self, spec: WorldSpec) -> Result<(WorldId, Vec<BodyHandle>), Error> {
        #[cfg(feature = "gpu")]
        if self.backend == Backend::Gpu {
            let entry = self.build_gpu(0, spec)?;
            let handles = entry.world.handles().to_vec();
            return Ok((self.insert(entry), handles));
        }
        let entry = build(self.backend, 0, spec)?;
        let handles = entry.world.handles().to_vec();
        Ok((self.insert(entry), handles))
    }

    /// Removes a world; its id is never valid again.
    pub fn remove_world(&mut self, id: WorldId) -> Result<(), Error> {
        self.entry(id)?;
        #[cfg(feature = "gpu")]
        self.leave_group(id.index)?;
        let slot = &mut self.slots[id.index as usize];
        slot.entry = None;
        // A slot whose generation would wrap is retired, so an id never repeats.
        if let Some(next) = slot.generation.checked_add(1) {
            slot.generation = next;
            self.free.push(id.index);
        }
        Ok(())
    }

    /// The backend every world runs on.
    pub fn backend(&self) -> Backend {
        self.backend
    }

    /// Device worlds the batch steps: on `Backend::Gpu` one per distinct `WorldConfig` among
    /// its worlds (each step of the batch is one GPU step per device world, whatever the
    /// number of worlds); 0 on the other backends.
    pub fn device_worlds(&self) -> usize {
        #[cfg(feature = "gpu")]
        return self.groups.len();
        #[cfg(not(feature = "gpu"))]
        0
    }

    /// On `Backend::Gpu` with GPU timestamps, the GPU time of each stage of the last step,
    /// seconds, summed over the device worlds (empty otherwise). Waits for the GPU.
    pub fn device_timings(&self) -> Result<Vec<(&'static str, f64)>, Error> {
        #[cfg(feature = "gpu")]
        {
            let mut out: Vec<(&'static str, f64)> = Vec::new();
            for g in &self.groups {
                for (name, s) in g.timings()? {
                    match out.iter_mut().find(|(n, _)| *n == name) {
                        Some(o) => o.1 += s,
                        None => out.push((name, s)),
                    }
                }
            }
            Ok(out)
        }
        #[cfg(not(feature = "gpu"))]
        Ok(Vec::new())
    }

    /// Bytes of GPU buffers the batch holds: its device worlds' on `Backend::Gpu`, its worlds'
    /// own on `Backend::Hybrid`, 0 on `Backend::Cpu`.
    pub fn device_buffer_bytes(&self) -> u64 {
        #[cfg(feature = "gpu")]
        if self.backend == Backend::Gpu {
            return self.groups.iter().map(|g| g.device_buffer_bytes()).sum();
        }
        self.live().map(|(_, w)| w.device_buffer_bytes()).sum()
    }

    /// Number of worlds.
    pub fn len(&self) -> usize {
        self.slots.iter().filter(|s| s.entry.is_some()).count()
    }

    /// True when the batch holds no world.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The ids of the worlds, by slot: the order of every whole-batch read.
    pub fn ids(&self) -> Vec<WorldId> {
        self.live().map(|(id, _)| id).collect()
    }

    /// A world, for any read `World` offers (poses by handle, contacts, statistics).
    pub fn world(&self, id: WorldId) -> Result<&World, Error> {
        Ok(&self.entry(id)?.world)
    }

    /// The handles of a world's bodies, in its internal order: the order of the reads.
    pub fn handles(&self, id: WorldId) -> Result<&[BodyHandle], Error> {
        Ok(self.entry(id)?.world.handles())
    }

    /// A world's body count.
    pub fn body_count(&self, id: WorldId) -> Result<usize, Error> {
        Ok(self.entry(id)?.world.body_count())
    }

    /// Steps a world has taken since it was added (or since the state it was last reset to).
    pub fn step_count(&self, id: WorldId) -> Result<u64, Error> {
        Ok(self.entry(id)?.world.step_count())
    }

    /// Adds a body to a world. Errs, leaving the batch unchanged, on a bad field of `desc`.
    pub fn add_body(&mut self, id: WorldId, desc: BodyDesc) -> Result<BodyHandle, Error> {
        let entry = self.entry_mut(id)?;
        let h = entry.world.add_body(desc).map_err(|e| world_error(id, e))?;
        entry.history.add(desc);
        #[cfg(feature = "gpu")]
        if let Some(g) = &entry.gpu {
            g.group.reshaped()?;
        }
        Ok(h)
    }

    /// Removes a body from a world (as [`World::remove_body`]).
    pub fn remove_body(&mut self, id: WorldId, h: BodyHandle) -> Result<(), Error> {
        let entry = self.entry_mut(id)?;
        entry.world.remove_body(h).map_err(|e| world_error(id, e))?;
        entry.history.remove(h);
        #[cfg(feature = "gpu")]
        if let Some(g) = &entry.gpu {
            g.group.reshaped()?;
        }
        Ok(())
    }

    /// Steps every world by its own `dt`: on `Backend::Cpu` in parallel, one rayon task per
    /// world; on `Backend::Gpu` as one GPU step per device world (the worlds of one config
    /// share one: [`WorldBatch::device_worlds`]), each world's changes since the last step
    /// written first; on `Backend::Hybrid` one world after another. Each world computes the
    /// same bits as when stepped alone on the same backend with the same calls.
    ///
    /// A world whose step fails is left as before it (as a `World` whose step errs); the
    /// others take their step. The error names the first failed world by slot.
    pub fn step(&mut self) -> Result<(), Error> {
        #[cfg(feature = "gpu")]
        if self.backend == Backend::Gpu {
            return self.step_gpu();
        }
        let step = |(i, slot): (usize, &mut Slot)| -> Option<(usize, Error)> {
            let entry = slot.entry.as_mut()?;
            match entry.world.step() {
                Ok(()) => {
                    entry.history.step();
                    None
                }
                Err(e) => Some((i, e)),
            }
        };
        let failed = if self.backend == Backend::Cpu {
            self.slots
                .par_iter_mut()
                .enumerate()
                .filter_map(step)
                .min_by_key(|(i, _)| *i)
        } else {
            self.slots.iter_mut().enumerate().filter_map(step).next()
        };
        match failed {
            None => Ok(()),
            Some((i, e)) => {
                let id = WorldId {
                    index: i as u32,
                    generation: self.slots[i].generation,
                };
                Err(world_error(id, e))
            }
        }
    }

    /// Applies `actions` in order. Every entry is checked first (its world and body, and
    /// each value against the bounds of the `World` method it stands for, from the state the
    /// earlier entries leave); when one is bad the error names its index, field and value and
    /// no entry is applied.
    pub fn apply_actions(&mut self, actions: &[Action]) -> Result<(), Error> {
        action::plan(actions, |id| {
            self.entry(id).map(|e| &e.world).map_err(|e| match e {
                Error::Batch(b) => b,
                other => BatchError::World {
                    world: id,
                    error: Box::new(other),
                },
            })
        })?;
        for a in actions {
            let entry = self.entry_mut(a.world)?;
            // Checked above with the same bounds: an error here is a device failure (the GPU
            // backends read the state back first), reported as the world's.
            action::apply(&mut entry.world, a.body, &a.kind)
                .map_err(|e| world_error(a.world, e))?;
            entry.history.action(a.body, a.kind);
        }
        Ok(())
    }

    /// Makes a world's present state the one [`WorldBatch::reset`] returns it to. Until
    /// this is called, a world's saved state is the one it was added in. On `Backend::Gpu`
    /// the saved state is the bodies' (poses, velocities, the bodies themselves), not the
    /// world's contacts: see [`WorldBatch::reset`].
    pub fn save_state(&mut self, id: WorldId) -> Result<(), Error> {
        let entry = self.entry_mut(id)?;
        #[cfg(feature = "gpu")]
        if let Some(g) = entry.gpu.as_mut() {
            entry
                .world
                .backend
                .sync_motion(&mut entry.world.host)
                .map_err(|e| world_error(id, e))?;
            g.saved = Saved::of(&entry.world);
        }
        entry.history.save();
        Ok(())
    }

    /// Steps a reset of the world replays: those between its creation and its saved state.
    pub fn reset_cost_steps(&self, id: WorldId) -> Result<u64, Error> {
        Ok(self.entry(id)?.history.saved_steps())
    }

    /// Returns each world of `ids` to its saved state; the other worlds are untouched.
    ///
    /// On `Backend::Cpu` and `Backend::Hybrid` the reset world then steps exactly as it did
    /// from that state: it is rebuilt from its config and its log replayed up to the saved
    /// state (see the `history` module for the cost; on `Backend::Cpu` in parallel).
    ///
    /// On `Backend::Gpu` the saved bodies are written back and the world's contacts are
    /// dropped, at no cost in steps: the world restarts cold, as a world built from that
    /// state (no warm start, no color seeds), which for the state a world was added in is
    /// exactly what it did the first time. When any id is bad or any rebuild fails, no world
    /// is reset.
    pub fn reset(&mut self, ids: &[WorldId]) -> Result<(), Error> {
        for &id in ids {
            self.entry(id)?;
        }
        #[cfg(feature = "gpu")]
        if self.backend == Backend::Gpu {
            return self.reset_gpu(ids);
        }
        let mut todo: Vec<u32> = ids.iter().map(|id| id.index).collect();
        todo.sort_unstable();
        todo.dedup();
        let replay = |&i: &u32| -> Result<World, Error> {
            let id = self.id_at(i);
            let entry = self.slots[i as usize]
                .entry
                .as_ref()
                .expect("checked above");
            entry.history.replay().map_err(|e| world_error(id, e))
        };
        let rebuilt: Vec<Result<World, Error>> = if self.backend == Backend::Cpu {
            todo.par_iter().map(replay).collect()
        } else {
            todo.iter().map(replay).collect()
        };
        // The first failure by slot, so the error does not depend on scheduling.
        let rebuilt: Vec<World> = rebuilt.into_iter().collect::<Result<_, _>>()?;
        for (i, world) in todo.into_iter().zip(rebuilt) {
            let entry = self.slots[i as usize]
                .entry
                .as_mut()
                .expect("checked above");
            entry.world = world;
            entry.history.rewind();
        }
        Ok(())
    }

    /// The live worlds by slot, with their ids.
    fn live(&self) -> impl Iterator<Item = (WorldId, &World)> {
        self.slots.iter().enumerate().filter_map(|(i, s)| {
            s.entry.as_ref().map(|e| {
                (
                    WorldId {
                        index: i as u32,
                        generation: s.generation,
                    },
                    &e.world,
                )
            })
        })
    }

    /// The id of the world in slot `i`.
    fn id_at(&self, i: u32) -> WorldId {
        WorldId {
            index: i,
            generation: self.slots[i as usize].generation,
        }
    }

    fn insert(&mut self, entry: Entry) -> WorldId {
        match self.free.pop() {
            Some(i) => {
                self.slots[i as usize].entry = Some(entry);
                self.id_at(i)
            }
            None => {
                self.slots.push(Slot {
                    generation: 0,
                    entry: Some(entry),
                });
                self.id_at(self.slots.len() as u32 - 1)
            }
        }
    }

    fn check(&self, id: WorldId) -> Result<(), BatchError> {
        let Some(slot) = self.slots.get(id.index as usize) else {
            return Err(BatchError::UnknownWorld(id));
        };
        if id.generation > slot.generation {
            return Err(BatchError::UnknownWorld(id));
        }
        if id.generation < slot.generation || slot.entry.is_none() {
            return Err(BatchError::RemovedWorld(id));
        }
        Ok(())
    }

    fn entry(&self, id: WorldId) -> Result<&Entry, Error> {
        self.check(id)?;
        Ok(self.slots[id.index as usize]
            .entry
            .as_ref()
            .expect("checked"))
    }

    fn entry_mut(&mut self, id: WorldId) -> Result<&mut Entry, Error> {
        self.check(id)?;
        Ok(self.slots[id.index as usize]
            .entry
            .as_mut()
            .expect("checked"))
    }
}
