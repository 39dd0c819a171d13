"""Checks of nexus_scenes.py that need neither nexus nor a GPU:

    python3 -m unittest discover -s benches/peers
"""

import csv
import json
import os
import tempfile
import unittest

import nexus_scenes as ns


def scene_file(folder, bodies, **extra):
    data = {"name": "probe", "bodies": bodies}
    data.update(extra)
    path = os.path.join(folder, "probe.json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(data, f)
    return path


class SceneReading(unittest.TestCase):
    def test_defaults_of_the_schema_fill_missing_fields(self):
        with tempfile.TemporaryDirectory() as d:
            path = scene_file(d, [{"half_extents": [0.5, 0.5, 0.5], "position": [0, 0.5, 0]}])
            scene = ns.SceneFile(path)
        body = scene.bodies[0]
        self.assertEqual(body.kind, "Dynamic")
        self.assertEqual(body.rotation, [0.0, 0.0, 0.0, 1.0])
        self.assertEqual((body.density, body.friction, body.restitution), (1.0, 0.6, 0.0))
        self.assertEqual(scene.gravity, [0.0, -9.81, 0.0])
        self.assertAlmostEqual(scene.dt, 1.0 / 60.0)
        self.assertEqual(scene.up_axis(), [0.0, 1.0, 0.0])

    def test_a_bad_body_is_rejected_with_its_index(self):
        with tempfile.TemporaryDirectory() as d:
            path = scene_file(d, [{"half_extents": [0.5, 0.5], "position": [0, 0, 0]}])
            with self.assertRaisesRegex(ValueError, "body 0"):
                ns.SceneFile(path)


class Measures(unittest.TestCase):
    def test_drift_is_horizontal_and_lowest_is_along_up(self):
        with tempfile.TemporaryDirectory() as d:
            path = scene_file(
                d,
                [
                    {"kind": "Fixed", "half_extents": [5, 0.5, 5], "position": [0, -0.5, 0]},
                    {"half_extents": [0.5, 0.5, 0.5], "position": [0, 0.5, 0]},
                    {"half_extents": [0.5, 0.5, 0.5], "position": [0, 1.5, 0]},
                ],
            )
            scene = ns.SceneFile(path)
        # The fixed body "moved" 9 m: ignored. The top box sank 1 m and slid 0.3 x 0.4.
        drift, lowest = ns.drift_and_lowest(scene, [[9, 0, 0], [0, 0.5, 0], [0.3, 0.5, 0.4]])
        self.assertAlmostEqual(drift, 0.5)
        self.assertAlmostEqual(lowest, 0.5)

    def test_steady_state_is_the_difference_of_two_runs(self):
        # 250 ms of one-off cost in both runs cancels: 10 ms per step.
        self.assertAlmostEqual(ns.steady_ms(10, 0.35, 60, 0.85), 10.0)
        with self.assertRaises(ValueError):
            ns.steady_ms(60, 1.0, 60, 1.0)


class Output(unittest.TestCase):
    def test_the_csv_has_bench_gpus_columns(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "sub", "nexus.csv")
            row = {c: "" for c in ns.CSV_COLUMNS}
            row.update(scene="pyramid_8", bodies=205, engine="nexus", note="a, b")
            ns.write_csv(path, [row])
            with open(path, newline="", encoding="utf-8") as f:
                rows = list(csv.reader(f))
        self.assertEqual(rows[0], ns.CSV_COLUMNS)
        self.assertEqual(rows[1][0], "pyramid_8")
        self.assertEqual(rows[1][-1], "a, b")

    def test_arguments_need_a_longer_second_run(self):
        with self.assertRaises(SystemExit):
            ns.parse_args(["x.json", "--steps", "10", "--short-steps", "10"])
        args = ns.parse_args(["x.json"])
        self.assertEqual((args.substeps, args.steps, args.short_steps), (4, 60, 10))


if __name__ == "__main__":
    unittest.main()
