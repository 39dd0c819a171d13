//! `WorldBatch` on `Backend::Gpu`: the worlds of one config stepped as one device world
//! (`crate::backend::member`).

use std::sync::Arc;

use super::build::{build_error, check_backend, fill, world_error};
use super::{Entry, GpuEntry, Saved, WorldBatch, WorldId, WorldSpec};
use crate::backend::group::Group;
use crate::{Error, World};

impl WorldBatch {
    /// The slot the next inserted world takes (`insert`'s choice).
    fn next_slot(&self) -> u32 {
        self.free.last().copied().unwrap_or(self.slots.len() as u32)
    }

    /// The group of worlds of `spec`'s config, created when it is the first.
    fn group_for(&mut self, spec: &WorldSpec) -> Result<Arc<Group>, Error> {
        if let Some(g) = self.groups.iter().find(|g| *g.config() == spec.config) {
            return Ok(g.clone());
        }
        let group = Group::new(&spec.config)?;
        self.groups.push(group.clone());
        Ok(group)
    }

    /// Builds a GPU world for the next slot (`index` names it in errors); on an error the
    /// group forgets the slot again.
    pub(super) fn build_gpu(&mut self, index: usize, spec: WorldSpec) -> Result<Entry, Error> {
        check_backend(self.backend, index, &spec)?;
        spec.config
            .validate()
            .map_err(|e| build_error(index, None, e.into()))?;
        let slot = self.next_slot();
        let group = self.group_for(&spec)?;
        let built = group
            .world(slot)
            .map_err(|e| build_error(index, None, e))
            .and_then(|world| fill(world, index, spec));
        match built {
            Ok(mut entry) => {
                entry.gpu = Some(GpuEntry {
                    saved: Saved::of(&entry.world),
                    group,
                });
                Ok(entry)
            }
            Err(e) => {
                group.remove(slot)?;
                self.drop_empty_groups()?;
                Err(e)
            }
        }
    }

    /// Takes the world in slot `slot` out of its group (dropping the group's device world
    /// when it was the last).
    pub(super) fn leave_group(&mut self, slot: u32) -> Result<(), Error> {
        let entry = self.slots[slot as usize].entry.as_ref();
        if let Some(g) = entry.and_then(|e| e.gpu.as_ref()) {
            g.group.remove(slot)?;
        }
        self.drop_empty_groups()
    }

    fn drop_empty_groups(&mut self) -> Result<(), Error> {
        let mut kept = Vec::with_capacity(self.groups.len());
        for g in self.groups.drain(..) {
            if !g.is_empty()? {
                kept.push(g);
            }
        }
        self.groups = kept;
        Ok(())
    }

    /// One step of every world: each group laid out again where bodies or worlds changed,
    /// each world's changes staged (`World::step` on its member backend), then one device
    /// step per group.
    pub(super) fn step_gpu(&mut self) -> Result<(), Error> {
        for group in self.groups.clone() {
            if !group.is_dirty()? {
                continue;
            }
            let mut worlds: Vec<(u32, &mut World)> = Vec::new();
            for (i, slot) in self.slots.iter_mut().enumerate() {
                let Some(entry) = slot.entry.as_mut() else {
                    continue;
                };
                let Some(g) = entry.gpu.as_ref() else {
                    continue;
                };
                if !Arc::ptr_eq(&g.group, &group) {
                    continue;
                }
                let id = WorldId {
                    index: i as u32,
                    generation: slot.generation,
                };
                // The device is uploaded from the host copies: bring each up to date.
                let world = &mut entry.world;
                world
                    .backend
                    .sync_motion(&mut world.host)
                    .map_err(|e| world_error(id, e))?;
                worlds.push((i as u32, world));
            }
            group.lay_out(&mut worlds)?;
        }
        // Which worlds have changes to stage, per group.
        let touched: Vec<Vec<bool>> = self
            .groups
            .iter()
            .map(|g| g.take_touched())
            .collect::<Result<_, _>>()?;
        for (i, slot) in self.slots.iter_mut().enumerate() {
            let Some(entry) = slot.entry.as_mut() else {
                continue;
            };
            let id = WorldId {
                index: i as u32,
                generation: slot.generation,
            };
            let Some(g) = entry.gpu.as_ref() else {
                continue;
            };
            let group = self
                .groups
                .iter()
                .position(|o| Arc::ptr_eq(o, &g.group))
                .expect("every GPU world's group is the batch's");
            let world = &mut entry.world;
            if touched[group].get(i).copied().unwrap_or(false) {
                world.step().map_err(|e| world_error(id, e))?;
            } else {
                // Nothing to stage: the step only counts (what `World::step` does around
                // its backend's step).
                world.query.invalidate();
                world.query.stepped();
                world.steps += 1;
            }
            entry.history.step();
        }
        for group in &self.groups {
            group.step()?;
        }
        Ok(())
    }

    /// [`WorldBatch::reset`] on the GPU: each world's saved host copy written back, its pairs
    /// of the last step dropped (a world whose bodies changed since it was saved is laid out
    /// again with its whole group). `ids` are checked.
    pub(super) fn reset_gpu(&mut self, ids: &[WorldId]) -> Result<(), Error> {
        for &id in ids {
            let entry = self.entry_mut(id)?;
            let Some(g) = entry.gpu.as_ref() else {
                continue;
            };
            let world = &mut entry.world;
            // Synced first, so that the next step compares the restored copy with what the
            // device holds and writes every difference.
            world
                .backend
                .sync_motion(&mut world.host)
                .map_err(|e| world_error(id, e))?;
            let reshaped = world.handles.handles() != g.saved.handles.handles();
            world.host = g.saved.host.clone();
            world.handles = g.saved.handles.clone();
            world.steps = g.saved.steps;
            world.query.invalidate();
            // The world's pairs are dropped either way: laid out again or not, it restarts.
            g.group.forget(id.index)?;
            if reshaped {
                g.group.reshaped()?;
            }
            entry.history.rewind();
        }
        Ok(())
    }
}
