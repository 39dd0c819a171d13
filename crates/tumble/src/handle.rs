//! Body handles: a slot index plus a generation, so a removed body's handle never comes back.

use crate::Error;

/// Identifies a body of a [`crate::World`]. Never reused: removing a body bumps its slot's
/// generation, so old handles report [`Error::RemovedHandle`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BodyHandle {
    index: u32,
    generation: u32,
}

impl BodyHandle {
    /// The slot index (stable for the body's lifetime).
    pub fn index(&self) -> u32 {
        self.index
    }

    /// The slot's generation when the body was added.
    pub fn generation(&self) -> u32 {
        self.generation
    }

    /// A 64-bit id unique over the world's lifetime (generation in the high half).
    pub fn to_bits(&self) -> u64 {
        (u64::from(self.generation) << 32) | u64::from(self.index)
    }

    /// The handle whose [`BodyHandle::to_bits`] is `bits`.
    pub fn from_bits(bits: u64) -> Self {
        Self {
            index: bits as u32,
            generation: (bits >> 32) as u32,
        }
    }
}

/// One slot: its current generation and, while alive, the body's index in the dense arrays.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Slot {
    generation: u32,
    dense: Option<u32>,
}

/// Maps handles to dense body indices and back.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct HandleMap {
    slots: Vec<Slot>,
    free: Vec<u32>,
    /// `handles[d]` is the handle of the body at dense index `d`.
    handles: Vec<BodyHandle>,
}

impl HandleMap {
    /// Registers a body appended at dense index `handles.len()`.
    pub(crate) fn insert(&mut self) -> BodyHandle {
        let dense = self.handles.len() as u32;
        let handle = match self.free.pop() {
            Some(index) => {
                let slot = &mut self.slots[index as usize];
                slot.dense = Some(dense);
                BodyHandle {
                    index,
                    generation: slot.generation,
                }
            }
            None => {
                self.slots.push(Slot {
                    generation: 0,
                    dense: Some(dense),
                });
                BodyHandle {
                    index: self.slots.len() as u32 - 1,
                    generation: 0,
                }
            }
        };
        self.handles.push(handle);
        handle
    }

    /// The dense index of a live handle.
    pub(crate) fn dense(&self, h: BodyHandle) -> Result<usize, Error> {
        let Some(slot) = self.slots.get(h.index as usize) else {
            return Err(Error::UnknownHandle(h));
        };
        if h.generation > slot.generation {
            return Err(Error::UnknownHandle(h));
        }
        match slot.dense {
            Some(d) if slot.generation == h.generation => Ok(d as usize),
            _ => Err(Error::RemovedHandle(h)),
        }
    }

    /// The dense index of the live body whose handle has `bits` as its
    /// [`BodyHandle::to_bits`]; `None` for a removed or unknown body.
    pub(crate) fn dense_of_bits(&self, bits: u64) -> Option<usize> {
        self.dense(BodyHandle::from_bits(bits)).ok()
    }

    /// Removes a live handle whose body sits at dense index `d`, mirroring a `swap_remove` of
    /// the dense arrays: the last body moves into `d`.
    pub(crate) fn remove(&mut self, h: BodyHandle, d: usize) {
        let slot = &mut self.slots[h.index as usize];
        slot.dense = None;
        // A slot whose generation would wrap is retired rather than reused, so a handle can
        // never repeat.
        if let Some(next) = slot.generation.checked_add(1) {
            slot.generation = next;
            self.free.push(h.index);
        }
        self.handles.swap_remove(d);
        if let Some(moved) = self.handles.get(d) {
            self.slots[moved.index as usize].dense = Some(d as u32);
        }
    }

    /// The handle of each dense index.
    pub(crate) fn handles(&self) -> &[BodyHandle] {
        &self.handles
    }

    /// Checks that the map is one `insert` and `remove` could have built for `bodies` live
    /// bodies (each live handle's slot at its generation and dense index, every other slot
    /// free or retired, free slots listed once): the check a map read from outside (a saved
    /// world) must pass. The error says what is wrong.
    pub(crate) fn check(&self, bodies: usize) -> Result<(), String> {
        if self.handles.len() != bodies {
            return Err(format!(
                "{} handles for {bodies} bodies",
                self.handles.len()
            ));
        }
        for (d, h) in self.handles.iter().enumerate() {
            match self.slots.get(h.index as usize) {
                Some(slot) if slot.generation == h.generation && slot.dense == Some(d as u32) => {}
                _ => return Err(format!("handle {h:?} does not name dense index {d}")),
            }
        }
        let live = self.slots.iter().filter(|s| s.dense.is_some()).count();
        if live != bodies {
            return Err(format!("{live} live slots for {bodies} bodies"));
        }
        let mut listed = vec![false; self.slots.len()];
        for &f in &self.free {
            match self.slots.get(f as usize) {
                Some(slot) if slot.dense.is_none() && !listed[f as usize] => {
                    listed[f as usize] = true;
                }
                _ => return Err(format!("free slot {f} is live, listed twice or unknown")),
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removed_handles_stay_removed_when_the_slot_is_reused() {
        let mut map = HandleMap::default();
        let a = map.insert();
        let b = map.insert();
        map.remove(a, 0);
        assert_eq!(map.dense(a), Err(Error::RemovedHandle(a)));
        // b moved into dense slot 0.
        assert_eq!(map.dense(b), Ok(0));
        let c = map.insert();
        assert_eq!(c.index(), a.index());
        assert_ne!(c, a);
        assert_eq!(map.dense(a), Err(Error::RemovedHandle(a)));
        assert_eq!(map.dense(c), Ok(1));
        let never = BodyHandle {
            index: 99,
            generation: 0,
        };
        assert_eq!(map.dense(never), Err(Error::UnknownHandle(never)));
    }
}
