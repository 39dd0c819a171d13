#!/usr/bin/env python3
"""Writes the hand-made seed inputs under fuzz/corpus/<target>/seed_*.

Each seed is a meaningful case (a box resting on a slab, crossed edges, a stack's AABBs, a
world with a floor and a falling box, ...) encoded the way the `arbitrary` crate decodes the
targets' input types: fields in order; integers little-endian; `bool` as one byte (bit 0);
`Option` and each element of a `Vec` behind a `bool`; an enum's variant as a little-endian
`u32` whose value `v` picks variant `(v * count) >> 32`. `cargo +nightly fuzz fmt TARGET FILE`
prints what a seed decodes to.

Run from the repository root: `python3 fuzz/make_seeds.py`.
"""

import math
import os
import shutil
import struct

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def variant(index, count):
    # The smallest u32 that selects `index` of `count`.
    v = -(-(index << 32) // count)
    assert (v * count) >> 32 == index
    return struct.pack("<I", v)


def u8(x):
    return struct.pack("<B", x)


def u32(x):
    return struct.pack("<I", x)


def boolean(b):
    return u8(1 if b else 0)


def num(x):
    """A `tumble_fuzz::Num`: `Small(v)` (v / 64) when exact, else the raw f32."""
    v = x * 64
    if math.isfinite(v) and v == int(v) and -32768 <= v <= 32767:
        return variant(1, 3) + struct.pack("<h", int(v))
    return variant(0, 3) + struct.pack("<f", x)


def scaled(v, e):
    """`Num::Scaled(v, e + 160)`: v / 64 * 2^e."""
    return variant(2, 3) + struct.pack("<hh", v, e + 160)


def nums(xs):
    return b"".join(num(x) for x in xs)


def quat_z(deg):
    a = math.radians(deg) / 2
    return [0.0, 0.0, math.sin(a), math.cos(a)]


def quat_x(deg):
    a = math.radians(deg) / 2
    return [math.sin(a), 0.0, 0.0, math.cos(a)]


IDENTITY = [0.0, 0.0, 0.0, 1.0]


def write(target, name, data):
    d = os.path.join(ROOT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "seed_" + name), "wb") as f:
        f.write(data)


# --- collide_cuboids: Input { half_a, half_b, pos_a, pos_b, rot_a, rot_b, margin, previous }


def pair(half_a, half_b, pos_a, pos_b, rot_a, rot_b, margin, previous=None, raw=None):
    parts = [nums(half_a), nums(half_b), nums(pos_a), nums(pos_b), nums(rot_a), nums(rot_b)]
    if raw:
        for k, v in raw.items():
            parts[k] = v
    out = b"".join(parts) + num(margin)
    if previous is None:
        return out + boolean(False)
    kind, feature = previous
    return out + boolean(True) + u8(kind) + u32(feature)


def collide_seeds():
    t = "collide_cuboids"
    # A unit cube 2 mm into a 10 m slab: a face contact of four points.
    write(t, "resting_on_slab", pair([5, 0.5, 5], [0.5] * 3, [0] * 3, [1, 0.998, 0],
                                     IDENTITY, IDENTITY, 0.02))
    # Two equal cubes face to face, last step's reference face B's bottom (feature 3).
    write(t, "equal_cubes_history", pair([0.5] * 3, [0.5] * 3, [0] * 3, [0.25, 0.999, 0.25],
                                         IDENTITY, quat_z(0.25), 0.02, previous=(1, 3)))
    # Crossed edges 1 cm deep: an edge contact of one point.
    write(t, "edge_edge", pair([0.5] * 3, [0.5] * 3, [0] * 3, [0, math.sqrt(2) - 0.01, 0],
                               quat_z(45), quat_x(45), 0.02))
    # Corners 1 cm apart diagonally: a vertex contact within the margin.
    write(t, "corners_apart", pair([0.5] * 3, [0.5] * 3, [0] * 3, [1.006, 1.008, 0],
                                   IDENTITY, IDENTITY, 0.02))
    # A tilted cube's corner dipping into a slab, B's face the reference.
    write(t, "tilted_corner", pair([0.5] * 3, [5, 0.5, 5], [0, -1.02, 0], [0] * 3,
                                   quat_z(2.9), IDENTITY, 0.02))
    # The resting pair 10 km from the origin, where f32 positions step by 1 mm.
    write(t, "far_from_origin", pair([5, 0.5, 5], [0.5] * 3, [10000, 0, 10000],
                                     [10001, 0.998, 10000], IDENTITY, IDENTITY, 0.02))
    # The resting pair scaled by 2^-100 (tiny), 2^100 (huge) and to subnormal sizes.
    for name, e in [("tiny", -100), ("huge", 100), ("subnormal", -140)]:
        s = lambda v: scaled(v, e)
        half_a = s(320) + s(32) + s(320)
        half_b = s(32) * 3
        pos_b = s(64) + s(63) + s(0)
        write(t, name, pair([0] * 3, [0] * 3, [0] * 3, [0] * 3, IDENTITY, IDENTITY, 0.0,
                            raw={0: half_a, 1: half_b, 3: pos_b}))
    # A thin plate on a long rod, crossed at right angles.
    write(t, "plate_on_rod", pair([10, 0.05, 0.05], [0.01, 1, 1], [0] * 3, [0, 1.04, 0],
                                  IDENTITY, quat_x(30), 0.05))


# --- sweep_and_prune: Input { boxes: Vec<InputBox>, second_len: u8, bad_flags: Option<bool> }


def aabb(lo, other, is_size=True, is_static=False):
    return boolean(True) + nums(lo) + nums(other) + boolean(is_size) + boolean(is_static)


def boxes_input(boxes, second_len, bad_flags=None):
    out = b"".join(boxes) + boolean(False) + u8(second_len)
    if bad_flags is None:
        return out + boolean(False)
    return out + boolean(True) + boolean(bad_flags)


def sap_seeds():
    t = "sweep_and_prune"
    # A floor and a column of unit cubes whose AABBs touch exactly.
    floor = aabb([-5, -1, -5], [10, 1, 10], is_static=True)
    column = [aabb([0, y, 0], [1, 1, 1]) for y in range(6)]
    write(t, "stack", boxes_input([floor] + column, 3))
    # A 4 x 4 grid of cubes touching at faces, edges and corners, one flag short.
    grid = [aabb([x, 0, z], [1, 1, 1], is_static=(x + z) % 3 == 0) for x in range(4)
            for z in range(4)]
    write(t, "grid", boxes_input(grid, 7, bad_flags=False))
    # Duplicates, an inverted box, an empty (point) box and boxes sharing a lower bound.
    odd = [aabb([0, 0, 0], [1, 1, 1]), aabb([0, 0, 0], [1, 1, 1]),
           aabb([2, 2, 2], [1, 1, 1], is_size=False), aabb([0.5, 0.5, 0.5], [0, 0, 0]),
           aabb([0, 5, 0], [0.5, 1, 1])]
    write(t, "degenerate", boxes_input(odd, 2, bad_flags=True))
    # Non-finite bounds among ordinary boxes: NaN, infinities, -0.
    nonfinite = [aabb([0, 0, 0], [1, 1, 1]), aabb([float("nan"), 0, 0], [1, 1, 1]),
                 aabb([float("-inf"), -1, -1], [float("inf"), 2, 2], is_size=False),
                 aabb([-0.0, 0, 0], [0, 1, 1], is_size=False), aabb([0.5, 0.5, 0.5], [1, 1, 1])]
    write(t, "nonfinite", boxes_input(nonfinite, 4))
    # Boxes spread along z only, so that the sweep axis is z.
    spread = [aabb([0.25 * (i % 3), 0, 2 * i], [1, 1, 2.5]) for i in range(10)]
    write(t, "spread_along_z", boxes_input(spread, 5))


# --- scene_from_json: the scene files shipped with tumble-scenes and a few small ones.


def scene_seeds():
    t = "scene_from_json"
    src = os.path.join(os.path.dirname(ROOT), "..", "crates", "tumble-scenes", "scenes")
    for f in sorted(os.listdir(src)):
        if f.endswith(".json"):
            shutil.copyfile(os.path.join(src, f), os.path.join(ROOT, t, "seed_" + f))
    small = {
        "minimal.json": '{"name": "empty", "bodies": []}',
        "kinematic.json": '{"name": "platform", "gravity": [0, -9.81, 0], "dt": 0.01, '
        '"steps": 10, "bodies": [{"kind": "Fixed", "half_extents": [5, 0.5, 5], '
        '"position": [0, -0.5, 0]}, {"kind": "Kinematic", "half_extents": [1, 0.1, 1], '
        '"position": [0, 0.5, 0], "linear_velocity": [1, 0, 0], "density": 0}, '
        '{"half_extents": [0.25, 0.25, 0.25], "position": [0, 0.85, 0], '
        '"rotation": [0, 0.7071, 0, 0.7071], "friction": 0.3, "restitution": 0.5}]}',
        "bad_half_extents.json": '{"name": "bad", "bodies": [{"half_extents": [0.5, -1, 0.5], '
        '"position": [0, 0, 0]}]}',
        "bad_rotation.json": '{"name": "bad", "bodies": [{"half_extents": [1, 1, 1], '
        '"position": [0, 0, 0], "rotation": [0, 0, 0, 2]}]}',
        "extreme_values.json": '{"name": "extreme", "dt": 1e-30, "bodies": [{"half_extents": '
        '[1e-30, 1e30, 1e-45], "position": [3e38, 0, 0], "density": 1e-38, '
        '"linear_velocity": [1e38, 0, 0]}]}',
    }
    for name, text in small.items():
        write(t, name, text.encode())


# --- world_calls: Vec<Call>, each call behind a `true`.
CALLS = ["Add", "Remove", "Step", "SetPose", "SetLinearVelocity", "SetAngularVelocity",
         "ApplyImpulse", "SetKinematicTarget"]


def call(name, body=b""):
    return boolean(True) + variant(CALLS.index(name), len(CALLS)) + body


def raw_pose(t, q=IDENTITY, unnormalized=False):
    return nums(t) + nums(q) + boolean(unnormalized)


def add(kind, half, pos, q=IDENTITY, density=1, friction=0.6, restitution=0, lin=(0, 0, 0),
        ang=(0, 0, 0), locks=0, damping=(0, 0)):
    body = (u8(kind) + nums(half) + raw_pose(pos, q) + num(density) + num(friction)
            + num(restitution) + nums(lin) + nums(ang) + u8(locks) + nums(damping))
    return call("Add", body)


DYNAMIC, FIXED, KINEMATIC = 0, 1, 2


def world_seeds():
    t = "world_calls"
    floor = add(FIXED, [5, 0.5, 5], [0, -0.5, 0])
    steps = lambda n: call("Step") * n
    # A cube dropped onto a floor, stepped until it lands.
    write(t, "drop_on_floor", floor + add(DYNAMIC, [0.5] * 3, [0, 1, 0]) + steps(30))
    # A stack of three, the middle one removed while the stack stands, then stepped.
    stack = floor + b"".join(add(DYNAMIC, [0.5] * 3, [0, 0.5 + y, 0]) for y in range(3))
    write(t, "remove_from_stack", stack + steps(5) + call("Remove", u8(2)) + steps(10)
          + call("SetPose", u8(2) + raw_pose([0, 3, 0])))
    # A kinematic platform carrying a box, driven by targets.
    platform = floor + add(KINEMATIC, [1, 0.1, 1], [0, 0.1, 0], density=0)
    platform += add(DYNAMIC, [0.25] * 3, [0, 0.45, 0], friction=1)
    for k in range(6):
        platform += call("SetKinematicTarget", u8(1) + raw_pose([0.05 * (k + 1), 0.1, 0]))
        platform += call("Step")
    write(t, "kinematic_platform", platform)
    # Velocities, impulses and rotations on a spinning, bouncing box with locks and damping.
    spin = floor + add(DYNAMIC, [0.5, 0.25, 1], [0, 2, 0], q=quat_z(30), restitution=0.5,
                       ang=(0, 5, 0), locks=0b001001, damping=(0.1, 0.5))
    spin += call("SetLinearVelocity", u8(1) + nums([1, 0, 0])) + steps(3)
    spin += call("SetAngularVelocity", u8(1) + nums([0, 0, 3])) + steps(3)
    spin += call("ApplyImpulse", u8(1) + nums([0, 2, 0]) + nums([0.5, 2, 0])) + steps(20)
    write(t, "spin_and_impulse", spin)
    # Bad input on every call (NaN, a fixed body given a velocity, a dynamic body a target,
    # a zero quaternion, a removed handle): each an Err that must leave the world unchanged.
    nan = float("nan")
    bad = floor + add(DYNAMIC, [0.5] * 3, [0, 0.5, 0]) + steps(2)
    bad += add(DYNAMIC, [0.5, nan, 0.5], [0, 2, 0])
    bad += call("SetPose", u8(1) + raw_pose([nan, 0, 0]))
    bad += call("SetPose", u8(1) + raw_pose([0, 1, 0], [0, 0, 0, 0], unnormalized=True))
    bad += call("SetLinearVelocity", u8(0) + nums([1, 0, 0]))
    bad += call("SetKinematicTarget", u8(1) + raw_pose([0, 1, 0]))
    bad += call("ApplyImpulse", u8(1) + nums([float("inf"), 0, 0]) + nums([0, 0, 0]))
    bad += call("Remove", u8(1)) + call("SetAngularVelocity", u8(1) + nums([0, 1, 0]))
    bad += steps(2)
    write(t, "bad_input", bad)
    # A tiny box on a huge one, and a heavy one on a light one.
    extremes = add(FIXED, [1e4, 1, 1e4], [0, -1, 0]) + add(DYNAMIC, [1e-3] * 3, [0, 1e-3, 0])
    extremes += add(DYNAMIC, [0.5] * 3, [3, 0.5, 0]) + add(DYNAMIC, [0.5] * 3, [3, 1.5, 0],
                                                           density=1000)
    write(t, "sizes_and_masses", extremes + steps(20))


if __name__ == "__main__":
    for d in ["collide_cuboids", "sweep_and_prune", "scene_from_json", "world_calls"]:
        os.makedirs(os.path.join(ROOT, d), exist_ok=True)
        for f in os.listdir(os.path.join(ROOT, d)):
            if f.startswith("seed_"):
                os.remove(os.path.join(ROOT, d, f))
    collide_seeds()
    sap_seeds()
    scene_seeds()
    world_seeds()
