#!/usr/bin/env python3
"""Unit tests of the surface evaluator (tools/eval: surface_metrics,
evaluate_surface, trajectory_io's PLY reader) on synthetic meshes of a
plane whose truth is known exactly."""
import os
import struct
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "eval"))
import evaluate_surface  # noqa: E402
import scene_geometry as sg  # noqa: E402
import surface_metrics as sm  # noqa: E402
import trajectory_io as tio  # noqa: E402

PLANE = [sg.Plane([0, 0, 0], [0, 0, 1], 0.5)]


def grid_mesh(x0, x1, y0, y1, step, z=0.0, jitter=0.0):
    """A triangulated grid on the plane z: (vertices, faces); jitter moves
    each vertex within +-jitter [m] in the plane, as a marching-cubes mesh's
    vertices lie anywhere on the surface."""
    xs, ys = np.arange(x0, x1 + 1e-12, step), np.arange(y0, y1 + 1e-12, step)
    gx, gy = np.meshgrid(xs, ys)
    v = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, z)])
    v[:, :2] += np.random.default_rng(1).uniform(-jitter, jitter, (len(v), 2))
    nx = len(xs)
    i, j = np.meshgrid(np.arange(len(ys) - 1), np.arange(nx - 1), indexing="ij")
    a = (i * nx + j).ravel()
    f = np.concatenate([np.column_stack([a, a + 1, a + nx]), np.column_stack([a + 1, a + nx + 1, a + nx])])
    return v, f


def looking_down(x, y, height):
    """T_world_camera of an optical frame at (x, y, height) looking along -z."""
    T = np.eye(4)
    T[:3, :3] = np.diag([1.0, -1.0, -1.0])
    T[:3, 3] = [x, y, height]
    return T


PATTERN_YAML = """
unit: PU
origin: [0, 0, 0]
along: [1, 0, 0]
up: [0, 1, 0]
base: 300
wave_amplitude: 100
wave_length: 0.05
bands:
  - {axis: s, from: 0.0, to: 0.02, value: 400}
discs:
  - {s: -0.02, t: 0.0, radius: 0.01, value: 300}
"""


class MeshDistanceTest(unittest.TestCase):
    def test_exact_distance_to_triangles(self):
        v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)
        f = np.array([[0, 1, 2]])
        pts = np.array([[0.2, 0.2, 0.3],    # above the inside: the height
                        [-1.0, -1.0, 0.0],  # beyond vertex a
                        [0.5, -2.0, 0.0],   # beyond edge ab
                        [1.0, 1.0, 0.0]])   # beyond edge bc
        d = sm.distance_to_mesh(pts, v, f)
        np.testing.assert_allclose(d, [0.3, np.sqrt(2), 2.0, np.sqrt(0.5)], atol=1e-12)


class AccuracyCompletenessTest(unittest.TestCase):
    def test_offset_mesh_accuracy(self):
        v, f = grid_mesh(-0.05, 0.05, -0.05, 0.05, 0.002, z=0.0005)
        a = sm.accuracy(v, PLANE)
        self.assertAlmostEqual(a["rms_mm"], 0.5, places=6)
        self.assertAlmostEqual(a["p95_mm"], 0.5, places=6)

    def test_completeness_of_half_the_seen_area(self):
        # A 100 x 100 px camera at f = 500 px, 0.25 m above the plane, sees
        # the 5 x 5 cm square about its foot; the mesh covers its x < 0 half.
        camera = (500.0, 500.0, 49.5, 49.5, 100, 100)
        poses = [looking_down(0.0, 0.0, 0.25)] * 3
        seen, counts = sm.seen_points(PLANE, poses, camera, 0.15, 0.5, step=1)
        self.assertTrue(np.all(counts == 3))
        self.assertTrue(np.all(np.abs(seen[:, :2]) <= 0.0251))
        v, f = grid_mesh(-0.03, 0.0, -0.03, 0.03, 0.002)
        c = sm.completeness(v, f, seen, counts)
        # Covered: the seen points within 1 mm of the half plane x <= 0 (about half).
        self.assertAlmostEqual(c["completeness_pct"], 100.0 * np.mean(seen[:, 0] <= 0.001 + 1e-12), places=6)
        self.assertAlmostEqual(c["completeness_pct"], 50.0, delta=5.0)
        # Seen in fewer keyframes than required: nothing to score.
        with self.assertRaises(ValueError):
            sm.completeness(v, f, seen, counts, min_frames=4)
        # 2 mm off the surface: nothing covered.
        v2, f2 = grid_mesh(-0.03, 0.03, -0.03, 0.03, 0.002, z=0.002)
        self.assertEqual(sm.completeness(v2, f2, seen, counts)["completeness_pct"], 0.0)

    def test_occluded_and_far_surfaces_are_not_seen(self):
        camera = (500.0, 500.0, 49.5, 49.5, 100, 100)
        pose = looking_down(0.0, 0.0, 0.25)
        blocker = sg.Plane([0, 0, 0.12], [0, 0, 1], 0.5)  # nearer than 0.15 m: out of range, yet in front
        seen, _ = sm.seen_points(PLANE + [blocker], [pose], camera, 0.15, 0.5)
        self.assertEqual(len(seen), 0)
        seen, _ = sm.seen_points(PLANE, [pose], camera, 0.15, 0.2)  # the plane beyond max depth
        self.assertEqual(len(seen), 0)


class RegistrationTest(unittest.TestCase):
    def setUp(self):
        self.pattern = sm.parse_perfusion(PATTERN_YAML)
        self.v, _ = grid_mesh(-0.04, 0.04, -0.03, 0.03, 0.0005, jitter=0.00025)

    def test_pattern_values(self):
        p = self.pattern
        self.assertAlmostEqual(p.value([[0.01, 0.0125, 0]])[0], 300 + 100 * np.cos(2 * np.pi * 0.2) * np.cos(
            2 * np.pi * 0.25) + 400)
        self.assertAlmostEqual(p.value([[-0.02, 0.0, 0]])[0], 300 + 100 * np.cos(2 * np.pi * -0.4) + 300)
        with self.assertRaises(ValueError):
            sm.parse_perfusion("base: 1")

    def test_perfect_projection_has_no_offset(self):
        r = sm.registration(self.v, self.pattern.value(self.v), self.pattern)
        self.assertGreater(r["edge_pieces"], 10)
        self.assertLess(r["registration_rms_mm"], 0.1)

    def test_shifted_projection_shows_the_shift(self):
        # The projected image lands 1 mm too far along +s: every band edge
        # (across s) moves by 1 mm; the disc's edge by 1 mm times |cos|.
        shifted = self.pattern.value(self.v - [0.001, 0, 0])
        off = sm.edge_offsets(self.v, shifted, self.pattern)
        band = sm.edge_offsets(self.v, shifted, sm.parse_perfusion(PATTERN_YAML.split("discs:")[0]))
        np.testing.assert_allclose(np.abs(band), 0.001, atol=0.0001)
        self.assertEqual(len(band), 12)  # 2 edges x 6 pieces of 1 cm
        self.assertGreater(np.max(np.abs(off)), 0.0009)
        # A blurred projection of the same shift: the mean-based offset is unchanged.
        blurred = np.mean([self.pattern.value(self.v - [0.001 + e, 0, 0]) for e in np.linspace(-0.0015, 0.0015, 7)],
                          axis=0)
        band_blurred = sm.edge_offsets(self.v, blurred, sm.parse_perfusion(PATTERN_YAML.split("discs:")[0]))
        np.testing.assert_allclose(np.abs(band_blurred), 0.001, atol=0.0002)

    def test_unseen_vertices_are_ignored(self):
        values = self.pattern.value(self.v)
        values[self.v[:, 0] > 0.005] = np.nan  # the band's inside never seen
        off = sm.edge_offsets(self.v, values, self.pattern)
        self.assertTrue(np.all(np.abs(off) < 0.0001))


class PlyAndCliTest(unittest.TestCase):
    def write_binary_ply(self, path, v, f, values):
        """The layout hapi_surface writes (x y z nx ny nz red green blue value value_weight)."""
        head = ("ply\nformat binary_little_endian 1.0\ncomment test\nelement vertex %d\n"
                "property float x\nproperty float y\nproperty float z\n"
                "property float nx\nproperty float ny\nproperty float nz\n"
                "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                "property float value\nproperty float value_weight\n"
                "element face %d\nproperty list uchar int vertex_indices\nend_header\n") % (len(v), len(f))
        with open(path, "wb") as out:
            out.write(head.encode())
            for p, val in zip(v, values):
                out.write(struct.pack("<6f3B2f", *p, 0, 0, 1, 10, 20, 30, val, 1.0))
            for tri in f:
                out.write(struct.pack("<B3i", 3, *tri))

    def test_binary_and_ascii_ply(self):
        v, f = grid_mesh(0, 0.002, 0, 0.002, 0.001)
        values = np.arange(len(v), dtype=float)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "m.ply")
            self.write_binary_ply(path, v, f, values)
            rv, rf, rval = evaluate_surface.read_mesh(path)
            np.testing.assert_allclose(rv, v, atol=1e-7)
            np.testing.assert_array_equal(rf, f)
            np.testing.assert_allclose(rval, values)
            with open(os.path.join(d, "a.ply"), "w") as out:
                out.write("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n1 2 3\n4 5 6\n")
            np.testing.assert_allclose(tio.read_ply_points(os.path.join(d, "a.ply")), [[1, 2, 3], [4, 5, 6]])

    def test_cli_on_files(self):
        v, f = grid_mesh(-0.04, 0.04, -0.03, 0.03, 0.0005, z=0.0003, jitter=0.00025)
        pattern = sm.parse_perfusion(PATTERN_YAML)
        with tempfile.TemporaryDirectory() as d:
            mesh, scene, perf, gt, out = (os.path.join(d, n) for n in
                                          ("m.ply", "scene.yaml", "p.yaml", "gt.tum", "r.json"))
            self.write_binary_ply(mesh, v, f, pattern.value(v))
            with open(scene, "w") as o:
                o.write("name: plane\nsurfaces:\n  - {type: plane, point: [0, 0, 0], normal: [0, 0, 1], "
                        "half_extent: 0.5}\n")
            with open(perf, "w") as o:
                o.write(PATTERN_YAML)
            with open(gt, "w") as o:  # looking down from 0.25 m (qx = 1: 180 deg about x)
                for i in range(20):  # 2 s: 4 keyframes at 2 Hz
                    o.write(f"{0.1 * i} 0 0 0.25 1 0 0 0\n")
            self.assertEqual(evaluate_surface.main(
                ["--mesh", mesh, "--scene", scene, "--perfusion", perf, "--trajectory", gt,
                 "--camera", "500,500,49.5,49.5,100,100", "--json", out]), 0)
            import json
            with open(out) as i:
                r = json.load(i)
            self.assertAlmostEqual(r["rms_mm"], 0.3, places=4)
            self.assertEqual(r["completeness_pct"], 100.0)
            self.assertLess(r["registration_rms_mm"], 0.1)


if __name__ == "__main__":
    unittest.main()
