#!/usr/bin/python3
"""The reliability verdicts fail what they are there to catch (no ROS):

  * two_hosts_verdict.motion_error: a track that follows the truth scores
    near 0; a frozen pose and dead-reckoning at 10x the speed score far
    beyond the --max-motion-error bound;
  * soak_verdict.py: a 30 s odometry silence on the 10 Hz stream fails,
    loop resets of a few tenths of a second do not;
  * outage_verdict.player_lags: a player stalled for 3 s is measured as 3 s
    late until it has caught up, an on-time one as 0.
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import outage_verdict  # noqa: E402
import two_hosts_verdict  # noqa: E402

BOUND = 0.25  # two_hosts_verdict.py's --max-motion-error default


def globe_track(seconds=10.0, rate=10.0):
    """(truth {stamp: xyz} on the 0.1 s grid, odometry [(wall, stamp, x, y, z)] on it)."""
    t = np.arange(0.0, seconds, 1.0 / rate)
    p = np.stack([0.5 * np.cos(0.2 * t), 0.5 * np.sin(0.2 * t), 0.02 * t], axis=1)  # 0.1 m/s, as the globe bag
    gt = {round(s, 1): tuple(x) for s, x in zip(t, p)}
    return t, p, gt


def odom(t, p):
    return [(100.0 + s, s, *x) for s, x in zip(t, p)]


class PlayerLag(unittest.TestCase):
    def test_stalled_player_is_measured(self):
        # 10 Hz truth poses on time for 20 s, then sent 3 s late from bag time 20 s on.
        inputs = [[100.0 + 0.1 * k, 0.1 * k] for k in range(200)]
        inputs += [[103.0 + 0.1 * k, 0.1 * k] for k in range(200, 300)]
        walls = [105.0, 115.0, 125.0, 129.0]
        lags = outage_verdict.player_lags(inputs, walls, before_wall=110.0)
        self.assertAlmostEqual(lags[0], 0.0, places=6)
        self.assertAlmostEqual(lags[1], 0.0, places=6)
        self.assertAlmostEqual(lags[2], 3.0, places=6)
        self.assertAlmostEqual(lags[3], 3.0, places=6)
        self.assertEqual(outage_verdict.player_lags([], walls, before_wall=110.0), [0.0] * 4)


class MotionError(unittest.TestCase):
    def test_tracking_passes(self):
        t, p, gt = globe_track()
        rng = np.random.default_rng(1)
        e = two_hosts_verdict.motion_error(odom(t, p + rng.normal(0, 0.002, p.shape)), gt)
        self.assertLess(e, BOUND)

    def test_frozen_pose_fails(self):
        t, p, gt = globe_track()
        e = two_hosts_verdict.motion_error(odom(t, np.repeat(p[:1], len(p), axis=0)), gt)
        self.assertAlmostEqual(e, 1.0, places=6)
        self.assertGreater(e, BOUND)

    def test_ten_times_the_speed_fails(self):
        t, p, gt = globe_track()
        fast = p[0] + 10.0 * np.cumsum(np.vstack([np.zeros(3), np.diff(p, axis=0)]), axis=0)
        self.assertGreater(two_hosts_verdict.motion_error(odom(t, fast), gt), BOUND)

    def test_bag_loop_starts_a_new_timeline(self):
        t, p, gt = globe_track()
        both = odom(t, p) + odom(t, p)  # stamps go back at the loop
        self.assertLess(two_hosts_verdict.motion_error(both, gt), 1e-9)

    def test_no_truth_is_nan(self):
        t, p, _ = globe_track()
        self.assertTrue(math.isnan(two_hosts_verdict.motion_error(odom(t, p), {})))


class SoakVerdict(unittest.TestCase):
    def run_verdict(self, odom_wall):
        gaps = np.diff(odom_wall) if len(odom_wall) > 1 else [0.0]
        with tempfile.TemporaryDirectory() as out:
            with open(out + "/samples.csv", "w") as f:
                f.write("t_s,rss_mib,threads\n")
                for k in range(0, 61, 10):
                    f.write("%d,%.1f,15\n" % (k, 100.0))
            probe = {"odom": [[w] for w in odom_wall], "odom_count": len(odom_wall), "odom_rate_hz": 10.0,
                     "max_gap_s": float(np.max(gaps)), "diagnostics": {}}
            with open(out + "/probe.json", "w") as f:
                json.dump(probe, f)
            r = subprocess.run([sys.executable, HERE + "/soak_verdict.py", "--out", out, "--warmup", "10"],
                               capture_output=True, text=True)
        return r.returncode, r.stdout

    def test_steady_stream_with_loop_resets_passes(self):
        wall = list(np.arange(0.0, 60.0, 0.1))
        del wall[200:204]  # a 0.5 s loop reset
        rc, out = self.run_verdict(wall)
        self.assertEqual(rc, 0, out)

    def test_long_silence_fails(self):
        wall = [w for w in np.arange(0.0, 60.0, 0.1) if not 20.0 < w < 49.0]  # 29 s without odometry
        rc, out = self.run_verdict(wall)
        self.assertEqual(rc, 1, out)
        self.assertIn("VERDICT: FAIL", out)


if __name__ == "__main__":
    unittest.main()
