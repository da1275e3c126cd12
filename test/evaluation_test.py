#!/usr/bin/env python3
"""Unit tests of tools/eval/evaluation.py (alignment, association, metrics)."""
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "eval"))
import evaluation as ev  # noqa: E402


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


class EvaluationTest(unittest.TestCase):
    def test_alignment_recovers_rigid_transform(self):
        rng = np.random.default_rng(3)
        est = rng.normal(size=(50, 3))
        r_true = rot_z(0.7) @ np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
        t_true = np.array([0.3, -1.0, 2.0])
        ref = (r_true @ est.T).T + t_true
        r, t = ev.align_rigid(est, ref)
        np.testing.assert_allclose(r, r_true, atol=1e-9)
        np.testing.assert_allclose(t, t_true, atol=1e-9)
        self.assertLess(ev.trajectory_error(est, ref)["rmse"], 1e-9)

    def test_ate_of_noisy_trajectory(self):
        rng = np.random.default_rng(4)
        ref = np.cumsum(rng.normal(scale=0.1, size=(200, 3)), axis=0)
        est = ref + rng.normal(scale=0.01, size=ref.shape)
        res = ev.trajectory_error(est, ref)
        self.assertGreater(res["rmse"], 0.005)
        self.assertLess(res["rmse"], 0.02)

    def test_association_nearest_within_tolerance(self):
        pairs = ev.associate([0.0, 0.1, 0.5], [0.001, 0.099, 0.3], max_dt=0.005)
        self.assertEqual(pairs, [(0, 0), (1, 1)])

    def test_sphere_error(self):
        rng = np.random.default_rng(5)
        d = rng.normal(size=(100, 3))
        d /= np.linalg.norm(d, axis=1)[:, None]
        pts = np.array([1.0, 2.0, 3.0]) + 0.2 * d
        rms, med = ev.sphere_error(pts, np.eye(3), np.zeros(3), [1.0, 2.0, 3.0], 0.2)
        self.assertLess(rms, 1e-12)
        rms, _ = ev.sphere_error(pts * 1.0 + 0.01 * d, np.eye(3), np.zeros(3), [1.0, 2.0, 3.0], 0.2)
        self.assertAlmostEqual(rms, 0.01, places=9)

    def test_quaternion(self):
        np.testing.assert_allclose(ev.quat_to_rot([0, 0, np.sin(0.35), np.cos(0.35)]), rot_z(0.7), atol=1e-12)

    def test_path_length(self):
        self.assertAlmostEqual(ev.path_length([[0, 0, 0], [3, 4, 0], [3, 4, 1]]), 6.0)


if __name__ == "__main__":
    unittest.main()
