//! Constants shared by the host and the shaders, defined once here and handed to every
//! pipeline as WGSL `override` values (the shaders declare them in `common/constants.wgsl`
//! without a value, so a missing one fails pipeline creation instead of drifting).

/// Threads per workgroup for every kernel. 256 is a multiple of every vendor's SIMD width
/// (32 on NVIDIA, 64 on AMD, 8 on lavapipe) and the WebGPU default invocation limit.
pub const WORKGROUP_SIZE: u32 = 256;

/// Bits of the key sorted per radix pass. Four bits (16 buckets) keeps the per-tile
/// histogram and the digit-major scan small; 32-bit keys take 8 passes.
pub const RADIX_BITS: u32 = 4;

/// Buckets per radix pass.
pub const RADIX: u32 = 1 << RADIX_BITS;

/// The most contact points in one manifold (the thesis's reduction to four points).
pub const MAX_MANIFOLD_POINTS: u32 = tumble_geometry::MAX_MANIFOLD_POINTS as u32;

/// The most bodies a scene may have on the GPU path. The radix sort's offset scan runs in a
/// single workgroup over `RADIX * bodies / WORKGROUP_SIZE` entries (one key per thread of a tile); at this cap that is 2^18
/// entries (1024 per thread), still one short dispatch. Bodies are also indexed with 24 bits
/// in debugging dumps.
pub const MAX_BODIES: u32 = 1 << 22;

/// Workgroups per dispatch dimension guaranteed by WebGPU; larger dispatches fold into `y`.
pub const MAX_WORKGROUPS_PER_DIMENSION: u32 = 65_535;

/// Marks "no manifold last step" in `GpuManifold::previous`.
pub const NO_PREVIOUS: u32 = u32::MAX;

/// `GpuManifold::kind` of a manifold whose reference face is on A.
pub const MANIFOLD_FACE_A: u32 = 0;
/// `GpuManifold::kind` of a manifold whose reference face is on B.
pub const MANIFOLD_FACE_B: u32 = 1;
/// `GpuManifold::kind` of an edge-edge (or vertex) manifold.
pub const MANIFOLD_EDGE: u32 = 2;

/// Farthest a contact point may move in body A's frame and still inherit last step's impulse
/// when its feature id changed (`carry_impulses`' position fallback): tumble-solver's
/// contact-cache limit, so both backends warm start the same points.
pub const PERSIST_DISTANCE: f32 = tumble_solver::PERSIST_DISTANCE;

/// Bit offsets of the contact id fields, read off `tumble_narrow`'s id packing so that the
/// GPU packs ids exactly as the CPU does without a second copy of the layout:
/// `(kind, reference face, incident face, edge_in)`; `edge_out` is at bit 0.
fn id_shifts() -> [u32; 4] {
    use tumble_narrow::feature_id::face_point_id;
    [
        face_point_id(1, 0, 0, 0, 0).trailing_zeros(),
        face_point_id(0, 1, 0, 0, 0).trailing_zeros(),
        face_point_id(0, 0, 1, 0, 0).trailing_zeros(),
        face_point_id(0, 0, 0, 1, 0).trailing_zeros(),
    ]
}

/// Long boxes the broad phase pairs apart from its sweep (see `shaders/common/sweep.wgsl`):
/// floors, walls and terrain slabs, a handful in a scene. With more, the sweep pairs them all
/// as before.
pub const MAX_LONG_BOXES: u32 = 64;

/// A box is long on the sweep axis past this many times the median body's diameter.
/// A pile's boxes scan a few neighbours each; a box spanning 16 of them already scans 16
/// times as many, and a floor under a pile of 42,926 cubes spans all of them.
pub const LONG_BOX_FACTOR: f32 = 16.0;

/// `(WGSL name, value)` pairs of `override` values, each value converted by `f64::from`:
/// `NAME` takes the constant `NAME` in scope (the name is written once), `NAME = value` any
/// other value.
macro_rules! override_values {
    ($($name:ident $(= $value:expr)?),* $(,)?) => {
        vec![$((stringify!($name), $crate::constants::override_values!(@ $name $($value)?))),*]
    };
    (@ $name:ident) => { f64::from($name) };
    (@ $name:ident $value:expr) => { f64::from($value) };
}
pub(crate) use override_values;

/// Every override value the shaders may declare, by WGSL name.
pub fn shader_constants() -> Vec<(&'static str, f64)> {
    use crate::kernels::rank_sort::RANK_SORT_ITEMS;
    use crate::kernels::remap_pairs::REMAP_DROPPED;
    use crate::layout::{BODY_STATIC, BODY_WORLD_SHIFT};
    use crate::solver::constants::PERSIST_NORMAL_COS;
    use tumble_geometry::{SEGMENT_DEGENERATE_RATIO, SEGMENT_PARALLEL_SIN_SQ};
    use tumble_narrow::tolerance::*;
    use tumble_narrow::{EDGE_PAIR_COUNT, VERTEX_OF_A_FEATURE, feature_id as id};
    let [kind_shift, reference_shift, incident_shift, field_shift] = id_shifts();
    override_values![
        WORKGROUP_SIZE,
        RADIX_BITS,
        RADIX,
        RANK_SORT_ITEMS,
        MAX_WORKGROUPS_PER_DIMENSION,
        BODY_STATIC,
        BODY_WORLD_SHIFT,
        REMAP_DROPPED,
        MAX_LONG_BOXES,
        NO_PREVIOUS,
        MANIFOLD_FACE_A,
        MANIFOLD_FACE_B,
        MANIFOLD_EDGE,
        PERSIST_DISTANCE,
        // Also in the solver's list (its tilt carry); both read tumble-solver's value.
        PERSIST_NORMAL_COS,
        RECYCLE_NORMAL_COS = tumble_solver::RECYCLE_NORMAL_COS,
        RECYCLE_SIZE_FRACTION = tumble_solver::RECYCLE_SIZE_FRACTION,
        PARALLEL_EDGE_SIN_SQ,
        FACE_B_REL_TOL,
        FACE_B_ABS_TOL,
        EDGE_REL_TOL,
        EDGE_ABS_TOL,
        FACE_LIKE_EDGE_COS,
        FACE_LIKE_MAX_DEPTH,
        HYSTERESIS_REL_TOL,
        HYSTERESIS_ABS_TOL,
        WITNESS_TOL,
        SEGMENT_DEGENERATE_RATIO,
        SEGMENT_PARALLEL_SIN_SQ,
        MAX_POSITION = tumble_solver::bounds::MAX_POSITION,
        ID_KIND_FACE_A = id::KIND_FACE_A,
        ID_KIND_FACE_B = id::KIND_FACE_B,
        ID_KIND_EDGE = id::KIND_EDGE,
        ID_KIND_VERTEX = id::KIND_VERTEX,
        ID_KIND_SHIFT = kind_shift,
        ID_REFERENCE_SHIFT = reference_shift,
        ID_INCIDENT_SHIFT = incident_shift,
        ID_FIELD_SHIFT = field_shift,
        SIDE_LABEL_BASE = id::SIDE_LABEL_BASE,
        EDGE_PAIR_COUNT,
        VERTEX_OF_A_FEATURE,
    ]
}

/// WGSL `const` declarations generated from Rust values, composed in front of every shader.
///
/// Only for values WGSL needs as const-expressions, which `override`s cannot be: the sizes of
/// function-scope arrays, and lookup tables. Each line is a declaration written from the Rust
/// constant; no shader text is ever edited.
pub fn wgsl_const_prelude() -> String {
    let faces: Vec<String> = tumble_geometry::CUBOID_FACES
        .iter()
        .map(|f| format!("vec4<u32>({}u, {}u, {}u, {}u)", f[0], f[1], f[2], f[3]))
        .collect();
    format!(
        "// Generated from crates/tumble-gpu/src/constants.rs (wgsl_const_prelude).\n\
         const MAX_MANIFOLD_POINTS: u32 = {}u;\n\
         const MAX_CLIP_VERTICES: u32 = {}u;\n\
         const CUBOID_FACES = array<vec4<u32>, 6>({});\n",
        MAX_MANIFOLD_POINTS,
        tumble_geometry::MAX_CLIP_VERTICES,
        faces.join(", ")
    )
}

/// Workgroup counts `(x, y)` covering `items` threads, folding into `y` past the per-dimension
/// limit. Kernels rebuild the linear index with `linear_index` in `common/indexing.wgsl`.
pub fn workgroups_for(items: u32) -> (u32, u32) {
    let groups = items.div_ceil(WORKGROUP_SIZE);
    if groups <= MAX_WORKGROUPS_PER_DIMENSION {
        (groups, 1)
    } else {
        (
            MAX_WORKGROUPS_PER_DIMENSION,
            groups.div_ceil(MAX_WORKGROUPS_PER_DIMENSION),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispatches_fold_past_the_dimension_limit_and_cover_every_item() {
        assert_eq!(workgroups_for(0), (0, 1));
        assert_eq!(workgroups_for(1), (1, 1));
        assert_eq!(workgroups_for(WORKGROUP_SIZE + 1), (2, 1));
        let items = (MAX_WORKGROUPS_PER_DIMENSION + 5) * WORKGROUP_SIZE;
        let (x, y) = workgroups_for(items);
        assert_eq!(x, MAX_WORKGROUPS_PER_DIMENSION);
        assert!(u64::from(x) * u64::from(y) * u64::from(WORKGROUP_SIZE) >= u64::from(items));
        assert_eq!(y, 2);
    }

    #[test]
    fn id_shifts_reproduce_the_cpu_id_packing() {
        use tumble_narrow::feature_id::{edge_point_id, face_point_id, vertex_point_id};
        let [kind, reference, incident, field] = id_shifts();
        for (k, r, i, a, b) in [(0, 2, 3, 1, 6), (1, 5, 0, 7, 4)] {
            let gpu = (k << kind) | (r << reference) | (i << incident) | (a << field) | b;
            assert_eq!(gpu, face_point_id(k, r, i, a, b));
        }
        let edge = tumble_narrow::feature_id::KIND_EDGE;
        assert_eq!((edge << kind) | (7 << field) | 3, edge_point_id(7, 3));
        let vertex = tumble_narrow::feature_id::KIND_VERTEX;
        assert_eq!(
            (vertex << kind) | (1 << field) | 5,
            vertex_point_id(5, true)
        );
    }

    #[test]
    fn const_prelude_declares_the_rust_values() {
        let prelude = wgsl_const_prelude();
        assert!(prelude.contains(&format!(
            "const MAX_MANIFOLD_POINTS: u32 = {MAX_MANIFOLD_POINTS}u;"
        )));
        assert!(
            prelude.contains("vec4<u32>(1u, 3u, 7u, 5u)"),
            "first face of CUBOID_FACES"
        );
    }
}
