#!/usr/bin/env python3
"""Unit tests of the evaluator's metrics, scene geometry, file formats, the
offline CLI and the plots (tools/eval: trajectory_metrics, scene_geometry,
trajectory_io, run_analysis, evaluate.py, plots)."""
import os
import sys
import tempfile
import unittest

import numpy as np
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "eval"))
import evaluate  # noqa: E402
import evaluation as ev  # noqa: E402
import plots  # noqa: E402
import run_analysis  # noqa: E402
import scene_geometry as sg  # noqa: E402
import surface_motion_metrics as smm  # noqa: E402
import trajectory_io as tio  # noqa: E402
import trajectory_metrics as tm  # noqa: E402


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rot_x(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def circle_trajectory(n=400, rate=20.0):
    """Camera on a 2 m circle at 0.3 rad/s, looking inwards, gently bobbing."""
    t = np.arange(n) / rate
    p = np.column_stack([2 * np.cos(0.3 * t), 2 * np.sin(0.3 * t), 0.2 * np.sin(0.7 * t)])
    r = np.array([rot_z(0.3 * ti) @ rot_x(0.1 * np.sin(ti)) for ti in t])
    return t, p, r


def as_traj(t, p, r):
    return {"t": t, "p": p, "q": np.array([ev.rot_to_quat(x) for x in r])}


class AlignmentTest(unittest.TestCase):
    def test_se3_and_sim3_recover_transform_and_scale(self):
        rng = np.random.default_rng(1)
        est = rng.normal(size=(60, 3))
        r_true = rot_z(-1.1) @ rot_x(0.4)
        t_true = np.array([1.0, -2.0, 0.5])
        ref_rigid = (r_true @ est.T).T + t_true
        r, t, s = ev.align_umeyama(est, ref_rigid)
        np.testing.assert_allclose(r, r_true, atol=1e-9)
        np.testing.assert_allclose(t, t_true, atol=1e-9)
        self.assertEqual(s, 1.0)
        ref_scaled = 1.7 * (r_true @ est.T).T + t_true
        r, t, s = ev.align_umeyama(est, ref_scaled, with_scale=True)
        np.testing.assert_allclose(r, r_true, atol=1e-9)
        np.testing.assert_allclose(t, t_true, atol=1e-9)
        self.assertAlmostEqual(s, 1.7, places=9)
        # The rigid fit of a scaled copy leaves an error that Sim(3) removes.
        self.assertGreater(tm.ate(est, ref_scaled)["rmse"], 0.1)
        self.assertLess(tm.ate(est, ref_scaled, with_scale=True)["rmse"], 1e-9)

    def test_so3_log_and_rotation_angle(self):
        r = rot_z(0.3) @ rot_x(-0.2)
        np.testing.assert_allclose(tm.exp_so3(ev.so3_log(r)), r, atol=1e-12)
        self.assertAlmostEqual(ev.rotation_angle(rot_z(3.0)), 3.0, places=9)
        self.assertAlmostEqual(ev.rotation_angle(np.eye(3)), 0.0, places=12)


class RelativeErrorTest(unittest.TestCase):
    def test_rpe_of_a_known_drift(self):
        t, p, r = circle_trajectory()
        # Estimate drifts 2 cm per second along world x and turns 0.5 deg/s
        # about world z more than the truth: over 1 s each relative motion is
        # off by 2 cm and 0.5 deg, whatever the world alignment.
        drift = np.array([[ti * 0.02, 0.0, 0.0] for ti in t])
        est_r = np.array([rot_z(np.radians(0.5) * ti) @ ri for ti, ri in zip(t, r)])
        est_p = np.array([rot_z(np.radians(0.5) * ti) @ pi for ti, pi in zip(t, p)]) + drift
        trans, rot = tm.rpe(t, est_p, est_r, p, r, delta=1.0)
        self.assertEqual(len(trans), len(t) - 20)
        np.testing.assert_allclose(rot, 0.5, atol=1e-9)
        self.assertGreater(trans.min(), 0.0)
        trans0, rot0 = tm.rpe(t, p, r, p, r, delta=1.0)
        self.assertLess(trans0.max(), 1e-12)
        self.assertLess(rot0.max(), 1e-9)
        # A pure translation drift: exactly 2 cm per second.
        trans_d, _ = tm.rpe(t, p + drift, r, p, r, delta=1.0)
        np.testing.assert_allclose(trans_d, 0.02, atol=1e-9)


class NeesTest(unittest.TestCase):
    def test_nees_of_a_known_gaussian_sample(self):
        rng = np.random.default_rng(7)
        n = 2000
        a = rng.normal(size=(3, 3))
        cov = a @ a.T + 0.1 * np.eye(3)
        e = rng.multivariate_normal(np.zeros(3), cov, size=n)
        v = tm.nees(e, np.repeat(cov[None], n, axis=0))
        s = tm.nees_summary(v)
        lo, hi = s["mean_bounds_95"]
        self.assertLess(lo, s["mean"])
        self.assertLess(s["mean"], hi)
        self.assertAlmostEqual(s["fraction_in_95_band"], 0.95, delta=0.02)
        self.assertAlmostEqual(s["fraction_above_95_band"], 0.025, delta=0.015)
        # A covariance stated 4x too small is detected.
        s_bad = tm.nees_summary(tm.nees(e, np.repeat(cov[None] / 4, n, axis=0)))
        self.assertGreater(s_bad["mean"], s_bad["mean_bounds_95"][1])
        self.assertGreater(s_bad["fraction_above_95_band"], 0.3)

    def test_pose_nees_uses_the_alignment(self):
        rng = np.random.default_rng(8)
        t, p, r = circle_trajectory(n=300)
        sp, sr = 0.01, np.radians(0.5)
        r_w = rot_z(0.8)
        t_w = np.array([0.5, 0.1, -0.3])
        # Estimate in its own world: T_est = T_w^-1 * (perturbed truth).
        e_p = p + rng.normal(scale=sp, size=p.shape)
        e_r = np.array([tm.exp_so3(rng.normal(scale=sr, size=3)) @ ri for ri in r])
        est_p = (r_w.T @ (e_p - t_w).T).T
        est_r = np.array([r_w.T @ x for x in e_r])
        cov = np.zeros((len(t), 6, 6))
        # Covariances in the estimate's world frame (rotated by R_w^T).
        cov[:, :3, :3] = sp ** 2 * np.eye(3)
        cov[:, 3:, 3:] = r_w.T @ np.diag([sr ** 2, sr ** 2, sr ** 2]) @ r_w
        rep, series = run_analysis.analyse({**as_traj(t, est_p, est_r), "cov": cov}, as_traj(t, p, r), max_dt=1e-6)
        for key in ("nees_position", "nees_rotation"):
            lo, hi = rep[key]["mean_bounds_95"]
            self.assertTrue(lo * 0.9 < rep[key]["mean"] < hi * 1.1, (key, rep[key]))
            self.assertEqual(len(series[key]), len(t))


class SceneGeometryTest(unittest.TestCase):
    def test_distance_to_each_surface_type(self):
        sphere = sg.Sphere([1, 2, 3], 0.5)
        np.testing.assert_allclose(sphere.distance(np.array([[1, 2, 4.0], [1, 2, 3.2]])), [0.5, -0.3])
        cyl = sg.Cylinder([0, 0, 0], [0, 0, 2], 1.0, 2.0)
        pts = np.array([[1.5, 0, 0], [0, 0.5, 1.9], [1.0, 0, 3.0], [4.0, 0, 6.0]])
        np.testing.assert_allclose(cyl.distance(pts), [0.5, -0.5, 1.0, 5.0])
        plane = sg.Plane([0, 0, 1], [0, 0, -3], 2.0)
        pts = np.array([[0.5, 0.5, 1.2], [1.0, 0, 0.7], [5.0, 0, 1.0], [0, 5.0, 5.0]])
        np.testing.assert_allclose(plane.distance(pts), [-0.2, 0.3, 3.0, -5.0])
        scene = [sphere, plane]
        np.testing.assert_allclose(sg.distance_to_scene(np.array([[1, 2, 3.6], [0, 0, 1.05]]), scene), [0.1, 0.05])

    def test_scene_yaml_globe_info_and_map_error(self):
        name, surfaces = sg.parse_scene(
            "name: hall\nsurfaces:\n  - {type: sphere, centre: [0, 0, 0], radius: 1}\n"
            "  - {type: cylinder, centre: [3, 0, 0], axis: [0, 0, 1], radius: 0.2, half_length: 1}\n"
            "  - {type: plane, point: [0, 0, -2], normal: [0, 0, 1], half_extent: 10}\n")
        self.assertEqual(name, "hall")
        self.assertEqual([type(s).__name__ for s in surfaces], ["Sphere", "Cylinder", "Plane"])
        with self.assertRaises(ValueError):
            sg.parse_scene("surfaces:\n  - {type: cone}\n")
        with self.assertRaises(ValueError):
            sg.parse_scene("surfaces:\n  - {type: sphere, centre: [0, 0, 0]}\n")
        _, globe = sg.parse_globe_info("radius: 2.0\ncentre: [0, 0, 1]\nframe_id: world\n")
        # Points 1 cm outside the sphere, seen through a known map -> world transform.
        rng = np.random.default_rng(2)
        d = rng.normal(size=(200, 3))
        d /= np.linalg.norm(d, axis=1)[:, None]
        world = np.array([0, 0, 1.0]) + 2.01 * d
        r, t = rot_z(0.4), np.array([0.2, 0.0, -0.1])
        local = (r.T @ (world - t).T).T
        rms, med = sg.map_error(local, r, t, globe)
        self.assertAlmostEqual(rms, 0.01, places=9)
        self.assertAlmostEqual(med, 0.01, places=9)


class MapGaugeTest(unittest.TestCase):
    """run_analysis.map_gauge: the trajectory's SE(3) alignment carries the
    map only when the trajectory fixes its rotation."""

    def map_case(self, t, p, r, noise):
        """A map 0.3-0.5 m in front of the first pose, and an estimate whose
        world is turned by 0.2 rad about z and shifted, its positions noisy."""
        rng = np.random.default_rng(4)
        truth_map = p[0] + np.column_stack([rng.uniform(-0.1, 0.1, 300), rng.uniform(-0.1, 0.1, 300),
                                            rng.uniform(0.3, 0.5, 300)])
        r_w, t_w = rot_z(0.2), np.array([0.1, -0.2, 0.05])  # truth -> estimate world
        est_p = (r_w @ p.T).T + t_w + noise * rng.normal(size=p.shape)
        est_r = np.array([r_w @ x for x in r])
        est_map = (r_w @ truth_map.T).T + t_w
        se3 = tm.ate(est_p, p)
        return run_analysis.map_gauge(est_p, est_r, p, r, se3, est_map), truth_map, est_map

    def test_a_trajectory_that_barely_moves_ties_the_map_at_its_first_pose(self):
        rng = np.random.default_rng(5)
        t = np.arange(70) * 0.1
        p = 0.002 * rng.normal(size=(70, 3))  # tremor only
        r = np.array([np.eye(3)] * 70)
        (r_map, t_map, name), truth_map, est_map = self.map_case(t, p, r, noise=0.001)
        self.assertEqual(name, "anchored")
        # Exact up to the first pose's own noise (1 mm), where the free
        # alignment's rotation would move points 0.4 m away by centimetres.
        err = np.linalg.norm((r_map @ est_map.T).T + t_map - truth_map, axis=1)
        self.assertLess(np.sqrt(np.mean(err ** 2)), 0.004)

    def test_a_wide_trajectory_carries_the_map_by_its_alignment(self):
        t, p, r = circle_trajectory()
        (r_map, t_map, name), truth_map, est_map = self.map_case(t, p, r, noise=0.001)
        self.assertEqual(name, "se3")
        err = np.linalg.norm((r_map @ est_map.T).T + t_map - truth_map, axis=1)
        self.assertLess(np.sqrt(np.mean(err ** 2)), 0.001)


class FilesAndCliTest(unittest.TestCase):
    def test_asl_ground_truth_to_camera_and_tum_round_trip(self):
        with tempfile.TemporaryDirectory() as d:
            t_bs = np.eye(4)
            t_bs[:3, :3] = rot_x(np.pi / 2)
            t_bs[:3, 3] = [0.1, -0.05, 0.02]
            csv = os.path.join(d, "gt.csv")
            with open(csv, "w") as f:
                f.write("#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
                        "q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1]\r\n")
                f.write("1403636580838555648,1.0,2.0,3.0,%r,0,0,%r,0,0,0\r\n" % (np.cos(0.5), np.sin(0.5)))
            sensor = os.path.join(d, "sensor.yaml")
            with open(sensor, "w") as f:
                f.write("%YAML:1.0\nT_BS:\n  cols: 4\n  rows: 4\n  data: [" +
                        ", ".join(repr(v) for v in t_bs.reshape(-1)) + "]\n")
            gt = tio.read_trajectory(csv, tio.read_t_bs(sensor))
            self.assertAlmostEqual(gt["t"][0], 1403636580.838555648, places=6)
            r_wb = rot_z(1.0)
            np.testing.assert_allclose(gt["p"][0], [1, 2, 3] + r_wb @ t_bs[:3, 3], atol=1e-12)
            np.testing.assert_allclose(ev.quat_to_rot(gt["q"][0]), r_wb @ t_bs[:3, :3], atol=1e-12)
            np.testing.assert_allclose(tio.read_t_bs(",".join(str(v) for v in t_bs.reshape(-1))), t_bs)
            tum = os.path.join(d, "gt.tum")
            tio.write_tum(tum, gt["t"], gt["p"], gt["q"])
            back = tio.read_tum(tum)
            np.testing.assert_allclose(back["p"], gt["p"], atol=1e-9)

    def test_offline_cli_writes_report(self):
        t, p, r = circle_trajectory()
        rng = np.random.default_rng(5)
        r_w, t_w = rot_z(-0.6), np.array([3.0, 1.0, 0.0])
        noisy = p + rng.normal(scale=0.01, size=p.shape)
        est_p = (r_w @ noisy.T).T + t_w
        est_r = np.array([r_w @ x for x in r])
        with tempfile.TemporaryDirectory() as d:
            tio.write_tum(os.path.join(d, "est.txt"), t, est_p, [ev.rot_to_quat(x) for x in est_r])
            tio.write_tum(os.path.join(d, "gt.txt"), t + 0.001, p, [ev.rot_to_quat(x) for x in r])
            with open(os.path.join(d, "scene.yaml"), "w") as f:
                f.write("name: ring\nsurfaces:\n  - {type: sphere, centre: [0, 0, 0], radius: 5}\n")
            with open(os.path.join(d, "map.ply"), "w") as f:
                pts = (r_w @ np.array([[5.02, 0, 0], [0, -4.98, 0]]).T).T + t_w
                f.write("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                        "property float z\nend_header\n" + "".join("%f %f %f\n" % tuple(x) for x in pts))
            out = os.path.join(d, "out")
            rc = evaluate.main(["--estimate", os.path.join(d, "est.txt"), "--truth", os.path.join(d, "gt.txt"),
                                "--scene", os.path.join(d, "scene.yaml"), "--map", os.path.join(d, "map.ply"),
                                "--out", out])
            self.assertEqual(rc, 0)
            with open(os.path.join(out, "report.yaml")) as f:
                rep = yaml.safe_load(f)
            self.assertEqual(rep["poses_compared"], len(t))
            self.assertTrue(0.01 < rep["ate_rmse_m"] < 0.025, rep["ate_rmse_m"])
            self.assertLessEqual(rep["ate_sim3_rmse_m"], rep["ate_rmse_m"])
            self.assertAlmostEqual(rep["sim3_scale"], 1.0, delta=0.01)
            self.assertLess(rep["rotation_max_deg"], 1.0)
            self.assertIn("rpe_1s_translation_rmse_m", rep)
            self.assertAlmostEqual(rep["map_rms_to_surface_m"], 0.02, delta=0.005)
            self.assertEqual(rep["map_points"], 2)
            # Interpolation matches the truth shifted by 1 ms as well.
            rc = evaluate.main(["--estimate", os.path.join(d, "est.txt"), "--truth", os.path.join(d, "gt.txt"),
                                "--interpolate", "--max-dt", "0.1", "--out", out])
            self.assertEqual(rc, 0)
            # Too tight a tolerance matches nothing: exit 1, not a made-up number.
            self.assertEqual(evaluate.main(["--estimate", os.path.join(d, "est.txt"), "--truth",
                                            os.path.join(d, "gt.txt"), "--max-dt", "0.0001", "--out", out]), 1)

    def test_plots(self):
        reason = plots.available()
        if reason is not None:
            self.skipTest(reason)
        t, p, r = circle_trajectory(n=100)
        cov = np.repeat(np.eye(6)[None] * 1e-4, len(t), axis=0)
        _, series = run_analysis.analyse({**as_traj(t, p + 0.005, r), "cov": cov}, as_traj(t, p, r), max_dt=1e-6)
        series["surface_motion"] = {"t": t, "estimate": np.ones((len(t), 3)), "truth": np.zeros((len(t), 3))}
        with tempfile.TemporaryDirectory() as d:
            files = plots.write_plots(series, d)
            self.assertEqual(sorted(os.path.basename(f) for f in files), sorted(plots.PLOT_FILES))
            for f in files:
                with open(f, "rb") as fh:
                    self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")


class VelocityTest(unittest.TestCase):
    def test_velocity_rms_against_truth_twist(self):
        t, p, r = circle_trajectory(n=50)
        twist = np.tile([0.5, 0.0, 0.1, 0.0, 0.3, 0.0], (len(t), 1))
        est = {**as_traj(t, p, r), "twist": twist + [0.03, 0.04, 0.0, 0.0, 0.0, 0.02]}
        rep, _ = run_analysis.analyse(est, as_traj(t, p, r), max_dt=1e-6, gt_twist={"t": t, "twist": twist})
        self.assertAlmostEqual(rep["linear_velocity_rms_m_s"], 0.05, places=12)
        self.assertAlmostEqual(rep["angular_velocity_rms_rad_s"], 0.02, places=12)
        self.assertEqual(rep["velocity_samples"], len(t))


class StandstillTest(unittest.TestCase):
    """A truth that stands still with a real ground truth's jitter: 1 mm at
    20 Hz adds centimetres of path length, but its net travel stays small; the
    estimate is scored by its drift from its first pose, the NEES anchored."""

    def standing(self, drift_m, drift_rad):
        rng = np.random.default_rng(3)
        t = np.arange(100) / 20.0
        g_p = 0.4e-3 * rng.standard_normal((100, 3)).clip(-2, 2)
        g_r = np.array([np.eye(3)] * 100)
        e_p = np.outer(t / t[-1], [drift_m, 0.0, 0.0])
        e_r = np.array([rot_z(drift_rad * ti / t[-1]) for ti in t])
        est = dict(as_traj(t, e_p, e_r), cov=np.array([np.eye(6) * 1e-4] * 100))
        return run_analysis.analyse(est, as_traj(t, g_p, g_r), max_dt=0.001)

    def test_the_plotted_error_is_the_anchored_one(self):
        # A rotation drift of 0.5 deg about z plotted as such, not as what a
        # free SE(3) alignment of a standstill leaves.
        rep, series = self.standing(0.004, np.radians(0.5))
        self.assertAlmostEqual(series["rotation_error_deg"][0], 0.0, places=9)
        self.assertAlmostEqual(series["rotation_error_deg"][-1], 0.5, places=6)
        self.assertLess(series["position_error_m"][-1], 0.004 + 4 * 0.4e-3 * 2)
        self.assertIn("first pose", series["error_title"])

    def test_jitter_is_no_travel(self):
        rep = self.standing(0.004, np.radians(0.5))[0]
        self.assertGreater(rep["distance_travelled_m"], 0.05)  # the path length of the jitter
        self.assertTrue(rep["standstill"])
        self.assertLess(rep["truth_net_travel_m"], run_analysis.STANDSTILL_MAX_NET_TRAVEL_M)
        self.assertAlmostEqual(rep["standstill_rotation_drift_deg"], 0.5, places=6)
        self.assertAlmostEqual(rep["standstill_drift_m"], 0.004, places=9)
        for key in ("ate_fraction_of_distance", "rotation_rmse_deg"):
            self.assertNotIn(key, rep)
        self.assertTrue(rep["nees_anchored"])
        self.assertEqual(rep["nees_position"]["samples"], 100)

    def test_moving_truth_is_no_standstill(self):
        t, p, r = circle_trajectory(60)
        rep = run_analysis.analyse(as_traj(t, p, r), as_traj(t, p, r), max_dt=0.001)[0]
        self.assertNotIn("standstill", rep)
        self.assertIn("ate_fraction_of_distance", rep)

    def test_drift_bounds_decide_the_run(self):
        import evaluate_run
        good = dict(RunVerdictTest.GOOD, standstill=True, standstill_drift_m=0.004, standstill_rotation_drift_deg=0.5,
                    ate_fraction_of_distance=None)
        self.assertEqual(evaluate_run.failed_checks(good, RunVerdictTest.BOUNDS), {})
        for worse in ({"standstill_drift_m": 0.02}, {"standstill_rotation_drift_deg": 2.0}):
            failed = evaluate_run.failed_checks(dict(good, **worse), RunVerdictTest.BOUNDS)
            self.assertIn("standing still", failed["ate"])


class InputStallTest(unittest.TestCase):
    """input_stall: a /clock that stood still is measured, and a retry is
    granted to an attempt whose input stalled, never to one that failed with
    a real-time input."""

    def test_largest_clock_step(self):
        import input_stall
        steps = input_stall.ClockSteps()
        self.assertEqual(steps.still_for(50.0), 0.0)
        for t in [100.0 + 0.001 * i for i in range(3000)] + [106.0 + 0.001 * i for i in range(100)]:
            steps.add(t, t - 90.0)
        self.assertAlmostEqual(steps.largest, 106.0 - 102.999, places=6)
        self.assertAlmostEqual(steps.at, 102.999, places=6)
        self.assertAlmostEqual(steps.still_for(106.099 - 90.0 + 4.0), 4.0, places=6)
        steps.add(106.099, 20.0)  # a repeated reading: the clock has not moved
        self.assertAlmostEqual(steps.still_for(106.099 - 90.0 + 4.0), 4.0, places=6)

    def test_retry_only_after_a_stalled_input(self):
        import input_stall
        with tempfile.TemporaryDirectory() as d:
            argv = ["evaluate_run.py", "--gtest_output=xml:%s" % os.path.join(d, "result.xml")]
            first = input_stall.AttemptRecord(argv, run=7)
            self.assertIsNone(first.previous_failure())
            first.write(input_stall.STALL_S + 1.0, {"map_rms": "map 13 mm"})
            self.assertIsNone(input_stall.AttemptRecord(argv, run=7).previous_failure())
            first.write(0.05, {"map_rms": "map 13 mm"})
            self.assertEqual(input_stall.AttemptRecord(argv, run=7).previous_failure(), {"map_rms": "map 13 mm"})
            # Another rostest run (another parent process) starts afresh.
            self.assertIsNone(input_stall.AttemptRecord(argv, run=8).previous_failure())
            first.write(0.05, {})
            self.assertIsNone(input_stall.AttemptRecord(argv, run=7).previous_failure())


class RunVerdictTest(unittest.TestCase):
    """evaluate_run.failed_checks: a complete run passes, a partial one (the
    back end died 2 s into the 15 s bag) fails on its coverage."""
    BOUNDS = {"max_ate_fraction": 0.02, "max_position_error": None, "max_map_rms": 0.01,
              "min_pose_coverage": 0.5, "max_end_gap": 1.0}
    GOOD = {"ended": True, "odom_messages": 150, "odom_stamps_not_increasing": 0, "gt_messages": 150,
            "poses_compared": 148, "pose_coverage": 148 / 150, "odom_end_gap_s": 0.0, "nodes_not_answering": [],
            "ate_rmse_m": 0.01, "ate_max_m": 0.02, "ate_fraction_of_distance": 0.005, "map_points": 500,
            "map_rms_to_sphere_m": 0.004,
            "latency": {k: {"p50": 20.0, "p99": 40.0, "max": 50.0}
                        for k in ("image_to_landmarks_ms", "image_to_odometry_ms")}}

    def test_complete_run_passes(self):
        import evaluate_run
        self.assertEqual(evaluate_run.failed_checks(self.GOOD, self.BOUNDS), {})

    def test_truth_coverage_counts_each_frame_once(self):
        import evaluate_run
        gt = np.arange(0.0, 10.0, 0.1)
        imu_rate = np.arange(0.0, 10.0, 0.005)  # 20 estimates a frame
        self.assertAlmostEqual(evaluate_run.truth_coverage(imu_rate, gt, 0.006), 1.0)
        self.assertAlmostEqual(evaluate_run.truth_coverage(imu_rate[imu_rate < 1.99], gt, 0.006), 0.2)
        self.assertAlmostEqual(evaluate_run.truth_coverage(gt[::2] + 0.001, gt, 0.006), 0.5)
        self.assertEqual(evaluate_run.truth_coverage([], gt, 0.006), 0.0)

    def test_partial_run_fails(self):
        import evaluate_run
        partial = dict(self.GOOD, odom_messages=20, poses_compared=20, pose_coverage=20 / 150, odom_end_gap_s=13.0,
                       nodes_not_answering=["/hapi_manager"])
        self.assertEqual(sorted(evaluate_run.failed_checks(partial, self.BOUNDS)), ["coverage", "end", "nodes"])
        self.assertIn("ate", evaluate_run.failed_checks(dict(self.GOOD, ate_fraction_of_distance=0.05), self.BOUNDS))


class SurfaceMotionMetricsTest(unittest.TestCase):
    """surface_motion_metrics: the truth over an interval, px/frame to mm/s, the study's figures, the NEES."""

    def test_interval_mean_is_exact_for_a_linear_signal_and_none_outside(self):
        t = np.linspace(0.0, 1.0, 11)
        v = np.column_stack([2.0 * t + 1.0, -t])
        np.testing.assert_allclose(smm.interval_mean(t, v, 0.23, 0.57), [2.0 * 0.4 + 1.0, -0.4], atol=1e-12)
        self.assertIsNone(smm.interval_mean(t, v, -0.1, 0.5))
        self.assertIsNone(smm.interval_mean(t, v, 0.5, 1.2))

    def test_image_velocity_gives_back_the_on_surface_velocity(self):
        rng = np.random.default_rng(3)
        fx, fy, rate = 520.0, 515.0, 40.0
        for _ in range(20):
            r = np.array([rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 1.0])
            r /= np.linalg.norm(r)
            X = rng.uniform(0.2, 0.4) * r
            n = -r + rng.normal(0, 0.3, 3)
            n /= np.linalg.norm(n)
            xdot = rng.normal(0, 0.01, 3)  # m/s, any direction
            s = xdot - r * (xdot @ n) / (r @ n)
            self.assertAlmostEqual(float(s @ n), 0.0, places=12)
            iv = smm.projection_jacobian(X, fx, fy) @ xdot / rate  # px/frame
            np.testing.assert_allclose(smm.surface_velocity_from_image_velocity(iv, rate, X, n, fx, fy), 1000 * s,
                                       atol=1e-9)

    def test_truth_from_camera_motion_against_finite_differences(self):
        surfaces = [sg.Sphere([0.0, 0.0, 0.0], 0.2), sg.Plane([0.0, 0.0, 0.5], [0.0, 0.0, 1.0], 2.0)]
        R = rot_x(0.2) @ rot_z(0.3)
        p = -0.45 * R[:, 2]  # looking at the sphere's centre
        v, w = np.array([0.01, -0.02, 0.005]), np.array([0.05, 0.1, -0.2])
        ray = np.array([0.05, -0.03, 1.0])
        fx = fy = 500.0
        X, n, s, vn, iv = smm.truth_from_camera_motion(R, p, v, w, ray, surfaces, fx, fy, 40.0)
        self.assertAlmostEqual(float(np.linalg.norm(R @ X + p)), 0.2, places=9)  # on the sphere
        self.assertLess(float(n @ ray), 0.0)  # facing the camera
        self.assertAlmostEqual(float(s @ n), 0.0, places=9)
        # The material point, fixed in the world, seen from the camera moved by the twist for dt.
        dt = 1e-6
        Xw = R @ X + p
        wx = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        R2, p2 = R @ (np.eye(3) + wx * dt), p + R @ v * dt
        xdot = (R2.T @ (Xw - p2) - X) / dt
        self.assertAlmostEqual(1000.0 * float(xdot @ n), vn, places=4)
        uv = lambda Y: np.array([fx * Y[0] / Y[2], fy * Y[1] / Y[2]])  # noqa: E731
        np.testing.assert_allclose((uv(X + xdot * dt) - uv(X)) / dt / 40.0, iv, atol=1e-5)
        np.testing.assert_allclose(1000.0 * (xdot - ray / np.linalg.norm(ray) * (xdot @ n) / (ray @ n
                                   / np.linalg.norm(ray))), s, atol=1e-4)
        self.assertIsNone(smm.truth_from_camera_motion(R, p, v, w, -R.T @ R[:, 2], surfaces[:1], fx, fy, 40.0))

    def test_static_point_motion_is_the_ray_cast_truth_at_the_same_point(self):
        # The truth at a given point (a recording of unknown geometry, scored at
        # the output's own point) equals the ray-cast truth where the ray hits.
        surfaces = [sg.Sphere([0.0, 0.0, 0.0], 0.2)]
        R = rot_x(-0.1) @ rot_z(0.4)
        p = -0.5 * R[:, 2]
        v, w = np.array([-0.004, 0.012, 0.002]), np.array([0.02, -0.05, 0.1])
        ray = np.array([-0.04, 0.02, 1.0])
        X, n, s, vn, iv = smm.truth_from_camera_motion(R, p, v, w, ray, surfaces, 600.0, 610.0, 40.0)
        s2, vn2, iv2 = smm.static_point_motion(X, n, v, w, 600.0, 610.0, 40.0)
        np.testing.assert_allclose(s2, s, atol=1e-12)
        self.assertAlmostEqual(vn2, vn, places=12)
        np.testing.assert_allclose(iv2, iv, atol=1e-12)
        # A camera at rest sees a static point at rest.
        np.testing.assert_allclose(smm.static_point_motion(X, n, np.zeros(3), np.zeros(3), 600.0, 610.0, 40.0)[0],
                                   np.zeros(3), atol=0)

    def test_twist_from_poses_of_a_smooth_motion(self):
        t, p, r = circle_trajectory(n=200, rate=10.0)
        tw = smm.twist_from_poses(t, p, r)
        i = 100
        v_world = np.array([-0.6 * np.sin(0.3 * t[i]), 0.6 * np.cos(0.3 * t[i]), 0.14 * np.cos(0.7 * t[i])])
        np.testing.assert_allclose(tw[i, :3], r[i].T @ v_world, atol=2e-3)
        h = 1e-5
        wx = r[i].T @ (rot_z(0.3 * (t[i] + h)) @ rot_x(0.1 * np.sin(t[i] + h)) - r[i]) / h
        np.testing.assert_allclose(tw[i, 3:], [wx[2, 1], wx[0, 2], wx[1, 0]], atol=2e-3)

    def test_flow_figures(self):
        true = np.array([[1.0, 0.0]] * 4)
        est = true + np.array([[0.1, 0.0], [0.0, 0.1], [-0.1, 0.0], [0.0, -0.3]])
        f = smm.flow_errors(est, true, [10.0, 10.0, 1.0, 10.0])
        self.assertAlmostEqual(f["mae_px"], 0.15)
        self.assertAlmostEqual(f["mae_pct"], 15.0)
        self.assertAlmostEqual(f["median_relative_pct"], 10.0)  # the slow frame left out
        self.assertEqual(f["frames_faster_than_min"], 3)
        v = smm.velocity_errors([[3.0, 4.0, 0.0], [0.0, 0.0, 0.0]], [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
        self.assertAlmostEqual(v["rms_mm_s"], np.sqrt(12.5))

    def test_velocity_nees_has_two_degrees_of_freedom(self):
        rng = np.random.default_rng(5)
        n = np.array([0.2, -0.1, -1.0])
        n /= np.linalg.norm(n)
        B = smm.tangent_basis(n)
        L = np.array([[0.8, 0.0], [0.3, 0.5]])
        C = B @ (L @ L.T) @ B.T
        est = [B @ (L @ rng.normal(size=2)) for _ in range(4000)]
        nees = smm.velocity_nees(est, np.zeros((4000, 3)), [C] * 4000, [n] * 4000)
        self.assertAlmostEqual(float(np.mean(nees)), 2.0, delta=0.15)


if __name__ == "__main__":
    unittest.main()
