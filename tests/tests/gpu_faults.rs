//! GPU faults reach the caller as an `Err`, never as a panic or a hang: a device smaller than
//! the scene, limits the adapter cannot give, an error no error scope caught, a lost device.
//!
//! wgpu's default handler for errors outside an error scope panics, and a lost device makes
//! every later call fail; `GpuContext` records both (`check_health`) and every step and read
//! returns them. Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`.

use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest};
use tumble_gpu::{GpuContext, GpuError, GpuOptions, wgpu};
use tumble_tests::scene_support::gpu_world_of;

/// The adapter the shared test device was opened on, with its limits.
fn adapter() -> Option<(wgpu::Adapter, wgpu::Limits)> {
    let ctx = GpuContext::for_tests()?;
    let limits = ctx.adapter.limits();
    Some((ctx.adapter.clone(), limits))
}

/// A device on the test adapter whose storage bindings and buffers hold at most `bytes`.
fn device_with_bindings_of(bytes: u64) -> Option<GpuContext> {
    let (adapter, limits) = adapter()?;
    let name = adapter.get_info().name;
    let ctx = GpuContext::with_options(&GpuOptions {
        adapter_name: Some(name),
        timestamps: false,
        limits: Some(wgpu::Limits {
            max_storage_buffer_binding_size: bytes,
            max_buffer_size: bytes,
            ..limits
        }),
    })
    .expect("a device with limits below the adapter's opens");
    Some(ctx)
}

/// A device of its own (what a test does to it must not reach other tests' worlds) with a
/// pyramid of 2 on it, stepped once.
fn own_device_world() -> Option<(GpuContext, GpuWorld)> {
    GpuContext::for_tests()?;
    let ctx = GpuContext::new().expect("device");
    let mut world =
        gpu_world_of(&ctx, &tumble_scenes::pyramid(2), GpuWorldConfig::default()).expect("world");
    world.step().expect("step");
    Some((ctx, world))
}

fn poses(world: &mut GpuWorld) -> Result<Vec<[f32; 4]>, GpuError> {
    let read = world.read_now(ReadRequest {
        poses: true,
        ..Default::default()
    })?;
    Ok(read.poses.iter().map(|p| p.position).collect())
}

#[test]
fn a_scene_over_the_devices_binding_size_is_refused_naming_the_limit() {
    // 4 MiB per binding: a small pyramid fits, the pyramid of 20 (2,871 boxes, hundreds of
    // bytes of constraint per contact) does not.
    const BINDING: u64 = 4 << 20;
    let Some(ctx) = device_with_bindings_of(BINDING) else {
        return;
    };
    assert_eq!(ctx.limits().max_storage_buffer_binding_size, BINDING);
    let big = tumble_scenes::pyramid(20);
    // The body buffers are sized when the bodies are set, the pair and contact buffers at the
    // first step, from the broad phase's count: either may be the one refused.
    let err = gpu_world_of(&ctx, &big, GpuWorldConfig::default())
        .and_then(|mut world| world.step())
        .err()
        .expect("the pyramid of 20 must not fit in 4 MiB bindings");
    match &err {
        GpuError::LimitExceeded {
            value,
            limit_name,
            limit,
            ..
        } => {
            assert_eq!(*limit_name, "max_storage_buffer_binding_size", "{err}");
            assert_eq!(*limit, BINDING, "{err}");
            assert!(
                *value > *limit,
                "{err}: the count named is not over the limit"
            );
        }
        other => panic!("expected LimitExceeded, got {other}"),
    }
    // The same device still runs what fits: the pyramid of 3 (14 bodies) falls into place,
    // its top cube's centre 2.5 m up within 2 cm after a second (the resting height of three
    // unit cubes on a floor whose top is y = 0).
    let mut world =
        gpu_world_of(&ctx, &tumble_scenes::pyramid(3), GpuWorldConfig::default()).expect("fits");
    for _ in 0..60 {
        world.step().expect("step");
    }
    let top = poses(&mut world)
        .expect("read")
        .iter()
        .map(|p| p[1])
        .fold(f32::MIN, f32::max);
    assert!((top - 2.5).abs() < 0.02, "top cube at {top}");
}

#[test]
fn limits_over_the_adapters_are_a_clear_error() {
    let Some((adapter, limits)) = adapter() else {
        return;
    };
    let name = adapter.get_info().name;
    let err = GpuContext::with_options(&GpuOptions {
        adapter_name: Some(name.clone()),
        timestamps: false,
        limits: Some(wgpu::Limits {
            max_storage_buffers_per_shader_stage: limits.max_storage_buffers_per_shader_stage + 1,
            ..limits
        }),
    })
    .err()
    .expect("a device over the adapter's limits must not open");
    match &err {
        GpuError::DeviceRequest { adapter, reason } => {
            assert_eq!(adapter, &name);
            assert!(!reason.is_empty(), "{err}");
        }
        other => panic!("expected DeviceRequest, got {other}"),
    }
}

#[test]
fn an_uncaught_error_is_returned_once_and_a_lost_device_from_then_on() {
    // One device for both faults: opening one compiles every kernel again (slow on lavapipe).
    let Some((ctx, mut world)) = own_device_world() else {
        return;
    };
    let before = poses(&mut world).expect("read");
    // A copy past the end of a buffer: a validation error at submit, outside any scope,
    // which wgpu's default handler would turn into a panic.
    let small = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("too small"),
        size: 16,
        usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.encoder("bad copy");
    encoder.copy_buffer_to_buffer(&small, 0, &small, 8, 16);
    ctx.queue.submit([encoder.finish()]);
    let err = world
        .step()
        .err()
        .expect("the step after the bad copy reports it");
    assert!(matches!(err, GpuError::Device(_)), "{err}");
    // Reported once, and the refused step did not run: the world steps on from where it was,
    // one step of falling (at most g dt^2 = 2.7 mm per body) from the poses read before.
    world
        .step()
        .expect("the error was reported; the world steps again");
    let after = poses(&mut world).expect("read");
    for (a, b) in before.iter().zip(&after) {
        let moved = (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f32::max);
        assert!(moved < 3e-3, "a body moved {moved} m in one step");
    }
    // The one loss wgpu lets a program cause.
    ctx.device.destroy();
    ctx.wait_idle().ok();
    assert!(ctx.is_lost(), "destroy must report the device lost");
    for attempt in 0..3 {
        match world.step() {
            Err(GpuError::DeviceLost { reason }) => {
                assert!(reason.contains("Destroyed"), "{reason}")
            }
            other => panic!("step {attempt} after the loss: {other:?}"),
        }
        assert!(
            matches!(poses(&mut world), Err(GpuError::DeviceLost { .. })),
            "a read after the loss must be DeviceLost"
        );
    }
}
