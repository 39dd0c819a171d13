#!/usr/bin/env python3
"""Runs nexus (PyPI `dimforge-nexus3d`, module `nexus3d`) on Tumble's JSON scene files and
writes a CSV with the columns of `cargo xtask bench-gpu`, whose `--nexus-csv FILE` joins it.

    xtask bench-gpu --write-scenes target/bench-gpu/scenes
    python3 benches/peers/nexus_scenes.py target/bench-gpu/scenes/*.json \\
        --out target/bench-gpu/nexus.csv

Each scene (the `tumble-scenes` schema: bodies with kind, half extents, position, rotation
`[x, y, z, w]`, velocities, density, friction, restitution; gravity; dt) becomes one nexus
state of boxes. The time per step is the steady state taken from two run lengths, each ending
in a pose read (the first read costs a few hundred ms once, and `simulate` blocks on the GPU):
`(t2 - t1) / (N2 - N1)`, measured `--repeats` times (median and 90th percentile over repeats).
Drift (largest horizontal displacement of a dynamic body from its start) and the lowest
dynamic body's centre along the up axis (against gravity) are read at the end, as bench-gpu
reports them.

`--dry-run` reads the scenes and builds the body list (and, where `nexus3d` imports, the
nexus state, which needs no GPU) without simulating. The script uses no network and nothing
outside the Python standard library and the nexus wheel (with numpy, which its pose reads
return).
"""

import argparse
import csv
import json
import math
import os
import statistics
import sys
import time

# The columns of bench-gpu's results.csv (xtask/src/bench_gpu_report/mod.rs, CSV_COLUMNS).
CSV_COLUMNS = (
    "scene,bodies,engine,steps,median_ms,p90_ms,drift_m,lowest_m,gpu_ms,bytes_per_step,"
    "floor_ms,x_floor,mem_bytes_per_body,manifolds,note"
).split(",")

# Defaults of the tumble-scenes schema (crates/tumble-scenes/src/body.rs, scene.rs).
DEFAULT_GRAVITY = [0.0, -9.81, 0.0]
DEFAULT_DT = 1.0 / 60.0
DEFAULT_DENSITY = 1.0
DEFAULT_FRICTION = 0.6
DEFAULT_RESTITUTION = 0.0


class Body:
    """One box of a scene, with the schema's defaults filled in."""

    __slots__ = (
        "kind",
        "half_extents",
        "position",
        "rotation",
        "linear_velocity",
        "angular_velocity",
        "density",
        "friction",
        "restitution",
    )

    def __init__(self, spec, index):
        def vec(name, default, n=3):
            value = spec.get(name, default)
            if not isinstance(value, list) or len(value) != n:
                raise ValueError(f"body {index}: {name} must be a list of {n} numbers")
            return [float(v) for v in value]

        self.kind = spec.get("kind", "Dynamic")
        if self.kind not in ("Fixed", "Dynamic", "Kinematic"):
            raise ValueError(f"body {index}: unknown kind {self.kind!r}")
        if "half_extents" not in spec or "position" not in spec:
            raise ValueError(f"body {index}: half_extents and position are required")
        self.half_extents = vec("half_extents", None)
        self.position = vec("position", None)
        self.rotation = vec("rotation", [0.0, 0.0, 0.0, 1.0], 4)
        self.linear_velocity = vec("linear_velocity", [0.0, 0.0, 0.0])
        self.angular_velocity = vec("angular_velocity", [0.0, 0.0, 0.0])
        self.density = float(spec.get("density", DEFAULT_DENSITY))
        self.friction = float(spec.get("friction", DEFAULT_FRICTION))
        self.restitution = float(spec.get("restitution", DEFAULT_RESTITUTION))
        if min(self.half_extents) <= 0.0:
            raise ValueError(f"body {index}: half extents must be positive")


class SceneFile:
    """A scene file: name, gravity, dt and bodies."""

    def __init__(self, path):
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
        if not isinstance(data, dict) or not isinstance(data.get("bodies"), list):
            raise ValueError(f"{path}: not a tumble-scenes scene (no bodies list)")
        self.path = path
        self.name = data.get("name") or os.path.splitext(os.path.basename(path))[0]
        self.gravity = [float(g) for g in data.get("gravity", DEFAULT_GRAVITY)]
        self.dt = float(data.get("dt", DEFAULT_DT))
        self.bodies = [Body(b, i) for i, b in enumerate(data["bodies"])]
        if not self.bodies:
            raise ValueError(f"{path}: the scene has no bodies")

    def up_axis(self):
        g = self.gravity
        norm = math.sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2])
        if norm == 0.0:
            return [0.0, 1.0, 0.0]
        return [-g[0] / norm, -g[1] / norm, -g[2] / norm]

    def dynamic_count(self):
        return sum(1 for b in self.bodies if b.kind == "Dynamic")


def drift_and_lowest(scene, positions):
    """Largest horizontal displacement of a dynamic body, lowest dynamic centre along up."""
    up = scene.up_axis()
    drift = 0.0
    lowest = math.inf
    for body, p in zip(scene.bodies, positions):
        if body.kind != "Dynamic":
            continue
        d = [float(p[i]) - body.position[i] for i in range(3)]
        along = d[0] * up[0] + d[1] * up[1] + d[2] * up[2]
        total = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        drift = max(drift, math.sqrt(max(total - along * along, 0.0)))
        height = float(p[0]) * up[0] + float(p[1]) * up[1] + float(p[2]) * up[2]
        lowest = min(lowest, height)
    return drift, (lowest if lowest != math.inf else None)


def percentile(values, q):
    ordered = sorted(values)
    return ordered[int(round((len(ordered) - 1) * q))]


def steady_ms(n1, t1, n2, t2):
    """Milliseconds per step from two run lengths, each ending in a read."""
    if n2 <= n1:
        raise ValueError("the long run must be longer than the short one")
    return (t2 - t1) / (n2 - n1) * 1e3


def import_nexus():
    try:
        import nexus3d  # noqa: PLC0415 (imported only where a run needs it)
    except ImportError as e:
        return None, str(e)
    return nexus3d, None


def build_state(nx, scene, args, viewer=None):
    """The nexus state of the scene's boxes (before `finalize`) and the handles in scene
    order. Friction combines by nexus's `average` rule: equal to the scenes' geometric mean
    when both surfaces have the same coefficient, as in every benchmark scene."""
    state = nx.NexusState()
    handles = []
    for b in scene.bodies:
        if b.kind == "Fixed":
            builder = nx.RigidBodyBuilder.fixed()
        elif b.kind == "Kinematic":
            builder = nx.RigidBodyBuilder.kinematic_velocity_based()
        else:
            builder = nx.RigidBodyBuilder.dynamic()
        x, y, z, w = b.rotation
        pose = nx.Pose.from_parts(nx.Vec3(*b.position), nx.Quat.from_xyzw(x, y, z, w))
        builder = builder.pose(pose)
        if b.kind != "Fixed":
            builder = builder.linvel(nx.Vec3(*b.linear_velocity))
            builder = builder.angvel(nx.Vec3(*b.angular_velocity))
        builder = builder.can_sleep(False)
        collider = (
            nx.ColliderBuilder.cuboid(*b.half_extents)
            .density(b.density)
            .friction(b.friction)
            .friction_combine_rule("average")
            .restitution(b.restitution)
        )
        handles.append(
            state.insert_rigid_body(builder.build(), collider.build(), nx.RbdCoupling.NONE)
        )
    state.set_rbd_timestep(scene.dt, args.substeps)
    # One step per `simulate`, whatever nexus's default frame holds.
    state.set_rbd_steps_per_frame(1)
    capacity = max(4096, args.pairs_per_body * len(scene.bodies))
    state.set_rbd_collisions_capacity(capacity)
    return state, handles, capacity


def run_scene(nx, viewer, pipeline, scene, args):
    """One CSV row (a dict) for the scene."""
    row = {c: "" for c in CSV_COLUMNS}
    row.update(scene=scene.name, bodies=len(scene.bodies), engine="nexus")
    built = time.perf_counter()
    state, handles, capacity = build_state(nx, scene, args, viewer)
    state.finalize(viewer)
    notes = []
    try:
        state.set_rbd_gravity(viewer, nx.Vec3(*scene.gravity))
    except Exception as e:  # noqa: BLE001 (the run stands at nexus's default gravity)
        notes.append(f"gravity left at nexus's default ({type(e).__name__}: {e})")
    rows = [state.body_gpu_index(0, h) for h in handles]
    if any(r is None for r in rows):
        raise RuntimeError("a body has no GPU slot after finalize")
    setup_s = time.perf_counter() - built

    def simulate(n):
        for _ in range(n):
            pipeline.simulate(viewer, state)

    def read():
        positions, _quats = state.read_body_poses(viewer)
        return positions

    # Warm-up, and the one slow first read.
    simulate(args.warmup)
    read()
    samples = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        simulate(args.short_steps)
        read()
        t1 = time.perf_counter() - t0
        t0 = time.perf_counter()
        simulate(args.steps)
        positions = read()
        t2 = time.perf_counter() - t0
        samples.append(steady_ms(args.short_steps, t1, args.steps, t2))
    by_body = [positions[r] for r in rows]
    drift, lowest = drift_and_lowest(scene, by_body)
    gpu_ms = ""
    if args.gpu_timestamps:
        gpu_ms = gpu_time(nx, viewer, pipeline, state)
    total = args.warmup + args.repeats * (args.short_steps + args.steps)
    row.update(
        steps=args.steps - args.short_steps,
        median_ms=f"{statistics.median(samples):.6f}",
        p90_ms=f"{percentile(samples, 0.9):.6f}",
        drift_m=f"{drift:.6f}",
        lowest_m="" if lowest is None else f"{lowest:.6f}",
        gpu_ms=gpu_ms,
        note=(
            f"steady state (t2-t1)/(N2-N1), N1={args.short_steps} N2={args.steps}, "
            f"{args.repeats} repeats, {total} steps in all; {args.substeps} substeps; "
            f"pair capacity {capacity}; setup {setup_s:.1f} s"
            + "".join(f"; {n}" for n in notes)
        ),
    )
    return row


def gpu_time(nx, viewer, pipeline, state):
    """GPU ms of a step from nexus's own timestamps (`run_stats`), or "" when unavailable.
    The timings are harvested by `viewer.sync`, a frame or two late, so a few steps run."""
    try:
        stamps = nx.GpuTimestamps(viewer, 4096)
        total = None
        for _ in range(5):
            pipeline.simulate(viewer, state, stamps)
            viewer.sync(state, stamps)
            value = state.run_stats().get("gpu_total_time_ms")
            if value:
                total = float(value)
        return "" if total is None else f"{total:.6f}"
    except Exception as e:  # noqa: BLE001 (an optional column; the row stands without it)
        print(f"  GPU timestamps unavailable: {e}", file=sys.stderr)
        return ""


def parse_args(argv):
    p = argparse.ArgumentParser(
        description="Runs nexus on tumble-scenes JSON files; writes bench-gpu's CSV columns.",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    p.add_argument("scenes", nargs="+", help="scene files (JSON, the tumble-scenes schema)")
    p.add_argument("--out", default="target/bench-gpu/nexus.csv", help="CSV to write")
    p.add_argument("--substeps", type=int, default=4, help="solver substeps per step")
    p.add_argument("--steps", type=int, default=60, help="long run length N2")
    p.add_argument("--short-steps", type=int, default=10, help="short run length N1")
    p.add_argument("--warmup", type=int, default=10, help="steps before the first read")
    p.add_argument("--repeats", type=int, default=3, help="(N1, N2) measurements per scene")
    p.add_argument(
        "--pairs-per-body",
        type=int,
        default=8,
        help="collision-pair capacity per body (nexus's default is 4096 pairs per scene)",
    )
    p.add_argument(
        "--backend",
        default=None,
        help="nexus GPU backend by name, see nexus3d.available_backends() (none: nexus's own)",
    )
    p.add_argument(
        "--gpu-timestamps",
        action="store_true",
        help="also read nexus's GPU timestamps (run_stats) into the gpu_ms column",
    )
    p.add_argument(
        "--dry-run",
        action="store_true",
        help="read the scenes and build the bodies (and the nexus state) without simulating",
    )
    args = p.parse_args(argv)
    if args.substeps < 1 or args.warmup < 0 or args.repeats < 1 or args.short_steps < 1:
        p.error("--substeps, --short-steps and --repeats must be at least 1, --warmup >= 0")
    if args.steps <= args.short_steps:
        p.error("--steps (N2) must be larger than --short-steps (N1)")
    return args


def write_csv(path, rows):
    folder = os.path.dirname(path)
    if folder:
        os.makedirs(folder, exist_ok=True)
    with open(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        writer.writerows(rows)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    nx, why = import_nexus()
    if nx is None and not args.dry_run:
        print(f"error: cannot import nexus3d ({why}); install dimforge-nexus3d", file=sys.stderr)
        return 2
    viewer = pipeline = None
    if not args.dry_run:
        # The backend is chosen and started before any state exists, as nexus requires.
        viewer = nx.NexusViewer(headless=True)
        if args.backend:
            viewer.with_backend(args.backend)
        viewer.init_backend()
        pipeline = nx.NexusPipeline()
        pipeline.preload_pipelines(viewer)
        print(f"nexus backend: {viewer.backend_name()}")
    rows = []
    failed = False
    for path in args.scenes:
        try:
            scene = SceneFile(path)
        except (OSError, ValueError) as e:
            print(f"{path}: skipped: {e}", file=sys.stderr)
            failed = True
            continue
        print(
            f"{scene.name}: {len(scene.bodies)} bodies ({scene.dynamic_count()} dynamic), "
            f"dt {scene.dt:.6f}, gravity {scene.gravity}",
            flush=True,
        )
        if args.dry_run:
            if nx is not None:
                state, handles, capacity = build_state(nx, scene, args)
                print(
                    f"  nexus state: {state.counts().rigid_bodies} rigid bodies, "
                    f"{state.counts().colliders} colliders, pair capacity {capacity}"
                )
            continue
        started = time.perf_counter()
        try:
            row = run_scene(nx, viewer, pipeline, scene, args)
        except Exception as e:  # noqa: BLE001 (one scene's failure must not lose the others)
            print(f"  skipped: {type(e).__name__}: {e}", file=sys.stderr)
            row = {c: "" for c in CSV_COLUMNS}
            row.update(
                scene=scene.name,
                bodies=len(scene.bodies),
                engine="nexus",
                steps=0,
                note=f"skipped: {type(e).__name__}: {e}",
            )
            failed = True
        print(
            f"  median {row['median_ms'] or '-'} ms/step, p90 {row['p90_ms'] or '-'}, "
            f"drift {row['drift_m'] or '-'} m, lowest {row['lowest_m'] or '-'} m "
            f"({time.perf_counter() - started:.1f} s)",
            flush=True,
        )
        rows.append(row)
        # Written after every scene, so a run cut short keeps what it measured.
        write_csv(args.out, rows)
    if not args.dry_run:
        print(f"wrote {args.out}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
