#!/usr/bin/python3
"""rostest node: the self-checks on /diagnostics (docs/CALIBRATION.md
"Self-checks") while a simulated bag with one thing broken plays.

Parameters (~):
  expect: list of "STATUS|KEY|LEVEL|TEXT": a DiagnosticStatus whose name
          ends with STATUS must, at least once, have the value of KEY at
          level >= LEVEL (1 WARN, 2 ERROR; the value starts with its level's
          name) and containing TEXT.
  expect_quiet: list of STATUS: these statuses never go above OK in the
          reports that judged frames, and at least ~min_reports of them
          came (the unbroken recording: no false alarm; default 4, the 4 s
          bag).
  timeout: wall seconds to wait (default 60).
"""
import sys
import time
import unittest

import rospy
from diagnostic_msgs.msg import DiagnosticArray


class SelfCheckTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("hapi_self_check_test")
        cls.timeout = float(rospy.get_param("~timeout", 60.0))
        cls.expect = [e.split("|") for e in rospy.get_param("~expect", [])]
        cls.quiet = list(rospy.get_param("~expect_quiet", []))
        cls.min_reports = int(rospy.get_param("~min_reports", 4))
        cls.statuses = []  # (name, level, message, {key: value})
        rospy.Subscriber("/diagnostics", DiagnosticArray, cls.on_diagnostics, queue_size=100)

    @classmethod
    def on_diagnostics(cls, msg):
        for s in msg.status:
            cls.statuses.append((s.name, s.level, s.message, {kv.key: kv.value for kv in s.values}))

    LEVELS = {"WARN": 1, "ERROR": 2}

    @staticmethod
    def judged(status):
        """A report that judged frames (not one before the bag or after it)."""
        values = status[3]
        return values.get("frames judged", "1") != "0" and values.get("landmarks per frame median") != "nan"

    def matching(self, status, key, level, text):
        def check_level(value):
            return self.LEVELS.get(value.split(":", 1)[0], 0)
        return [s for s in self.statuses if s[0].endswith(status) and s[1] >= level
                and check_level(s[3].get(key, "")) >= level and text in s[3].get(key, "")]

    def test_self_checks(self):
        end = time.time() + self.timeout
        if self.expect:
            while time.time() < end and not rospy.is_shutdown():
                if all(self.matching(st, key, int(lvl), text) for st, key, lvl, text in self.expect):
                    break
                time.sleep(0.2)
            for st, key, lvl, text in self.expect:
                seen = [(s[1], s[3]) for s in self.statuses if s[0].endswith(st)][-3:]
                self.assertTrue(self.matching(st, key, int(lvl), text),
                                "no '%s' %s >= %s containing '%s'; last seen: %s" % (st, key, lvl, text, seen))
                print("self-check seen: %s" % (self.matching(st, key, int(lvl), text)[0][3],))
        for st in self.quiet:
            while time.time() < end and not rospy.is_shutdown():
                judged = [s for s in self.statuses if s[0].endswith(st) and self.judged(s)]
                if len(judged) >= self.min_reports:
                    break
                time.sleep(0.2)
            judged = [s for s in self.statuses if s[0].endswith(st) and self.judged(s)]
            self.assertGreaterEqual(len(judged), self.min_reports, "too few '%s' reports" % st)
            print("%s, last report: %s" % (st, judged[-1][3] if judged else None))
            alarms = [(s[1], s[2]) for s in judged if s[1] > 0]
            self.assertEqual(alarms, [], "false alarm of '%s'" % st)


if __name__ == "__main__":
    import rostest
    rostest.rosrun("hapi_slam", "self_check_test", SelfCheckTest, sys.argv)
