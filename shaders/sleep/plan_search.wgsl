// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// plan_search: one thread writes the dispatch sizes of the island search and of the kernels
// after it: the step's manifold groups and the every-body groups when some body's rest time
// reached TIME_TO_SLEEP, and zero workgroups otherwise (no island can fall asleep then, so
// the search would change nothing). The decision is an exact count, so it is deterministic.

@group(0) @binding(0) var<uniform> params: SleepParams;
// The step's pair `WorkList`.
@group(0) @binding(1) var<storage, read> work: WorkList;
// One `u32`: bodies whose rest reached `TIME_TO_SLEEP`.
@group(0) @binding(2) var<storage, read> ready: array<u32>;
// `array<DispatchArgs, 2>`: the manifold and every-body dispatches of the search.
@group(0) @binding(3) var<storage, read_write> search_groups: array<DispatchArgs, 2>;

@compute @workgroup_size(1)
fn main() {
    var links = DispatchArgs(0u, 1u, 1u, 0u);
    var bodies = DispatchArgs(0u, 1u, 1u, 0u);
    if ready[0] != 0u {
        links = work.groups;
        bodies = DispatchArgs(params.body_groups_x, params.body_groups_y, 1u, 0u);
    }
    search_groups[0] = links;
    search_groups[1] = bodies;
}
