//! Which backends a validation can run here: the CPU always; the GPU and the hybrid only on a
//! hardware adapter unless asked for by name (a software rasterizer such as lavapipe runs the
//! kernels correctly but its timings say nothing about a GPU).

use tumble_gpu::GpuContext;
use tumble_gpu::wgpu::DeviceType;

use crate::engine_tumble::probe_backend;
use crate::grid::BackendChoice;

/// The backends to run and the ones left out, each with the reason.
#[derive(Clone, Debug, Default)]
pub struct BackendPlan {
    /// Backends that will run.
    pub run: Vec<BackendChoice>,
    /// Backends left out, with why.
    pub skipped: Vec<(BackendChoice, String)>,
    /// The GPU adapter in use, when one was opened: name and type.
    pub adapter: Option<String>,
}

/// Decides the backends: `requested` is the `--backends` list, `None` for "every backend
/// that has hardware here".
pub fn plan_backends(requested: Option<&[BackendChoice]>) -> BackendPlan {
    let wanted: Vec<BackendChoice> = match requested {
        Some(list) => list.to_vec(),
        None => vec![
            BackendChoice::Cpu,
            BackendChoice::Gpu,
            BackendChoice::Hybrid,
        ],
    };
    let mut plan = BackendPlan::default();
    let needs_gpu = wanted.iter().any(|&b| b != BackendChoice::Cpu);
    let adapter = needs_gpu.then(|| GpuContext::new().map(|ctx| ctx.info));
    if let Some(Ok(info)) = &adapter {
        plan.adapter = Some(format!(
            "{} ({:?}, {:?})",
            info.name, info.device_type, info.backend
        ));
    }
    for b in wanted {
        if b == BackendChoice::Cpu {
            plan.run.push(b);
            continue;
        }
        match &adapter {
            Some(Err(e)) => plan.skipped.push((b, format!("no GPU adapter: {e}"))),
            Some(Ok(info)) if requested.is_none() && info.device_type == DeviceType::Cpu => {
                plan.skipped.push((
                    b,
                    format!(
                        "only a software adapter ({}); its timings would not describe a GPU. \
                     Pass --backends {} to run it anyway",
                        info.name,
                        b.name()
                    ),
                ))
            }
            _ => match probe_backend(b) {
                Ok(()) => plan.run.push(b),
                Err(e) => plan.skipped.push((b, e)),
            },
        }
    }
    plan
}
