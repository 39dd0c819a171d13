//! GPU faults reach the caller as an `Err`, never as a panic or a hang: a device smaller than
//! the scene, limits the adapter cannot give, an error no error scope caught, a lost device.
//!
//! wgpu's default handler for errors outside an error scope panics, and a lost device makes
//! every later call fail; `GpuContext` records both (`check_health`) and every step and read
//! returns them. Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`.

use std::time::{Duration, Instant};

use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest};
use tumble_gpu::{GpuContext, GpuError, GpuOptions, Readback, wgpu};
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
        .expect_err("the pyramid of 20 must not fit in 4 MiB bindings");
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
    .expect_err("a device over the adapter's limits must not open");
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
        .expect_err("the step after the bad copy reports it");
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

/// Workgroups of [`LONG_KERNEL`]: 2 to 4 s on lavapipe with two threads, far past the 100 ms
/// read timeout of the test, and a fraction of a second on a GPU.
const LONG_WORKGROUPS: u32 = 25_000;

/// Steps of the generator per workgroup of [`LONG_KERNEL`].
const LONG_STEPS: u32 = 60_000;

/// A kernel whose every workgroup runs one thread through [`LONG_STEPS`] dependent steps of a
/// linear congruential generator, its result kept: bounded, and not foldable. The length
/// comes from the workgroup count because llvmpipe stops any one invocation's loops after
/// 65,535 iterations in all.
const LONG_KERNEL: &str = "
@group(0) @binding(0) var<storage, read_write> data: array<u32>;
@compute @workgroup_size(1)
fn main(@builtin(workgroup_id) id: vec3<u32>) {
    var x = data[id.x];
    for (var i = 0u; i < 60000u; i++) {
        x = x * 1664525u + 1013904223u;
    }
    data[id.x] = x;
}";

#[test]
fn a_read_behind_work_longer_than_the_read_timeout_errs_in_time_and_succeeds_after() {
    if GpuContext::for_tests().is_none() {
        return;
    }
    // A device of its own: the timeout and the long kernel must not reach other tests.
    let ctx = GpuContext::new().expect("device");
    let refused = ctx.set_read_timeout(Duration::ZERO).unwrap_err();
    assert!(refused.to_string().contains("read_timeout"), "{refused}");
    let module = ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("long"),
            source: wgpu::ShaderSource::Wgsl(LONG_KERNEL.into()),
        });
    let pipeline = ctx
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("long"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
    let data = ctx.storage_buffer("long", &vec![1u32; LONG_WORKGROUPS as usize]);
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("long"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: data.as_entire_binding(),
        }],
    });
    // The kernel and the copy of its results in one submission, as a step records them: on
    // lavapipe a second submission would block in `submit` until the first is done.
    let mut readback = Readback::new(&ctx);
    let bytes = data.size();
    let slot = readback.begin(bytes).expect("staging");
    let mut encoder = ctx.encoder("long");
    let mut pass = encoder.begin_compute_pass(&Default::default());
    pass.set_pipeline(&pipeline);
    pass.set_bind_group(0, &group, &[]);
    pass.dispatch_workgroups(LONG_WORKGROUPS, 1, 1);
    drop(pass);
    let region = readback.copy(&mut encoder, slot, &data, 0, bytes);
    let timeout = Duration::from_millis(100);
    ctx.set_read_timeout(timeout).expect("a positive timeout");
    let start = Instant::now();
    ctx.submit(encoder).expect("submit");
    let ticket = readback.submitted(slot);
    let err = readback
        .wait(&ticket, &[region])
        .expect_err("the read times out");
    let failed_after = start.elapsed();
    assert!(
        matches!(err, GpuError::TimedOut { after } if after == timeout),
        "{err}"
    );
    ctx.set_read_timeout(Duration::from_secs(60)).unwrap();
    let read = readback
        .wait(&ticket, &[region])
        .expect("the same read succeeds once the work is done");
    let finished_after = start.elapsed();
    // Without the timeout the read would have returned at `finished_after` at the earliest:
    // it gave up within a second (slack for a loaded machine), while the work ran on for
    // more than twice as long.
    assert!(
        failed_after < Duration::from_secs(1) && finished_after > failed_after * 2,
        "the read failed after {failed_after:?}, the work finished after {finished_after:?}"
    );
    // Every workgroup ran all its steps.
    let expected = (0..LONG_STEPS).fold(1u32, |x, _| {
        x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223)
    });
    let words = read[0]
        .chunks_exact(4)
        .map(|w| u32::from_le_bytes(w.try_into().unwrap()));
    assert!(words.eq(std::iter::repeat_n(expected, LONG_WORKGROUPS as usize)));
}

#[test]
fn a_substep_wait_that_gave_up_is_read_with_the_steps_stats() {
    // The one substep dispatch (`solve_step`) sets a fault word when one of its waits gives
    // up, which means that step's results may be wrong; the world must hear of it. No real
    // step can be made to give up (its waits are for chunks running workgroups took), so
    // this drives the stats readback directly: a step whose copied fault word is nonzero
    // reads as given up, one whose word is zero or not copied does not, and each step's
    // stats come back two steps later, in order.
    use tumble_gpu::step::stats_ring::{STATS_LAG, StatsRing, StatsSources};
    use wgpu::util::DeviceExt;
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let buffer = |words: &[u32]| {
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        ctx.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("test words"),
                contents: &bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
    };
    // A work list of eight words (the count first), then a fault word at byte 8 of its own
    // buffer, as solve_step's step_progress holds it.
    let work = buffer(&[7, 0, 0, 0, 0, 0, 0, 0]);
    let faulted = buffer(&[0, 0, 1]);
    let clean = buffer(&[5, 5, 0]);
    let mut ring = StatsRing::new(&ctx);
    let mut step = |fault: Option<&wgpu::Buffer>| {
        let taken = ring.take_lagged().unwrap();
        let mut encoder = ctx.encoder("stats test");
        let sources = StatsSources {
            substep_fault: fault.map(|b| (b, 8)),
            ..Default::default()
        };
        ring.record(&mut encoder, &work, sources, 0);
        let index = ctx.submit(encoder).unwrap();
        ring.submitted(index);
        taken.map(|s| (s.work.count, s.substep_wait_gave_up))
    };
    assert_eq!(
        STATS_LAG, 2,
        "the sequence below assumes stats two steps late"
    );
    assert_eq!(step(Some(&faulted)), None);
    assert_eq!(step(Some(&clean)), None);
    assert_eq!(
        step(None),
        Some((7, true)),
        "a set fault word reads as given up"
    );
    assert_eq!(step(None), Some((7, false)), "a zero fault word does not");
    assert_eq!(
        step(None),
        Some((7, false)),
        "no fault word copied does not"
    );
}
