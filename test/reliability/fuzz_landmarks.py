#!/usr/bin/python3
"""Fuzzes the ES-EKF back end with malformed hapi_msgs/StereoLandmarks.

Publishes a static scene (a patch of the globe seen by a still camera) as
valid StereoLandmarks, interleaved with malformed messages of every kind the
back end must refuse: NaN/Inf values, descriptor byte count that does not match
the landmark count, zero/absurd/changed descriptor length, foreign descriptor
type, huge landmark counts, wrong or empty frame_id, non-symmetric and
non-positive-definite covariances, duplicate ids, stamps going backwards.
Then checks, through the back end's own /diagnostics and outputs, that

  * every malformed message was rejected and counted under its reason,
  * every valid message was accepted (nothing valid was rejected),
  * the node is alive (diagnostics and odometry keep coming afterwards),
  * the published pose never jumped (the scene is static: the estimate must
    stay at the origin within a few millimetres),
  * a large backwards time jump (bag loop) resets the filter cleanly.

Run as a rostest (test/reliability/fuzz.test) or by hand against a running
back end:  rosrun hapi_slam fuzz_landmarks.py _landmarks_topic:=/stereo/landmarks
"""
import copy
import math
import random
import sys
import threading
import time
import unittest

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from hapi_msgs.msg import StereoLandmark, StereoLandmarks
from nav_msgs.msg import Odometry

DESC_LEN = 32


class Scene(object):
    """N points of a sphere (radius 0.2 m, 0.6 m in front of the camera) on
    the side facing the camera, each with a fixed random ORB-like descriptor."""

    def __init__(self, n, seed):
        rng = random.Random(seed)
        self.points, self.descs = [], []
        while len(self.points) < n:
            # Uniform on the cap facing the camera (normal . -z > 0.4).
            x, y, z = rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)
            r = math.sqrt(x * x + y * y + z * z)
            x, y, z = x / r, y / r, z / r
            if -z < 0.4:
                continue
            self.points.append((0.2 * x, 0.2 * y, 0.6 + 0.2 * z))
            self.descs.append(bytes(rng.getrandbits(8) for _ in range(DESC_LEN)))
        self.rng = random.Random(seed + 1)

    def message(self, stamp, frame):
        m = StereoLandmarks()
        m.header.stamp = stamp
        m.header.frame_id = frame
        m.descriptor_type = StereoLandmarks.DESCRIPTOR_ORB
        m.descriptor_length = DESC_LEN
        desc = bytearray()
        for i, (x, y, z) in enumerate(self.points):
            # Stereo depth noise grows with z^2; lateral noise is small.
            sxy, sz = 0.0005, 0.002 * (z / 0.6) ** 2
            l = StereoLandmark()
            l.id = i
            l.position.x = x + self.rng.gauss(0, sxy)
            l.position.y = y + self.rng.gauss(0, sxy)
            l.position.z = z + self.rng.gauss(0, sz)
            l.position_covariance = [sxy * sxy, 0, 0, 0, sxy * sxy, 0, 0, 0, sz * sz]
            l.response = 50.0 + i % 17
            l.r = l.g = l.b = 128
            m.landmarks.append(l)
            desc += self.descs[i]
        m.descriptors = bytes(desc)
        return m


def malformed(valid, last_stamp, kind):
    """A copy of `valid` broken in one way; returns (message, expected reject reason)."""
    m = copy.deepcopy(valid)
    if kind == "nan_position":
        m.landmarks[3].position.x = float("nan")
        return m, "non_finite"
    if kind == "inf_covariance":
        m.landmarks[5].position_covariance = list(m.landmarks[5].position_covariance)
        m.landmarks[5].position_covariance[4] = float("inf")
        return m, "non_finite"
    if kind == "nan_response":
        m.landmarks[0].response = float("nan")
        return m, "non_finite"
    if kind == "descriptor_bytes_short":
        m.descriptors = m.descriptors[:-1]
        return m, "descriptor_size"
    if kind == "count_mismatch":  # one landmark more than descriptors
        m.landmarks.append(copy.deepcopy(m.landmarks[0]))
        m.landmarks[-1].id = 100000
        return m, "descriptor_size"
    if kind == "descriptor_length_zero":
        m.descriptor_length = 0
        return m, "descriptor_length"
    if kind == "descriptor_length_huge":
        m.descriptor_length = 4000000000
        return m, "descriptor_length"
    if kind == "descriptor_length_changed":
        m.descriptor_length = 16
        m.descriptors = m.descriptors[:16 * len(m.landmarks)]
        return m, "descriptor_length"
    if kind == "descriptor_type":
        m.descriptor_type = StereoLandmarks.DESCRIPTOR_AKAZE
        return m, "descriptor_type"
    if kind == "huge_count":  # far more landmarks than max_measurements_per_msg
        base = m.landmarks[0]
        m.landmarks = []
        for i in range(5000):
            l = copy.copy(base)
            l.id = i
            m.landmarks.append(l)
        m.descriptors = bytes(DESC_LEN * 5000)
        return m, "too_many_measurements"
    if kind == "wrong_frame":
        m.header.frame_id = "base_link"
        return m, "frame_id"
    if kind == "empty_frame":
        m.header.frame_id = ""
        return m, "frame_id"
    if kind == "non_pd_covariance":
        m.landmarks[7].position_covariance = [-1e-6, 0, 0, 0, 1e-6, 0, 0, 0, 1e-6]
        return m, "bad_covariance"
    if kind == "non_symmetric_covariance":
        m.landmarks[8].position_covariance = [1e-6, 5e-7, 0, 0, 1e-6, 0, 0, 0, 1e-6]
        return m, "bad_covariance"
    if kind == "duplicate_id":
        m.landmarks[9].id = m.landmarks[10].id
        return m, "duplicate_id"
    if kind == "stamp_backwards":  # reordered message, well within time_jump_reset
        m.header.stamp = last_stamp - rospy.Duration(0.05)
        return m, "stamp_backwards"
    if kind == "stamp_repeated":
        m.header.stamp = last_stamp
        return m, "stamp_backwards"
    raise ValueError(kind)


KINDS = ["nan_position", "inf_covariance", "nan_response", "descriptor_bytes_short", "count_mismatch",
         "descriptor_length_zero", "descriptor_length_huge", "descriptor_length_changed", "descriptor_type",
         "huge_count", "wrong_frame", "empty_frame", "non_pd_covariance", "non_symmetric_covariance",
         "duplicate_id", "stamp_backwards", "stamp_repeated"]


class Monitor(object):
    def __init__(self, odom_topic, diag_match):
        self.lock = threading.Lock()
        self.odom = []       # (wall time, stamp, x, y, z)
        self.diag = None     # latest key/value dict of the back end's status
        self.diag_count = 0
        self.diag_match = diag_match
        rospy.Subscriber(odom_topic, Odometry, self.on_odom, queue_size=200)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=50)

    def on_odom(self, msg):
        p = msg.pose.pose.position
        with self.lock:
            self.odom.append((time.time(), msg.header.stamp.to_sec(), p.x, p.y, p.z))

    def on_diag(self, msg):
        for st in msg.status:
            kv = {v.key: v.value for v in st.values}
            if self.diag_match in st.name and "rejected_total" in kv:
                with self.lock:
                    self.diag = kv
                    self.diag_count += 1

    def snapshot(self):
        with self.lock:
            return list(self.odom), (dict(self.diag) if self.diag else None), self.diag_count


def wait_for(cond, timeout, what):
    end = time.time() + timeout
    while time.time() < end and not rospy.is_shutdown():
        if cond():
            return True
        time.sleep(0.05)
    raise AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))


class FuzzLandmarks(unittest.TestCase):
    def test_fuzz(self):
        topic = rospy.get_param("~landmarks_topic", "/stereo/landmarks")
        odom_topic = rospy.get_param("~odom_topic", "/eskf/odom")
        diag_match = rospy.get_param("~diagnostics_name", "eskf")
        frame = rospy.get_param("~frame_id", "stereo_left_optical_frame")
        rate = float(rospy.get_param("~rate", 10.0))
        rounds = int(rospy.get_param("~rounds", 2))   # each round sends every malformed kind once
        max_drift = float(rospy.get_param("~max_drift", 0.01))      # [m] from the origin
        max_step = float(rospy.get_param("~max_step", 0.005))       # [m] between consecutive odometry
        seed = int(rospy.get_param("~seed", 7))

        mon = Monitor(odom_topic, diag_match)
        pub = rospy.Publisher(topic, StereoLandmarks, queue_size=100)
        wait_for(lambda: pub.get_num_connections() > 0, 30.0, "the back end to subscribe to " + topic)
        wait_for(lambda: mon.snapshot()[1] is not None, 30.0, "the back end's diagnostics")
        base = mon.snapshot()[1]
        base_rejected = int(base["rejected_total"])
        base_accepted = int(base["frames_accepted"])
        base_resets = int(base.get("time_jumps", 0))

        scene = Scene(120, seed)
        stamp = rospy.Time(1000.0)  # message time, independent of the clock
        period = rospy.Duration(1.0 / rate)
        sleep = 1.0 / rate
        n_valid, expected = 0, {}
        schedule = []
        for _ in range(rounds):
            kinds = list(KINDS)
            random.Random(seed + len(schedule)).shuffle(kinds)
            schedule += kinds

        def send_valid(n):
            nonlocal stamp, n_valid
            for _ in range(n):
                stamp = stamp + period
                pub.publish(scene.message(stamp, frame))
                n_valid += 1
                time.sleep(sleep)

        send_valid(20)  # warm-up: the filter initialises and settles
        wait_for(lambda: len(mon.snapshot()[0]) >= 5, 30.0, "odometry from the back end")
        for kind in schedule:
            valid = scene.message(stamp + period, frame)
            bad, reason = malformed(valid, stamp, kind)
            pub.publish(bad)
            expected[reason] = expected.get(reason, 0) + 1
            time.sleep(sleep / 2)
            send_valid(2)
        send_valid(20)
        n_bad = sum(expected.values())
        rospy.loginfo("fuzz: sent %d valid and %d malformed messages", n_valid, n_bad)

        # Diagnostics are periodic: wait until they show everything we sent.
        def counted():
            d = mon.snapshot()[1]
            return int(d["frames_received"]) - int(base["frames_received"]) >= n_valid + n_bad
        wait_for(counted, 20.0, "diagnostics counting all %d messages" % (n_valid + n_bad))
        odom, diag, _ = mon.snapshot()
        for reason, n in sorted(expected.items()):
            got = int(diag["rejected_" + reason]) - int(base.get("rejected_" + reason, 0))
            self.assertEqual(got, n, "rejected_%s: %d counted, %d sent" % (reason, got, n))
        self.assertEqual(int(diag["rejected_total"]) - base_rejected, n_bad)
        self.assertEqual(int(diag["frames_accepted"]) - base_accepted, n_valid, "a valid message was rejected")
        self.assertEqual(int(diag["filter_errors"]), 0, diag.get("last_filter_error", ""))

        # The pose never jumped and stayed at the (static) origin.
        self.assertGreater(len(odom), 10)
        worst_drift = max(math.sqrt(x * x + y * y + z * z) for _, _, x, y, z in odom)
        worst_step = max(math.sqrt((a[2] - b[2]) ** 2 + (a[3] - b[3]) ** 2 + (a[4] - b[4]) ** 2)
                         for a, b in zip(odom, odom[1:]))
        rospy.loginfo("fuzz: %d odometry messages, max |p| %.4f m, max step %.4f m", len(odom), worst_drift,
                      worst_step)
        self.assertLess(worst_drift, max_drift)
        self.assertLess(worst_step, max_step)
        for _, t, _, _, _ in odom:
            self.assertTrue(math.isfinite(t))

        # Alive: a bag loop (stamp far in the past) resets the filter, which
        # then runs on the new timeline.
        n_odom = len(odom)
        stamp = rospy.Time(10.0)
        send_valid(20)
        wait_for(lambda: len(mon.snapshot()[0]) > n_odom + 5, 20.0, "odometry after the time jump")
        wait_for(lambda: int(mon.snapshot()[1]["time_jumps"]) >= base_resets + 1, 20.0,
                 "time_jumps to count the backwards jump")
        odom, diag, _ = mon.snapshot()
        after = [o for o in odom[n_odom:] if o[1] < 100.0]
        self.assertGreater(len(after), 5, "no odometry on the new timeline")
        self.assertLess(max(math.sqrt(x * x + y * y + z * z) for _, _, x, y, z in after), max_drift)
        self.assertEqual(int(diag["time_jumps"]) - base_resets, 1)


if __name__ == "__main__":
    import rostest
    rospy.init_node("fuzz_landmarks")
    rostest.rosrun("hapi_slam", "fuzz_landmarks", FuzzLandmarks, sys.argv)
