// requires: common/indexing.wgsl solver/common/coloring.wgsl
// color_resolve: the first coloring round's decisions, one thread per constraint: a
// constraint whose (body, color) claims all hold keeps its color and marks it used at its
// dynamic bodies; the others stay undecided for color_finish.

@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> contact_work: WorkList;
@group(0) @binding(2) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(3) var<storage, read> bodies: array<GpuBody>;
@group(0) @binding(4) var<storage, read> previous_colors: array<ColorSlot>;
@group(0) @binding(5) var<storage, read_write> color_state: array<ColorSlot>;
@group(0) @binding(6) var<storage, read_write> color_marks: array<atomic<u32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= contact_work.count {
        return;
    }
    _ = color_resolve(i);
}
