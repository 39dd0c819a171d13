//! Shader checks that need no GPU: every WGSL file in `shaders/` is embedded and used, parses,
//! validates (before and after specialization with the host's override values) and translates
//! to SPIR-V; every kernel's argument struct names its shader's bindings in binding order; and
//! every struct shared with the host has the same size and field offsets in Rust and in WGSL
//! (naga's layouter).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use tumble_gpu::kernel::KernelSpec;
use tumble_gpu::naga;
use tumble_gpu::registry::{
    KERNELS, all_common_files, all_kernels, all_struct_layouts, host_shared_files,
};
use tumble_gpu::shader::{Binding, FILES, ShaderSource, reflect_bindings};
use tumble_tests::shader_checks::{assert_same_layout, compute_spirv, fully_specialized, is_vec3};

fn shaders_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders")
}

/// Every `.wgsl` file under `dir`, as paths relative to `shaders/`.
fn wgsl_files(dir: &Path, root: &Path, out: &mut BTreeSet<String>) {
    for entry in std::fs::read_dir(dir).expect("shaders folder readable") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            wgsl_files(&path, root, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            let rel = path.strip_prefix(root).expect("under shaders/");
            out.insert(rel.to_string_lossy().replace('\\', "/"));
        }
    }
}

#[test]
fn every_shader_file_is_registered_and_every_registration_is_a_file() {
    let root = shaders_dir();
    assert!(
        root.is_dir(),
        "shaders folder missing at {}",
        root.display()
    );
    let mut on_disk = BTreeSet::new();
    wgsl_files(&root, &root, &mut on_disk);
    let registered: BTreeSet<String> = all_common_files()
        .iter()
        .map(|f| f.path.to_string())
        .chain(all_kernels().iter().map(|k| k.spec.file.path.to_string()))
        .collect();
    // A file nobody registers would escape validation; a registered file that is not on disk
    // could not have been embedded.
    let unregistered: Vec<&String> = on_disk.difference(&registered).collect();
    assert!(
        unregistered.is_empty(),
        "WGSL files neither a kernel in tumble_gpu::registry::KERNELS nor required by one: {unregistered:?}"
    );
    assert_eq!(on_disk, registered);
    // Guards against an empty or misplaced folder making the other tests vacuous: the
    // collision stages alone have 11 kernels.
    assert!(
        all_kernels().len() >= 11,
        "found {} kernels",
        all_kernels().len()
    );
    // Every file is embedded, and the embedded text is the file on disk (no stale copy).
    let embedded: BTreeSet<String> = FILES.iter().map(|f| f.path.to_string()).collect();
    assert_eq!(on_disk, embedded);
    for file in FILES {
        let disk = std::fs::read_to_string(root.join(file.path)).unwrap();
        assert_eq!(disk, file.source, "{}", file.path);
    }
}

#[test]
fn every_kernel_parses_validates_specializes_and_translates() {
    for k in all_kernels() {
        let spec = k.spec;
        // Specialization resolves every override to a value (none is left to the driver).
        let (module, info) = fully_specialized(spec, &k.overrides);
        assert_eq!(
            module.entry_points.len(),
            1,
            "{}: one entry point",
            spec.name
        );
        assert_eq!(module.entry_points[0].name, "main", "{}", spec.name);
        let words = compute_spirv(&module, &info, spec.name);
        assert!(!words.is_empty(), "{}: empty SPIR-V", spec.name);
    }
}

#[test]
fn workgroup_size_comes_from_the_host_constant() {
    // The shaders never spell the workgroup size: after specialization it must equal the
    // Rust constant (single-thread planning kernels excepted; the per-color passes have their
    // own, for which color_plan sizes their dispatches, solve_worlds its own, one
    // workgroup per world, and solve_step its own, one color chunk per workgroup).
    for k in all_kernels() {
        let spec = k.spec;
        let (module, _) = spec.check_specialized(&k.overrides).unwrap();
        let size = module.entry_points[0].workgroup_size;
        let expected = if matches!(spec.name, "solve_color" | "solve_color_immediate") {
            tumble_gpu::solver::constants::COLOR_PASS_WORKGROUP_SIZE
        } else if matches!(spec.name, "solve_worlds" | "solve_worlds_shared") {
            tumble_gpu::solver::fused::WORLDS_WORKGROUP_SIZE
        } else if spec.name == "solve_step" {
            tumble_gpu::solver::solve_step::SOLVE_STEP_WORKGROUP_SIZE
        } else {
            tumble_gpu::WORKGROUP_SIZE
        };
        assert!(
            size == [expected, 1, 1] || size == [1, 1, 1],
            "{}: workgroup size {size:?}",
            spec.name
        );
    }
}

/// The device check asks for as many storage buffers per stage as the widest kernel binds: a
/// device with fewer is refused when it opens (naming the limit), not when a pipeline that
/// binds more is first built, midway through a world's construction. A constant larger than
/// any kernel needs would refuse devices for nothing.
#[test]
fn the_storage_buffer_limit_asked_for_is_the_widest_kernels_count() {
    let counts: Vec<(&str, u32)> = KERNELS
        .iter()
        .map(|&spec| {
            let module = spec.check().unwrap_or_else(|e| panic!("{e}"));
            let storage = reflect_bindings(&module)
                .iter()
                .filter(|b| matches!(b.kind, Binding::StorageRead | Binding::StorageReadWrite))
                .count();
            (spec.name, storage as u32)
        })
        .collect();
    let widest = counts.iter().max_by_key(|c| c.1).unwrap();
    assert_eq!(
        widest.1,
        tumble_gpu::context::REQUIRED_STORAGE_BUFFERS_PER_STAGE,
        "{} binds the most storage buffers",
        widest.0
    );
}

#[test]
fn every_kernel_binds_its_shaders_group_0_bindings_in_order() {
    for &spec in KERNELS.iter() {
        let module = spec.check().unwrap_or_else(|e| panic!("{e}"));
        let bindings = reflect_bindings(&module);
        let names: Vec<&str> = bindings.iter().map(|b| b.name.as_str()).collect();
        assert_eq!(names, spec.buffers().unwrap(), "{}", spec.name);
        for (i, b) in bindings.iter().enumerate() {
            assert_eq!(
                (b.group, b.binding),
                (0, i as u32),
                "{}: {}",
                spec.name,
                b.name
            );
        }
        // A kernel names only its own file; the rest comes from its directives.
        let source = spec.source().unwrap();
        assert_eq!(source.files.last(), Some(&spec.file), "{}", spec.name);
        assert_eq!(
            spec.file.path.rsplit('/').next(),
            Some(format!("{}.wgsl", spec.name).as_str())
        );
    }
    // Every kernel is listed once.
    let names: BTreeSet<&str> = KERNELS.iter().map(|k| k.name).collect();
    assert_eq!(names.len(), KERNELS.len());
}

#[test]
fn a_kernels_buffers_are_read_from_its_shader() {
    // The names bind_named asks for, in binding order; nothing on the host lists them.
    static SCAN: KernelSpec = KernelSpec::new(tumble_gpu::shader::file("radix_scan.wgsl"));
    assert_eq!(SCAN.buffers().unwrap(), ["work", "tile_counts"]);
}

#[test]
fn unknown_specialization_is_an_error_not_ignored() {
    let spec = all_kernels()[0].spec;
    let err = spec
        .check_specialized(&[("NO_SUCH_OVERRIDE", 1.0)])
        .unwrap_err();
    assert!(err.to_string().contains("NO_SUCH_OVERRIDE"), "{err}");
}

/// Each host-shared WGSL file parsed with the common files it needs.
fn shared_modules() -> Vec<(&'static str, naga::Module)> {
    host_shared_files()
        .into_iter()
        .map(|file| {
            let source = ShaderSource::of(file).unwrap_or_else(|e| panic!("{e}"));
            (
                file.path,
                source.parse("layout").unwrap_or_else(|e| panic!("{e}")),
            )
        })
        .collect()
}

#[test]
fn shared_structs_have_the_same_layout_in_rust_and_wgsl() {
    let host = all_struct_layouts();
    let mut wgsl_names = BTreeSet::new();
    for (path, module) in shared_modules() {
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).expect("layout computable");
        // Only the structs this file declares (its prelude and needs are checked elsewhere).
        let declared: BTreeSet<String> = std::fs::read_to_string(shaders_dir().join(path))
            .unwrap()
            .lines()
            .filter_map(|l| l.trim().strip_prefix("struct "))
            .map(|l| l.trim_end_matches(['{', ' ']).to_string())
            .collect();
        for (handle, ty) in module.types.iter() {
            let (Some(name), naga::TypeInner::Struct { members, span }) = (&ty.name, &ty.inner)
            else {
                continue;
            };
            if !declared.contains(name) {
                continue;
            }
            wgsl_names.insert(name.clone());
            let rust = host
                .iter()
                .find(|l| l.name == name)
                .unwrap_or_else(|| panic!("WGSL struct {name} ({path}) has no Rust twin"));
            assert_same_layout(name, rust, members, *span, layouter[handle].size);
        }
    }
    for l in &host {
        assert!(
            wgsl_names.contains(l.name),
            "Rust struct {} has no WGSL twin",
            l.name
        );
    }
    // The collision stages' own structs are all there.
    assert!(
        wgsl_names.len() >= 13,
        "only {} shared structs found",
        wgsl_names.len()
    );
}

#[test]
fn storage_structs_hold_no_vec3() {
    // A vec3 is 16-byte aligned but 12 bytes long: host structs cannot mirror it without
    // hidden padding, so the shared structs spell padding out instead.
    for (path, module) in shared_modules() {
        for (_, ty) in module.types.iter() {
            if let naga::TypeInner::Struct { members, .. } = &ty.inner {
                for m in members {
                    assert!(
                        !is_vec3(&module, m),
                        "{path}: {:?}.{:?} is a vec3",
                        ty.name,
                        m.name
                    );
                }
            }
        }
    }
}
