// requires: solver/common/coloring.wgsl
// The bindings of the coloring kernels that run rounds (color_propose, color_resolve,
// color_withdraw, color_finish): what coloring.wgsl expects, and the pair work list.
// color_withdraw and color_finish bind more after these.

@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> contact_work: WorkList;
@group(0) @binding(2) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(3) var<storage, read> bodies: array<GpuBody>;
@group(0) @binding(4) var<storage, read> previous_colors: array<ColorSlot>;
@group(0) @binding(5) var<storage, read_write> color_state: array<ColorSlot>;
@group(0) @binding(6) var<storage, read_write> color_marks: array<atomic<u32>>;
