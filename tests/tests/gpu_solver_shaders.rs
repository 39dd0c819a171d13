//! The GPU solver's shaders and shared structs, checked without a GPU: every kernel parses,
//! validates, specializes for every effect set and translates; every constant is declared; every
//! shared struct has the same layout in Rust and WGSL.

use std::collections::BTreeSet;

use tumble_gpu::kernel::KernelSpec;
use tumble_gpu::naga;
use tumble_gpu::registry::KERNELS;
use tumble_gpu::shader::{FILES, ShaderSource};
use tumble_gpu::solver::constants::solver_constants;
use tumble_gpu::solver::layout::solver_struct_layouts;
use tumble_gpu::solver::{Effects, effect_overrides};
use tumble_tests::shader_checks::{assert_same_layout, compute_spirv, fully_specialized, is_vec3};

/// The solver's kernels: those of the registry under `shaders/solver/`.
fn kernels() -> Vec<&'static KernelSpec> {
    KERNELS
        .iter()
        .copied()
        .filter(|k| k.file.path.starts_with("solver/"))
        .collect()
}

/// The effect switches and `PASS` value `spec` declares.
fn solver_overrides(spec: &KernelSpec, extra: &[(&'static str, f64)]) -> Vec<(&'static str, f64)> {
    spec.declared(extra).unwrap_or_else(|e| panic!("{e}"))
}

// ---------------------------------------------------------------------------------------------
// Shaders and layouts (no GPU)
// ---------------------------------------------------------------------------------------------

#[test]
fn every_solver_kernel_parses_validates_specializes_and_translates() {
    let specs = kernels();
    assert!(
        specs.len() >= 11,
        "expected the solver kernels, found {}",
        specs.len()
    );
    for spec in specs {
        let mut extra: Vec<(&'static str, f64)> = effect_overrides(&Effects::ALL).to_vec();
        extra.push(("PASS", 1.0));
        // solve_step's wait, in the form CPU adapters build (a GPU's differs in one branch).
        extra.push(("SOLVE_STEP_PER_THREAD_SYNC", 1.0));
        let values = solver_overrides(spec, &extra);
        // Specialization resolves every override to a value (none is left to the driver).
        let (module, info) = fully_specialized(spec, &values);
        assert_eq!(module.entry_points.len(), 1, "{}", spec.name);
        compute_spirv(&module, &info, spec.name);
    }
}

#[test]
fn every_effect_combination_specializes() {
    // Each switch off alone and all off: every combination a scene can ask for must build.
    let all = Effects::ALL;
    let variants = [
        Effects {
            friction: false,
            ..all
        },
        Effects {
            restitution: false,
            ..all
        },
        Effects {
            gravity: false,
            ..all
        },
        Effects {
            rotation: false,
            ..all
        },
        Effects {
            friction: false,
            restitution: false,
            gravity: false,
            rotation: false,
            kinematic: false,
            sleep: false,
        },
    ];
    for effects in variants {
        for spec in [
            &tumble_gpu::solver::fused::SOLVE_FUSED,
            &tumble_gpu::solver::solve_color::SOLVE_COLOR,
        ] {
            let mut extra = effect_overrides(&effects).to_vec();
            extra.push(("PASS", 0.0));
            let values = solver_overrides(spec, &extra);
            spec.check_specialized(&values)
                .unwrap_or_else(|e| panic!("{effects:?} {}: {e}", spec.name));
        }
    }
}

#[test]
fn solver_constants_are_each_declared_by_some_shader() {
    // A constant no shader declares would be a value defined in Rust that never arrives.
    let declared: BTreeSet<String> = kernels()
        .iter()
        .flat_map(|spec| {
            let module = spec.check().unwrap();
            tumble_gpu::shader::override_names(&module)
        })
        .collect();
    for (name, _) in solver_constants() {
        assert!(
            declared.contains(name),
            "{name} is declared by no solver shader"
        );
    }
}

/// The body of WGSL function `name` in `source`: from its signature to the next function.
fn function_body<'a>(source: &'a str, name: &str) -> &'a str {
    let start = source
        .find(&format!("fn {name}("))
        .unwrap_or_else(|| panic!("no function {name}"));
    let rest = &source[start..];
    let end = rest[1..].find("\nfn ").map_or(rest.len(), |e| e + 1);
    &rest[..end]
}

/// The constraint-store indices a function body reads (`constraints[i]` not followed by
/// ` =`) or writes (followed by ` =`).
fn store_indices(body: &str, writes: bool) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let mut rest = body;
    while let Some(at) = rest.find("constraints[") {
        let after = &rest[at + "constraints[".len()..];
        let close = after.find(']').expect("an index closes");
        let assigned = after[close + 1..].trim_start().starts_with("= ");
        if assigned == writes {
            found.insert(after[..close].to_string());
        }
        rest = &after[close..];
    }
    found
}

#[test]
fn the_early_constraint_load_reads_again_every_row_a_pass_writes() {
    // solve_step loads a color chunk's constraints before it waits for the phases before
    // (everything but the impulses is fixed from prepare to store), then reads again what a
    // pass changes (reload_pass_impulses). A row that store_pass_impulses writes and the
    // reload leaves out would be read before the pass that last wrote it is known to be done:
    // a stale impulse on a GPU whose workgroups run at once. On a CPU adapter the kernel runs
    // one workgroup, which never reads ahead of itself, so the bits cannot show it there;
    // this compares the two functions' rows instead.
    let store = FILES
        .iter()
        .find(|f| f.path == "solver/common/constraint_store.wgsl")
        .expect("the constraint store's shader");
    let write = FILES
        .iter()
        .find(|f| f.path == "solver/common/constraint_write.wgsl")
        .expect("the constraint writes' shader");
    let written = store_indices(function_body(write.source, "store_pass_impulses"), true);
    let reloaded = store_indices(function_body(store.source, "reload_pass_impulses"), false);
    assert_eq!(
        written.len(),
        3,
        "the tilt row and two rows per point: {written:?}"
    );
    assert_eq!(
        reloaded, written,
        "reload_pass_impulses reads other rows than store_pass_impulses writes"
    );
    // And the point row the two name is the same row.
    let row = "let r = point_row(p) * stride + s;";
    assert!(function_body(write.source, "store_pass_impulses").contains(row));
    assert!(function_body(store.source, "reload_pass_impulses").contains(row));
}

#[test]
fn solver_structs_have_the_same_layout_in_rust_and_wgsl() {
    let source =
        ShaderSource::of_path("common/solver_types.wgsl").unwrap_or_else(|e| panic!("{e}"));
    let module = source
        .parse("solver_types")
        .unwrap_or_else(|e| panic!("{e}"));
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout computable");
    let host = solver_struct_layouts();
    let shared: BTreeSet<&str> = tumble_gpu::layout::shared_struct_layouts()
        .iter()
        .map(|l| l.name)
        .collect();
    let mut checked = BTreeSet::new();
    for (handle, ty) in module.types.iter() {
        let (Some(name), naga::TypeInner::Struct { members, span }) = (&ty.name, &ty.inner) else {
            continue;
        };
        if shared.contains(name.as_str()) {
            continue;
        }
        let rust = host
            .iter()
            .find(|l| l.name == name)
            .unwrap_or_else(|| panic!("WGSL struct {name} has no Rust twin in solver/layout.rs"));
        assert_same_layout(name, rust, members, *span, layouter[handle].size);
        // No vec3 members: their 16-byte alignment would hide padding from the host.
        for m in members {
            assert!(!is_vec3(&module, m), "{name}.{:?} is a vec3", m.name);
        }
        checked.insert(name.clone());
    }
    for l in &host {
        assert!(
            checked.contains(l.name),
            "Rust struct {} has no WGSL twin",
            l.name
        );
    }
}
