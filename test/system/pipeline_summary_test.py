#!/usr/bin/python3
"""Unit test of tools/eval/pipeline_summary.py, the printout of the main job.

A report YAML and a /diagnostics bag are written here with known values, so
the test checks what the summary computes (frame-weighted stage means, the
idle windows after the bag not counted, frame accounting) and its exit status:
0 in bounds, 2 a metric out of bounds, 1 something missing (never guessed).
"""
import os
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospy
import yaml
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "tools", "eval", "pipeline_summary.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
import pipeline_summary  # noqa: E402

GOOD = {
    "odom_messages": 150, "odom_rate_sim_hz": 10.0, "odom_rate_wall_hz": 9.9, "gt_messages": 150,
    "poses_compared": 150, "ate_rmse_m": 0.01, "ate_max_m": 0.03, "distance_travelled_m": 1.0,
    "ate_fraction_of_distance": 0.01, "map_points": 500, "map_rms_to_sphere_m": 0.004,
    "map_median_abs_to_sphere_m": 0.003,
    "latency": {"image_to_landmarks_ms": {"p50": 21.0, "p99": 30.5, "max": 41.0},
                "image_to_odometry_ms": {"p50": 33.0, "p99": 48.25, "max": 60.0}},
}


def status(name, **values):
    return DiagnosticStatus(name=name, values=[KeyValue(key=k, value=str(v)) for k, v in values.items()])


def write_diag_bag(path):
    """Three windows of the filter: 10 frames at 20 ms, 30 frames at 40 ms,
    then an idle window (no new frames, the nodelet reports 0 ms)."""
    windows = [(10, 20.0, 0), (40, 40.0, 2), (40, 0.0, 2)]
    with rosbag.Bag(path, "w") as bag:
        # A nodelet's first status may carry no values yet: it must not make
        # the counter unusable (then every window would weigh the same).
        bag.write("/diagnostics", DiagnosticArray(status=[status("eskf: filter")]), rospy.Time(99))
        for i, (processed, t_ms, dropped) in enumerate(windows):
            arr = DiagnosticArray()
            arr.status.append(status("eskf: filter", frames_processed=processed, frames_received=processed + dropped,
                                     frames_dropped=dropped, t_update_ms=t_ms, latency_p50_ms=30.0 + i))
            arr.status.append(status("unrelated: other node", frames_processed=99, t_x_ms=1000.0))
            bag.write("/diagnostics", arr, rospy.Time(100 + i))


class PipelineSummaryTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.diag = os.path.join(self.tmp.name, "diagnostics.bag")
        write_diag_bag(self.diag)

    def tearDown(self):
        self.tmp.cleanup()

    def run_summary(self, report, *extra):
        path = os.path.join(self.tmp.name, "report.yaml")
        with open(path, "w") as f:
            yaml.safe_dump(report, f)
        p = subprocess.run([sys.executable, SCRIPT, path, *extra], capture_output=True, text=True)
        return p.returncode, p.stdout

    def test_stage_means_weighted_by_frames(self):
        t = pipeline_summary.stage_timings(pipeline_summary.read_diagnostics(self.diag))
        self.assertEqual(set(t), {"eskf: filter"})  # other nodes' statuses are not ours
        f = t["eskf: filter"]
        self.assertEqual(f["counter"], "frames_processed")
        self.assertEqual(f["frames"], 40)
        mean, worst = f["stages"]["t_update_ms"]
        self.assertAlmostEqual(mean, (10 * 20.0 + 30 * 40.0) / 40)  # the idle window does not count
        self.assertAlmostEqual(worst, 40.0)
        # Run-wide percentiles are not stage means.
        self.assertNotIn("latency_p50_ms", f["stages"])
        self.assertEqual(f["account"]["frames_dropped"], "2")

    def test_pass(self):
        rc, out = self.run_summary(GOOD, self.diag)
        self.assertEqual(rc, 0, out)
        self.assertIn("= 1.00 %", out)
        self.assertIn("t_update_ms", out)
        self.assertIn("frames_dropped 2", out)
        self.assertIn("latency to odometry  : p50 33.0 ms, p99 48.2 ms", out)

    def test_metric_out_of_bounds(self):
        rc, out = self.run_summary(dict(GOOD, ate_fraction_of_distance=0.03), self.diag)
        self.assertEqual(rc, 2, out)
        self.assertIn("FAILED: ATE", out)
        rc, out = self.run_summary(dict(GOOD, map_rms_to_sphere_m=0.02), self.diag)
        self.assertEqual(rc, 2, out)
        self.assertIn("FAILED: map error", out)

    def test_missing_parts(self):
        rc, out = self.run_summary(GOOD)  # no diagnostics: timing missing
        self.assertEqual(rc, 1, out)
        self.assertIn("MISSING: per-stage timing", out)
        no_latency = {k: v for k, v in GOOD.items() if k != "latency"}
        rc, out = self.run_summary(no_latency, self.diag)
        self.assertEqual(rc, 1, out)
        self.assertIn("MISSING: latency", out)
        no_ate = {k: v for k, v in GOOD.items() if not k.startswith("ate_")}
        rc, out = self.run_summary(no_ate, self.diag)
        self.assertEqual(rc, 1, out)
        self.assertIn("MISSING: ATE", out)
        no_map = {k: v for k, v in GOOD.items() if not k.startswith("map_rms")}
        rc, out = self.run_summary(dict(no_map, ate_fraction_of_distance=0.5, map_points=0), self.diag)
        self.assertEqual(rc, 1, out)  # missing wins over failed
        self.assertIn("MISSING: map error (no map received)", out)

    def test_real_recording_without_geometry(self):
        # A data set with no known scene: the map error is not scored with
        # --map-error if-known, still missing without it.
        no_map = {k: v for k, v in GOOD.items() if not k.startswith("map_rms") and "sphere" not in k}
        rc, out = self.run_summary(no_map, self.diag, "--map-error", "if-known")
        self.assertEqual(rc, 0, out)
        self.assertIn("scene geometry unknown", out)
        rc, out = self.run_summary(no_map, self.diag)
        self.assertEqual(rc, 1, out)
        # An empty map is not a recording without geometry.
        rc, out = self.run_summary(dict(no_map, map_points=0), self.diag, "--map-error", "if-known")
        self.assertEqual(rc, 1, out)
        self.assertIn("MISSING: map error (no map received)", out)
        # The further metrics are printed when the report has them.
        rich = dict(GOOD, ate_sim3_rmse_m=0.009, sim3_scale=1.01, rotation_rmse_deg=0.5, rotation_max_deg=1.0,
                    nees_position={"mean": 3.1, "mean_bounds_95": [2.8, 3.2], "fraction_in_95_band": 0.94,
                                   "samples": 150})
        rc, out = self.run_summary(rich, self.diag)
        self.assertEqual(rc, 0, out)
        self.assertIn("scale 1.0100", out)
        self.assertIn("position NEES", out)

    def test_surface_printed(self):
        surface = {"mesh": "mesh.ply", "vertices": 1200, "faces": 2300, "keyframes_fused": 14, "integration": "cpu",
                   "depth_keyframes_published": 15,
                   "imaging_frames_projected": 30, "rms_mm": 0.412, "p95_mm": 0.9, "completeness_pct": 91.25,
                   "seen_points": 800, "registration_rms_mm": 0.55, "registration_p95_mm": 1.1, "edge_pieces": 12,
                   "picture": "mesh.png"}
        rc, out = self.run_summary(dict(GOOD, surface=surface), self.diag)
        self.assertEqual(rc, 0, out)
        self.assertIn("1200 vertices, 2300 triangles, 14 keyframes fused of 15 depth keyframes", out)
        self.assertIn("RMS 0.412 mm, p95 0.900 mm, completeness 91.2 %", out)
        self.assertIn("registration RMS 0.550 mm", out)
        self.assertIn("surface picture       : mesh.png", out)
        # Without a perfusion pattern (the globe) no registration is printed; a failed save is said.
        rc, out = self.run_summary(dict(GOOD, surface=dict(surface, edge_pieces=0)), self.diag)
        self.assertNotIn("registration", out)
        rc, out = self.run_summary(dict(GOOD, surface={"error": "no service", "keyframes_fused": 0}), self.diag)
        self.assertIn("surface               : not saved (no service; 0 keyframes fused)", out)

    def test_standstill_scored_by_drift(self):
        # A device standing still: ATE % of the jitter's path means nothing,
        # the drift from the first pose decides (1 cm, 1 deg by default).
        still = dict({k: v for k, v in GOOD.items() if k != "ate_fraction_of_distance"}, standstill=True,
                     ate_rmse_m=0.0016, ate_max_m=0.004, distance_travelled_m=0.017, truth_net_travel_m=0.0023,
                     standstill_drift_m=0.0043, standstill_rotation_drift_deg=0.99, nees_anchored=True,
                     nees_position={"mean": 1.4, "mean_bounds_95": [2.2, 3.9], "fraction_in_95_band": 0.9,
                                    "samples": 47})
        rc, out = self.run_summary(still, self.diag, "--stereo-rate-hz", "10.0")
        self.assertEqual(rc, 0, out)
        self.assertIn("drifts 4.30 mm, 0.990 deg from its first pose (bounds 10 mm, 1 deg: PASS)", out)
        self.assertNotIn("% (bound", out)
        self.assertIn("anchored at the first pose", out)
        self.assertIn("stereo frames         : 10.00 Hz in the bag; eskf dropped 2 (40 processed)", out)
        for worse in ({"standstill_drift_m": 0.011}, {"standstill_rotation_drift_deg": 1.5}):
            rc, out = self.run_summary(dict(still, **worse), self.diag)
            self.assertEqual(rc, 2, out)
            self.assertIn("FAILED: drift standing still", out)
        rc, out = self.run_summary(dict(still, standstill_drift_m=0.011), self.diag, "--max-drift", "0.02")
        self.assertEqual(rc, 0, out)


if __name__ == "__main__":
    unittest.main()
