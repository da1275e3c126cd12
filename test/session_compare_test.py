#!/usr/bin/env python3
"""Unit tests of the session comparison (tools/eval/session_compare.py) on
synthetic meshes whose differences are known exactly: a plane, the same
plane 1 mm above it with values 0.5 higher, vertices moved within the
plane, a second scan reaching beyond the first, and the files written."""
import os
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "eval"))
import session_compare as sc  # noqa: E402
import trajectory_io as tio  # noqa: E402


def plane_surface(x0, x1, step, z=0.0, shift=(0.0, 0.0), value=None):
    """A triangulated square grid on the plane z (normals +z), its vertices
    moved by `shift` within the plane; value(x, y) per vertex or none."""
    xs = np.arange(x0, x1 + 1e-12, step)
    gx, gy = np.meshgrid(xs, xs)
    v = np.column_stack([gx.ravel() + shift[0], gy.ravel() + shift[1], np.full(gx.size, z)])
    n = len(xs)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    f = np.concatenate([np.column_stack([a, a + 1, a + n]), np.column_stack([a + 1, a + n + 1, a + n])])
    return {"v": v, "n": np.tile([0.0, 0.0, 1.0], (len(v), 1)), "faces": f,
            "value": None if value is None else value(v[:, 0], v[:, 1])}


def wave(x, y):
    return 300.0 + 100.0 * np.sin(2 * np.pi * x / 0.05)


class CompareTest(unittest.TestCase):
    def test_offset_along_the_normal_and_value_offset(self):
        first = plane_surface(-0.02, 0.02, 0.001, value=wave)
        second = plane_surface(-0.02, 0.02, 0.001, z=0.001, value=lambda x, y: wave(x, y) + 0.5)
        fig, signed, diff = sc.compare(first, second)
        self.assertAlmostEqual(fig["overlap_fraction"], 1.0)
        self.assertAlmostEqual(fig["point_to_plane_m"]["rms"], 0.001, places=9)
        self.assertAlmostEqual(fig["point_to_plane_m"]["p95"], 0.001, places=9)
        self.assertAlmostEqual(fig["point_to_plane_m"]["mean"], 0.001, places=9)  # signed: above the first
        self.assertAlmostEqual(fig["value_difference"]["rms"], 0.5, places=9)
        self.assertAlmostEqual(fig["value_difference"]["mean"], 0.5, places=9)
        np.testing.assert_allclose(diff, 0.5, atol=1e-9)

    def test_point_to_plane_ignores_the_vertex_spacing(self):
        # Half a grid step off within the plane: the nearest vertex is
        # 0.35 mm away, the surfaces coincide.
        first = plane_surface(-0.02, 0.02, 0.001)
        second = plane_surface(-0.019, 0.019, 0.001, shift=(0.0005, 0.0005))
        fig, _, diff = sc.compare(first, second)
        self.assertLess(fig["point_to_plane_m"]["rms"], 1e-12)
        self.assertAlmostEqual(fig["nearest_vertex_m"]["rms"], 0.0005 * np.sqrt(2), places=9)
        self.assertEqual(fig["value_difference"]["count"], 0)  # no values: none compared
        self.assertTrue(np.isnan(diff).all())

    def test_vertices_beyond_the_first_scan_are_outside_the_overlap(self):
        first = plane_surface(-0.02, 0.0, 0.001, value=wave)
        second = plane_surface(-0.02, 0.02, 0.001, z=0.002, value=wave)
        fig, signed, diff = sc.compare(first, second, max_gap=0.004)
        # The first covers x, y <= 0; the second's vertices 2 mm above, the
        # nearest first vertex at (min(x, 0), min(y, 0)).
        beyond = np.clip(second["v"][:, :2], 0.0, None)
        inside = (beyond == 0).all(axis=1)
        near = np.sum(beyond ** 2, axis=1) + 0.002 ** 2 <= 0.004 ** 2 + 1e-12
        self.assertAlmostEqual(fig["overlap_fraction"], near.mean(), places=9)
        self.assertTrue(np.isnan(signed[~near]).all())
        np.testing.assert_allclose(signed[inside], 0.002, atol=1e-12)
        self.assertTrue(np.isnan(diff[~near]).all())
        np.testing.assert_allclose(diff[inside], 0.0, atol=1e-9)

    def test_normals_from_the_triangles_when_the_file_has_none(self):
        first = plane_surface(-0.01, 0.01, 0.001)
        n = sc.vertex_normals(first["v"], first["faces"])
        np.testing.assert_allclose(np.abs(n[:, 2]), 1.0, atol=1e-12)
        first["n"] = None
        second = plane_surface(-0.01, 0.01, 0.001, z=-0.0003)
        fig, _, _ = sc.compare(first, second)
        self.assertAlmostEqual(fig["point_to_plane_m"]["rms"], 0.0003, places=9)

    def test_colours_go_blue_white_red_and_grey_without_a_difference(self):
        rgb = sc.difference_colours(np.array([-1.0, 0.0, 1.0, np.nan]))
        np.testing.assert_array_equal(rgb, [[0, 0, 255], [255, 255, 255], [255, 0, 0], [128, 128, 128]])


class FilesTest(unittest.TestCase):
    def test_ply_png_json_written_and_read_back(self):
        first = plane_surface(-0.02, 0.02, 0.002, value=wave)
        second = plane_surface(-0.02, 0.02, 0.002, z=0.001, value=lambda x, y: wave(x, y) - 2.0)
        with tempfile.TemporaryDirectory() as d:
            a, b, prefix = os.path.join(d, "a.ply"), os.path.join(d, "b.ply"), os.path.join(d, "diff")
            for s, p in ((first, a), (second, b)):
                sc.write_ply(p, s["v"], s["n"], np.zeros((len(s["v"]), 3), np.uint8), s["value"], s["faces"])
            self.assertEqual(sc.main(["session_compare.py", a, b, prefix]), 0)
            out = tio.read_ply(prefix + ".ply")
            np.testing.assert_allclose(out["vertex"]["value"], -2.0, atol=1e-3)
            np.testing.assert_allclose(out["vertex"]["blue"], 255)  # negative: blue
            self.assertEqual(len(out["face"]["vertex_indices"]), len(second["faces"]))
            self.assertGreater(os.path.getsize(prefix + ".png"), 1000)
            with open(prefix + ".json") as f:
                fig = __import__("json").load(f)
            self.assertAlmostEqual(fig["point_to_plane_m"]["rms"], 0.001, places=6)
            self.assertAlmostEqual(fig["value_difference"]["mean"], -2.0, places=3)


if __name__ == "__main__":
    unittest.main()
