#!/usr/bin/env python3
"""Unit tests of the follow-up scan study's table and summary
(tools/eval/session_study.py) on figures as map_sessions_test.py --json
writes them: a relocalised seed, one that never relocalised, a false
relocalisation on the other skin, and a seed without figures."""
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "eval"))
import session_study as st  # noqa: E402


def seed(n, relocalised=True, other_relocalised=False, surfaces=None):
    s2 = {"relocalised": relocalised}
    if relocalised:
        s2.update({"relocalised_after_s": 0.4 * n, "position_error_median_m": 0.001 * n,
                   "position_error_max_m": 0.005 * n, "rotation_error_median_deg": 0.1 * n,
                   "rotation_error_max_deg": 0.5 * n})
    f = {"seed": n, "start_offset_m": 0.009, "session2": s2,
         "other": {"relocalised": other_relocalised, "frames_held": 36, "odometry": 0},
         "failures": [] if relocalised and not other_relocalised else ["a failure"]}
    if surfaces is not None:
        f["surfaces"] = {"point_to_plane_m": {"rms": surfaces, "p95": 2 * surfaces}, "overlap_fraction": 0.99}
    return f


class SessionStudyTest(unittest.TestCase):
    def test_row_of_a_relocalised_seed(self):
        r = st.row(seed(1, surfaces=0.001), surfaces=True)
        self.assertEqual(r, "| 1 | 9 | 0.40 | 1.0 / 5.0 | 0.100 / 0.500 | no (36 held) | 1.00 / 2.00 (99.0 %) | pass |")

    def test_row_of_failures(self):
        self.assertIn("| never | - | - |", st.row(seed(2, relocalised=False), surfaces=False))
        self.assertIn("| yes | a failure |", st.row(seed(3, other_relocalised=True), surfaces=False))
        missing = st.row({"seed": 4, "failures": ["map_sessions_test.py wrote no figures (exit 1)"]}, surfaces=True)
        self.assertIn("| never | - | - | - | - | map_sessions_test.py wrote no figures", missing)

    def test_summary_counts_every_seed(self):
        lines = st.summary([seed(1, surfaces=0.001), seed(2, relocalised=False), seed(3, other_relocalised=True),
                            seed(4, surfaces=0.003)], surfaces=True)
        self.assertEqual(lines[0], "relocalised: 3 of 4 seeds")
        self.assertIn("median 1.20 s, max 1.60 s", lines[1])
        self.assertIn("per-seed median 1.0-4.0 mm (median of medians 3.0), max 20.0 mm", lines[2])
        self.assertIn("false relocalisations on another skin: 1 of 4", lines)
        self.assertIn("surface overlay point-to-plane RMS: 1.00-3.00 mm (median 2.00) over 2 seeds", lines)


if __name__ == "__main__":
    unittest.main()
