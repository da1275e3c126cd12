"""Was a replay's input real time? The bag player's /clock, watched.

`rosbag play --clock` publishes /clock at --hz while it waits for the next
message. When the player falls behind the wall clock (its process starved or
frozen by the machine running the test), it publishes the messages it owes
back to back and no /clock until it has caught up; the clock then resumes at
the right bag time. A forward jump between two consecutive /clock messages is
therefore the time the input was not real time, whatever the system under
test did: its frames arrived late and in a burst, and a live system drops
most of them (newest wins).

ClockWatch records the largest such jump. A live test that failed with an
input stall of at least STALL_S is retried once (AttemptRecord); a test that
failed with a real-time input is not.
"""
import json
import os
import threading
import time

import rospy
from rosgraph_msgs.msg import Clock

# [s] a /clock jump this long is a stalled input: the replays publish /clock
# at 1 kHz (launch/replay.launch clock_hz), and a loaded 2-core machine
# delays it by up to about 1.3 s without the tests' figures changing.
STALL_S = 2.0


class ClockSteps(object):
    """The largest forward step of a sequence of clock readings [s], and how
    long (wall time) the clock has stood still since it last moved."""

    def __init__(self):
        self._last = None
        self._last_wall = None  # wall time of the last reading that moved the clock
        self.largest = 0.0
        self.at = None  # the reading where the largest step began

    def add(self, t, wall):
        if self._last is not None and t - self._last > self.largest:
            self.largest = t - self._last
            self.at = self._last
        if t != self._last:
            self._last, self._last_wall = t, wall

    def still_for(self, wall):
        """Wall seconds since the clock last moved (0 before the first reading)."""
        return 0.0 if self._last_wall is None else wall - self._last_wall

    def last(self):
        return self._last


class ClockWatch(object):
    """ClockSteps of /clock, as it arrives. A stall still in progress when the
    run is judged (the clock standing still while the player has not
    finished the bag) counts as a step of its length."""

    def __init__(self, topic="/clock"):
        self._lock = threading.Lock()
        self._steps = ClockSteps()
        rospy.Subscriber(topic, Clock, self._on_clock, queue_size=10000, tcp_nodelay=True)

    def _on_clock(self, msg):
        with self._lock:
            self._steps.add(msg.clock.to_sec(), time.time())

    def largest_step(self, player_running):
        """(largest /clock step [s], bag time where it began or None).
        player_running: the player has not finished the bag (its node still
        answers), so a clock standing still now is a stall too."""
        with self._lock:
            largest, at = self._steps.largest, self._steps.at
            still = self._steps.still_for(time.time()) if player_running else 0.0
            if still > largest:
                largest, at = still, self._steps.last()
            return largest, at


def results_file(argv):
    """The rostest results file of this test node (--gtest_output=xml:PATH), or None."""
    for a in argv:
        if a.startswith("--gtest_output=xml:"):
            return a[len("--gtest_output=xml:"):]
    return None


class AttemptRecord(object):
    """What the previous attempt of this rostest saw, next to its results file.

    rostest's `retry` reruns a failed test whatever the cause. This record
    keeps the retry for a stalled input: the attempt writes whether its input
    stalled and which checks failed; the next attempt of the same rostest run
    (same parent process) that finds a failure with a real-time input reports
    that failure again instead of scoring a new run.
    """

    def __init__(self, argv, run=None):
        path = results_file(argv)
        self.path = path + ".attempt.json" if path else None
        self.run = os.getppid() if run is None else run  # the rostest process: the same for its retries

    def previous_failure(self):
        """The failed checks of this run's previous attempt when its input was
        real time, else None."""
        if not self.path:
            return None
        try:
            with open(self.path) as f:
                rec = json.load(f)
        except (OSError, ValueError):
            return None
        if rec.get("run") != self.run or rec.get("stalled") or not rec.get("failed"):
            return None
        return rec["failed"]

    def write(self, stall_s, failed):
        if not self.path:
            return
        with open(self.path, "w") as f:
            json.dump({"run": self.run, "stall_s": stall_s, "stalled": stall_s >= STALL_S, "failed": failed}, f)
