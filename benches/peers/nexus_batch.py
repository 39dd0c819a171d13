#!/usr/bin/env python3
"""Runs nexus (PyPI `dimforge-nexus3d`) on one Tumble JSON scene copied into N batched
environments (`NexusState.add_environment`, `insert_rigid_body_in`), for the batch rows of
`batch_table` (benches/src/bin/batch_table.rs), and writes a CSV:

    cargo run --release -p tumble-benches --bin batch_table -- --write-scene target/batch/column20.json
    python3 benches/peers/nexus_batch.py target/batch/column20.json --environments 1,64,1024,4096 \\
        --out target/batch/nexus.csv

Each environment holds every body of the scene (floor included), as Tumble's batch holds one
world per copy. The time per step is the steady state from two run lengths, each ending in a
pose read (`nexus_scenes.py` explains why), over `--repeats` measurements; drift is the
largest horizontal displacement of a dynamic body in any environment at the end.
"""

import argparse
import csv
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from nexus_scenes import (  # noqa: E402 (the sibling script, found through the path above)
    SceneFile,
    drift_and_lowest,
    import_nexus,
    percentile,
    steady_ms,
)

COLUMNS = "scene,environments,bodies,engine,median_ms,p90_ms,us_per_world_step,drift_m,note".split(",")


def build(nx, scene, environments, args):
    """The state with `environments` copies of the scene and the GPU rows of each copy."""
    state = nx.NexusState()
    handles = []
    for env in range(environments):
        if env > 0:
            created = state.add_environment()
            if created != env:
                raise RuntimeError(f"add_environment gave {created}, expected {env}")
        own = []
        for b in scene.bodies:
            if b.kind == "Fixed":
                builder = nx.RigidBodyBuilder.fixed()
            else:
                builder = nx.RigidBodyBuilder.dynamic()
            x, y, z, w = b.rotation
            pose = nx.Pose.from_parts(nx.Vec3(*b.position), nx.Quat.from_xyzw(x, y, z, w))
            builder = builder.pose(pose).can_sleep(False)
            collider = (
                nx.ColliderBuilder.cuboid(*b.half_extents)
                .density(b.density)
                .friction(b.friction)
                .friction_combine_rule("average")
                .restitution(b.restitution)
            )
            own.append(
                state.insert_rigid_body_in(env, builder.build(), collider.build(), nx.RbdCoupling.NONE)
            )
        handles.append(own)
    state.set_rbd_timestep(scene.dt, args.substeps)
    state.set_rbd_steps_per_frame(1)
    state.set_rbd_collisions_capacity(max(4096, args.pairs_per_body * len(scene.bodies)))
    return state, handles


def run(nx, viewer, pipeline, scene, environments, args):
    state, handles = build(nx, scene, environments, args)
    state.finalize(viewer)
    try:
        state.set_rbd_gravity(viewer, nx.Vec3(*scene.gravity))
    except Exception as e:  # noqa: BLE001 (the run stands at nexus's default gravity)
        print(f"  gravity left at nexus's default: {e}", file=sys.stderr)
    rows = [[state.body_gpu_index(env, h) for h in own] for env, own in enumerate(handles)]

    def simulate(n):
        for _ in range(n):
            pipeline.simulate(viewer, state)

    def read():
        positions, _quats = state.read_body_poses(viewer)
        return positions

    simulate(args.warmup)
    read()
    samples = []
    positions = None
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
    drift = 0.0
    for own in rows:
        d, _ = drift_and_lowest(scene, [positions[r] for r in own])
        drift = max(drift, d)
    median = statistics.median(samples)
    return {
        "scene": scene.name,
        "environments": environments,
        "bodies": environments * len(scene.bodies),
        "engine": "nexus",
        "median_ms": f"{median:.6f}",
        "p90_ms": f"{percentile(samples, 0.9):.6f}",
        "us_per_world_step": f"{median * 1e3 / environments:.4f}",
        "drift_m": f"{drift:.6f}",
        "note": (
            f"steady state (t2-t1)/(N2-N1), N1={args.short_steps} N2={args.steps}, "
            f"{args.repeats} repeats; {args.substeps} substeps"
        ),
    }


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("scene", help="scene file (JSON, the tumble-scenes schema)")
    p.add_argument("--environments", default="1,64,1024,4096", help="comma-separated counts")
    p.add_argument("--out", default="target/batch/nexus.csv")
    p.add_argument("--substeps", type=int, default=4)
    p.add_argument("--steps", type=int, default=60, help="long run length N2")
    p.add_argument("--short-steps", type=int, default=10, help="short run length N1")
    p.add_argument("--warmup", type=int, default=10)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--pairs-per-body", type=int, default=8)
    args = p.parse_args(sys.argv[1:] if argv is None else argv)
    counts = [int(c) for c in args.environments.split(",") if c]
    if not counts or min(counts) < 1 or args.steps <= args.short_steps:
        p.error("--environments must be positive counts and --steps > --short-steps")
    nx, why = import_nexus()
    if nx is None:
        print(f"error: cannot import nexus3d ({why})", file=sys.stderr)
        return 2
    scene = SceneFile(args.scene)
    viewer = nx.NexusViewer(headless=True)
    viewer.init_backend()
    pipeline = nx.NexusPipeline()
    pipeline.preload_pipelines(viewer)
    out = []
    for n in counts:
        started = time.perf_counter()
        try:
            row = run(nx, viewer, pipeline, scene, n, args)
        except Exception as e:  # noqa: BLE001 (one count's failure must not lose the others)
            row = {c: "" for c in COLUMNS}
            row.update(scene=scene.name, environments=n, engine="nexus", note=f"failed: {e}")
        print(
            f"{n} environments: {row['median_ms'] or '-'} ms/step, drift {row['drift_m'] or '-'} m "
            f"({time.perf_counter() - started:.1f} s)",
            flush=True,
        )
        out.append(row)
        folder = os.path.dirname(args.out)
        if folder:
            os.makedirs(folder, exist_ok=True)
        with open(args.out, "w", newline="", encoding="utf-8") as f:
            w = csv.DictWriter(f, fieldnames=COLUMNS)
            w.writeheader()
            w.writerows(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
