#!/usr/bin/env python3
"""rostest node (surface_nodelet.test): feeds SurfaceNodelet the depth of a
plane at 25 cm and mono8 imaging frames of one value, then bad images, and
checks ~mesh, ~save_surface and /diagnostics. The marker is read through
the definition its publisher sends (Debian ships no Python
visualization_msgs)."""
import os
import struct
import tempfile
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from genpy.dynamic import generate_dynamic
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import TransformStamped
from hapi_msgs.srv import SaveSurface
from sensor_msgs.msg import CameraInfo, Image

W, H, F = 160, 120, 150.0
DEPTH = 0.25


def info(frame):
    m = CameraInfo()
    m.header.frame_id = frame
    m.width, m.height = W, H
    m.K = [F, 0, (W - 1) / 2.0, 0, F, (H - 1) / 2.0, 0, 0, 1]
    m.P = [F, 0, (W - 1) / 2.0, 0, 0, F, (H - 1) / 2.0, 0, 0, 0, 1, 0]
    return m


def image(stamp, frame, pixels, encoding):
    m = Image()
    m.header.stamp, m.header.frame_id = stamp, frame
    m.height, m.width = pixels.shape[:2]
    m.encoding = encoding
    m.step = m.width * pixels.dtype.itemsize
    m.data = pixels.tobytes()
    return m


class SurfaceNodeletTest(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.marker = None
        self.status = {}
        self.marker_class = None
        self.sub_marker = rospy.Subscriber("/surface/mesh", rospy.AnyMsg, self.on_marker)
        self.sub_diag = rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag)
        self.tf = tf2_ros.StaticTransformBroadcaster()
        transforms = []
        for child in ("stereo_left_optical_frame", "imaging_optical_frame"):
            t = TransformStamped()
            t.header.stamp = rospy.Time.now()
            t.header.frame_id, t.child_frame_id = "map", child
            t.transform.rotation.w = 1.0
            transforms.append(t)
        self.tf.sendTransform(transforms)
        self.depth_pub = rospy.Publisher("/depth", Image, queue_size=10)
        self.depth_info_pub = rospy.Publisher("/depth_camera_info", CameraInfo, queue_size=2, latch=True)
        self.imaging_pub = rospy.Publisher("/imaging/image", Image, queue_size=10)
        self.imaging_info_pub = rospy.Publisher("/imaging/camera_info", CameraInfo, queue_size=2, latch=True)

    def on_marker(self, raw):
        header = raw._connection_header
        if self.marker_class is None:
            self.marker_class = generate_dynamic(header["type"], header["message_definition"])[header["type"]]
        m = self.marker_class()
        m.deserialize(raw._buff)
        with self.lock:
            self.marker = m

    def on_diag(self, msg):
        with self.lock:
            for s in msg.status:
                self.status[s.name.lstrip("/")] = s

    def counter(self, node, key):
        with self.lock:
            s = self.status.get(node + ": surface")
            if s is None:
                return 0
            for kv in s.values:
                if kv.key == key:
                    return int(kv.value)
        return 0

    def wait_for(self, what, predicate, timeout=30.0):
        end = time.time() + timeout
        while time.time() < end and not rospy.is_shutdown():
            if predicate():
                return
            time.sleep(0.05)
        self.fail("timed out waiting for " + what)

    def test_surface(self):
        self.depth_info_pub.publish(info("stereo_left_optical_frame"))
        self.imaging_info_pub.publish(info("imaging_optical_frame"))
        depth = np.full((H, W), DEPTH, np.float32)
        depth[10, 10] = np.nan
        grey = np.full((H, W), 100, np.uint8)
        self.wait_for("subscribers", lambda: self.depth_pub.get_num_connections() > 0
                      and self.imaging_pub.get_num_connections() > 0)
        t0 = rospy.Time.now()
        self.depth_pub.publish(image(t0, "stereo_left_optical_frame", depth, "32FC1"))
        self.wait_for("a keyframe", lambda: self.counter("surface", "keyframes") >= 1)
        for k in range(3):
            self.imaging_pub.publish(image(t0 + rospy.Duration(0.1 * (k + 1)), "imaging_optical_frame", grey, "mono8"))
        self.wait_for("a projected imaging frame", lambda: self.counter("surface", "imaging projected") >= 1)

        # The mesh: the plane at 25 cm, coloured (not the grey of "no value").
        def coloured_mesh():
            with self.lock:
                m = self.marker
            if m is None or len(m.points) < 300:
                return False
            return any(abs(c.r - c.g) > 0.05 or abs(c.g - c.b) > 0.05 for c in m.colors[:300])
        self.wait_for("a coloured mesh", coloured_mesh)
        with self.lock:
            m = self.marker
        self.assertEqual(m.type, m.TRIANGLE_LIST)
        self.assertEqual(m.header.frame_id, "map")
        self.assertEqual(len(m.points) % 3, 0)
        self.assertEqual(len(m.points), len(m.colors))
        zs = np.array([p.z for p in m.points])
        self.assertLess(np.abs(zs - DEPTH).max(), 0.001)

        # ~save_surface: a binary PLY with the mesh's faces; a bad path fails.
        rospy.wait_for_service("/surface/save_surface", 10)
        save = rospy.ServiceProxy("/surface/save_surface", SaveSurface)
        path = os.path.join(tempfile.mkdtemp(), "skin.ply")
        r = save(path)
        self.assertTrue(r.success, r.message)
        self.assertGreater(r.faces, 100)
        with open(path, "rb") as f:
            head = f.read(400)
        self.assertTrue(head.startswith(b"ply\nformat binary_little_endian 1.0\n"))
        self.assertIn(b"element face %d\n" % r.faces, head)
        self.assertIn(b"property float value\n", head)
        bad = save("/nonexistent-folder/skin.ply")
        self.assertFalse(bad.success)
        # A path ending in .obj: OBJ with texture coordinates, its MTL and the
        # PNG texture atlas next to it.
        obj = os.path.join(tempfile.mkdtemp(), "skin.obj")
        r = save(obj)
        self.assertTrue(r.success, r.message)
        with open(obj) as f:
            lines = f.read().splitlines()
        self.assertIn("mtllib skin.mtl", lines)
        self.assertEqual(sum(1 for l in lines if l.startswith("f ")), r.faces)
        self.assertEqual(sum(1 for l in lines if l.startswith("vt ")), 3 * r.faces)
        with open(obj[:-4] + ".mtl") as f:
            self.assertIn("map_Kd skin.png", f.read())
        with open(obj[:-4] + ".png", "rb") as f:
            self.assertTrue(f.read(8) == b"\x89PNG\r\n\x1a\n")

        # Bad input: counted, and the node goes on.
        before = self.counter("surface", "depth rejected")
        self.depth_pub.publish(image(t0 + rospy.Duration(2.0), "stereo_left_optical_frame",
                                     np.zeros((H, W), np.uint8), "mono8"))
        self.depth_pub.publish(image(t0 + rospy.Duration(2.1), "stereo_left_optical_frame",
                                     np.full((H, W), np.nan, np.float32), "32FC1"))
        self.depth_pub.publish(image(t0 + rospy.Duration(2.2), "stereo_left_optical_frame",
                                     np.full((H // 2, W), DEPTH, np.float32), "32FC1"))
        self.wait_for("three depth rejections", lambda: self.counter("surface", "depth rejected") >= before + 3)
        self.assertGreaterEqual(self.counter("surface", "rejected: unknown_encoding"), 1)
        self.assertGreaterEqual(self.counter("surface", "rejected: no_valid_depth"), 1)
        self.assertGreaterEqual(self.counter("surface", "rejected: size_mismatch"), 1)
        self.imaging_pub.publish(image(t0 + rospy.Duration(2.3), "imaging_optical_frame", grey, "yuv422"))
        self.wait_for("an imaging rejection", lambda: self.counter("surface", "imaging rejected") >= 1)
        # Frames without TF (an unknown frame) wait in the TF filter's queue
        # (queue_size 5) and are dropped, counted, when it overflows.
        for k in range(7):
            self.depth_pub.publish(image(t0 + rospy.Duration(2.4 + 0.01 * k), "nowhere", depth, "32FC1"))
        self.wait_for("a frame without TF", lambda: self.counter("surface", "depth without TF") >= 1, 40)
        # A stamp slightly back is out of order; one far back (> time_jump_reset)
        # starts the surface again, and that frame is its first keyframe.
        self.depth_pub.publish(image(t0 + rospy.Duration(2.15), "stereo_left_optical_frame", depth, "32FC1"))
        self.wait_for("an out-of-order depth image", lambda: self.counter("surface", "depth out of order") >= 1)
        keyframes = self.counter("surface", "keyframes")
        self.depth_pub.publish(image(t0 - rospy.Duration(5.0), "stereo_left_optical_frame", depth, "32FC1"))
        self.wait_for("a time jump", lambda: self.counter("surface", "time jumps (reset)") >= 1)
        self.wait_for("the first keyframe after it", lambda: self.counter("surface", "keyframes") >= keyframes + 1)

    def test_invalid_parameters_refused(self):
        def error_reported():
            with self.lock:
                s = self.status.get("surface_invalid: surface")
            return s is not None and s.level == DiagnosticStatus.ERROR and "voxel_size" in s.message
        self.wait_for("ERROR of the invalid instance", error_reported)


if __name__ == "__main__":
    rospy.init_node("surface_nodelet_test")
    rostest.rosrun("hapi_surface", "surface_nodelet", SurfaceNodeletTest)
