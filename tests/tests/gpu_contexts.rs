//! Devices opened one after another in one process each run their own pipelines.
//!
//! The pipeline cache was once global and keyed by `wgpu::Device`, and devices of two wgpu
//! instances can compare equal: a world on a second `GpuContext` was handed the first
//! device's pipelines and panicked in wgpu ("Cannot get non-existent resource"). Each context
//! now holds its own cache. Needs a GPU (or lavapipe): without one it prints a loud "skipped"
//! unless `TUMBLE_REQUIRE_GPU=1`.

use tumble_gpu::GpuContext;
use tumble_gpu::layout::GpuPose;
use tumble_gpu::step::{GpuWorldConfig, ReadRequest};
use tumble_tests::scene_support::gpu_world_of;

/// Steps per run: half a second at 60 Hz, the pyramid settles on the floor meanwhile.
const STEPS: usize = 30;

fn run(ctx: &GpuContext) -> Vec<GpuPose> {
    let scene = tumble_scenes::pyramid(3);
    let mut world = gpu_world_of(ctx, &scene, GpuWorldConfig::default()).expect("GPU world");
    for _ in 0..STEPS {
        world.step().expect("step");
    }
    world
        .read_now(ReadRequest {
            poses: true,
            ..Default::default()
        })
        .expect("poses")
        .poses
}

#[test]
fn worlds_on_two_devices_of_one_process_step_alike() {
    if GpuContext::for_tests().is_none() {
        return;
    }
    let first = GpuContext::new().expect("first device");
    let second = GpuContext::new().expect("second device");
    let a = run(&first);
    let b = run(&second);
    // The first device again, after the second built its pipelines.
    let c = run(&first);
    // Same adapter, same kernels, same inputs: bitwise equal poses.
    let bits = |poses: &[GpuPose]| -> Vec<u32> {
        poses
            .iter()
            .flat_map(|p| p.position.iter().chain(&p.rotation).map(|c| c.to_bits()))
            .collect()
    };
    assert_eq!(bits(&a), bits(&b), "second device differs from the first");
    assert_eq!(bits(&a), bits(&c), "first device differs on its second run");
    // And the physics ran: the three rows of unit cubes rest on the floor (top surface at
    // y = 0), centres at 0.5, 1.5 and 2.5 m within 2 cm, none below the floor.
    let mut heights: Vec<f32> = a[1..].iter().map(|p| p.position[1]).collect();
    heights.sort_by(f32::total_cmp);
    assert!(heights[0] > 0.48, "lowest cube at {}", heights[0]);
    let top = heights[heights.len() - 1];
    assert!((top - 2.5).abs() < 0.02, "top cube at {top}");
}
