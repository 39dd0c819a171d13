//! Reads of poses and velocities straight into the caller's buffers: no allocation, the
//! length checked before anything is written.
//!
//! A world's bodies are written in its internal order ([`crate::World::handles`]; removing a
//! body moves the last one into its place). Whole-batch reads take the worlds by slot
//! ([`crate::WorldBatch::ids`]).

use super::WorldBatch;
use super::error::{BatchError, WorldId};
use crate::{Error, World};

/// Floats per body of a pose read: the centre `x, y, z`, then the rotation quaternion
/// `i, j, k, w`.
pub const POSE_FLOATS: usize = 7;
/// Floats per body of a velocity read: linear `x, y, z` (m/s), then angular `x, y, z`
/// (world axes, rad/s).
pub const VELOCITY_FLOATS: usize = 6;

/// One kind of read: its name, floats per body, and how to write one body.
struct Read {
    what: &'static str,
    floats: usize,
    write: WriteBody,
}

/// Writes body `d` of the world into its chunk of the output.
type WriteBody = fn(&World, usize, &mut [f32]) -> Result<(), Error>;

impl Read {
    const fn new(what: &'static str, floats: usize, write: WriteBody) -> Read {
        Read {
            what,
            floats,
            write,
        }
    }

    /// The same read as the method `what` (its errors name that method).
    const fn named(self, what: &'static str) -> Read {
        Read { what, ..self }
    }
}

fn write_pose(world: &World, d: usize, out: &mut [f32]) -> Result<(), Error> {
    let p = world.backend.pose(&world.host, d)?;
    let (t, q) = (p.translation.vector, p.rotation.coords);
    out.copy_from_slice(&[t.x, t.y, t.z, q.x, q.y, q.z, q.w]);
    Ok(())
}

fn write_velocity(world: &World, d: usize, out: &mut [f32]) -> Result<(), Error> {
    let s = world.backend.state(&world.host, d)?;
    let (v, w) = (s.linear_velocity, s.angular_velocity);
    out.copy_from_slice(&[v.x, v.y, v.z, w.x, w.y, w.z]);
    Ok(())
}

const POSES: Read = Read::new("read_poses", POSE_FLOATS, write_pose);
const ALL_POSES: Read = POSES.named("read_all_poses");
const STRIDED_POSES: Read = POSES.named("read_all_poses_strided");
const VELOCITIES: Read = Read::new("read_velocities", VELOCITY_FLOATS, write_velocity);
const ALL_VELOCITIES: Read = VELOCITIES.named("read_all_velocities");
const STRIDED_VELOCITIES: Read = VELOCITIES.named("read_all_velocities_strided");

/// Writes every body of `world` into `out` (exactly its length).
fn write_world(read: &Read, world: &World, out: &mut [f32]) -> Result<(), Error> {
    #[cfg(feature = "gpu")]
    if let Some((snap, first)) = world.backend.fetched_motion(&world.host)? {
        // A GPU batch's world whose host copy is behind: straight from the device's readback.
        for (d, chunk) in out.chunks_exact_mut(read.floats).enumerate() {
            if read.floats == POSE_FLOATS {
                let p = &snap.poses[first + d];
                chunk[..3].copy_from_slice(&p.position[..3]);
                chunk[3..].copy_from_slice(&p.rotation);
            } else {
                let v = &snap.velocities[first + d];
                chunk[..3].copy_from_slice(&v.linear[..3]);
                chunk[3..].copy_from_slice(&v.angular[..3]);
            }
        }
        return Ok(());
    }
    for (d, chunk) in out.chunks_exact_mut(read.floats).enumerate() {
        (read.write)(world, d, chunk)?;
    }
    Ok(())
}

fn length_error(what: &'static str, expected: usize, given: usize) -> Error {
    BatchError::BufferLength {
        what,
        expected,
        given,
    }
    .into()
}

impl WorldBatch {
    /// Floats of a world's pose read: `POSE_FLOATS` per body.
    pub fn poses_len(&self, id: WorldId) -> Result<usize, Error> {
        Ok(self.body_count(id)? * POSE_FLOATS)
    }

    /// Floats of the whole batch's pose read.
    pub fn all_poses_len(&self) -> usize {
        self.live().map(|(_, w)| w.body_count()).sum::<usize>() * POSE_FLOATS
    }

    /// Floats of the whole batch's velocity read.
    pub fn all_velocities_len(&self) -> usize {
        self.live().map(|(_, w)| w.body_count()).sum::<usize>() * VELOCITY_FLOATS
    }

    /// The most bodies of any world: the smallest stride of a strided read is this times the
    /// floats per body.
    pub fn max_body_count(&self) -> usize {
        self.live().map(|(_, w)| w.body_count()).max().unwrap_or(0)
    }

    /// Writes a world's poses into `out`, which must hold exactly `POSE_FLOATS` floats per
    /// body ([`WorldBatch::poses_len`]).
    pub fn read_poses(&self, id: WorldId, out: &mut [f32]) -> Result<(), Error> {
        self.read_one(&POSES, id, out)
    }

    /// Writes a world's velocities into `out`, which must hold exactly `VELOCITY_FLOATS`
    /// floats per body.
    pub fn read_velocities(&self, id: WorldId, out: &mut [f32]) -> Result<(), Error> {
        self.read_one(&VELOCITIES, id, out)
    }

    /// Writes every world's poses into `out`, one world after another by slot, packed
    /// ([`WorldBatch::all_poses_len`] floats).
    pub fn read_all_poses(&self, out: &mut [f32]) -> Result<(), Error> {
        self.read_all(&ALL_POSES, out)
    }

    /// Writes every world's velocities into `out`, packed as [`WorldBatch::read_all_poses`].
    pub fn read_all_velocities(&self, out: &mut [f32]) -> Result<(), Error> {
        self.read_all(&ALL_VELOCITIES, out)
    }

    /// Writes the `k`-th world's poses (by slot) at `out[k * stride..]`; the floats of a row
    /// past its world's bodies are left as they were. `out` must hold exactly
    /// `len() * stride` floats, and `stride` at least `POSE_FLOATS` per body of every world.
    pub fn read_all_poses_strided(&self, out: &mut [f32], stride: usize) -> Result<(), Error> {
        self.read_strided(&STRIDED_POSES, out, stride)
    }

    /// Writes the `k`-th world's velocities at `out[k * stride..]`, as
    /// [`WorldBatch::read_all_poses_strided`].
    pub fn read_all_velocities_strided(&self, out: &mut [f32], stride: usize) -> Result<(), Error> {
        self.read_strided(&STRIDED_VELOCITIES, out, stride)
    }

    fn read_one(&self, read: &Read, id: WorldId, out: &mut [f32]) -> Result<(), Error> {
        let world = self.world(id)?;
        let expected = world.body_count() * read.floats;
        if out.len() != expected {
            return Err(length_error(read.what, expected, out.len()));
        }
        write_world(read, world, out)
    }

    fn read_all(&self, read: &Read, out: &mut [f32]) -> Result<(), Error> {
        let expected = self.live().map(|(_, w)| w.body_count()).sum::<usize>() * read.floats;
        if out.len() != expected {
            return Err(length_error(read.what, expected, out.len()));
        }
        let mut rest = out;
        for (_, world) in self.live() {
            let (here, tail) = rest.split_at_mut(world.body_count() * read.floats);
            write_world(read, world, here)?;
            rest = tail;
        }
        Ok(())
    }

    fn read_strided(&self, read: &Read, out: &mut [f32], stride: usize) -> Result<(), Error> {
        for (id, world) in self.live() {
            let needed = world.body_count() * read.floats;
            if needed > stride {
                return Err(BatchError::Stride {
                    what: read.what,
                    stride,
                    world: id,
                    bodies: world.body_count(),
                    needed,
                }
                .into());
            }
        }
        let expected = self.len().checked_mul(stride);
        if expected != Some(out.len()) {
            let expected = expected.unwrap_or(usize::MAX);
            return Err(length_error(read.what, expected, out.len()));
        }
        if stride == 0 {
            return Ok(());
        }
        for ((_, world), row) in self.live().zip(out.chunks_exact_mut(stride)) {
            let needed = world.body_count() * read.floats;
            write_world(read, world, &mut row[..needed])?;
        }
        Ok(())
    }
}
