//! The constraint store's layout on the host: constraints live on the GPU as a structure of
//! arrays of 16-byte rows (`shaders/solver/common/constraint_store.wgsl`), row `r` of the
//! constraint in slot `s` at row index `r * stride + s`, and slot `s` holds the constraint of
//! manifold `color_order[s]`. A color's constraints are consecutive slots, so the threads of a
//! per-color pass read each of their rows in one coalesced access.

use super::constants::{CONSTRAINT_ROW_BYTES, CONSTRAINT_ROWS};
use super::layout::GpuConstraint;
use crate::GpuError;

/// Slots of a store buffer of `bytes` bytes (the shaders' `arrayLength / CONSTRAINT_ROWS`).
pub fn store_stride(bytes: u64) -> u64 {
    bytes / CONSTRAINT_ROW_BYTES as u64 / u64::from(CONSTRAINT_ROWS)
}

/// The constraints of the store's `rows` (`stride` slots) by manifold index, for the manifolds
/// `order` lists slot by slot (one entry per slot in use, a permutation of the manifolds).
pub fn constraints_by_manifold(
    rows: &[[u32; 4]],
    stride: u64,
    order: &[u32],
) -> Result<Vec<GpuConstraint>, GpuError> {
    let stride = stride as usize;
    if order.len() > stride || rows.len() < stride * CONSTRAINT_ROWS as usize {
        return Err(GpuError::Device(format!(
            "constraint store of {} rows holds {stride} slots, not {}",
            rows.len(),
            order.len()
        )));
    }
    let mut out = vec![GpuConstraint::default(); order.len()];
    for (slot, &manifold) in order.iter().enumerate() {
        let Some(target) = out.get_mut(manifold as usize) else {
            return Err(GpuError::Device(format!(
                "color order slot {slot} names manifold {manifold} of {}",
                order.len()
            )));
        };
        let words: &mut [[u32; 4]] = bytemuck::cast_slice_mut(std::slice::from_mut(target));
        for (r, word) in words.iter_mut().enumerate() {
            *word = rows[r * stride + slot];
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_of_a_slot_reassemble_its_manifolds_constraint() {
        // Three constraints whose every 4-byte word names (manifold, word), stored slot by slot
        // in the order [2, 0, 1] with one spare slot, as the shaders lay them out.
        let words = size_of::<GpuConstraint>() / 4;
        let order = [2u32, 0, 1];
        let stride = 4usize;
        let mut rows = vec![[0u32; 4]; stride * CONSTRAINT_ROWS as usize];
        for (slot, &m) in order.iter().enumerate() {
            for r in 0..CONSTRAINT_ROWS as usize {
                rows[r * stride + slot] = std::array::from_fn(|k| m * 1000 + (r * 4 + k) as u32);
            }
        }
        let got = constraints_by_manifold(&rows, stride as u64, &order).unwrap();
        for (m, c) in got.iter().enumerate() {
            let flat: &[u32] = bytemuck::cast_slice(std::slice::from_ref(c));
            assert_eq!(flat.len(), words);
            for (w, &v) in flat.iter().enumerate() {
                assert_eq!(v, m as u32 * 1000 + w as u32, "manifold {m} word {w}");
            }
        }
        // An order naming a manifold past the count is an error, not a panic.
        assert!(constraints_by_manifold(&rows, stride as u64, &[0, 5, 1]).is_err());
    }
}
