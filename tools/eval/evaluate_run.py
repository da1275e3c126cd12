#!/usr/bin/python3
"""Live evaluation of a pipeline run against the globe bag's ground truth.

Collects the back end's odometry, the ground-truth camera pose and the last
landmark map while a bag plays; when the odometry has been silent for
~idle_timeout wall seconds (the bag ended) or ~max_wall_time passed, it prints
the absolute trajectory error (after rigid alignment, see evaluation.py), the
map's RMS distance to the true sphere, the rates, and the per-stage timings
the nodelets report in /diagnostics. Writes the same as YAML to ~output.

With ~test:=true it is a rostest test node: it fails when a metric is outside
the bounds given as parameters.
"""
import os
import sys
import threading
import time
import unittest

import numpy as np
import rospy
import yaml
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import String

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import evaluation as ev  # noqa: E402


class RunCollector:
    def __init__(self):
        self.lock = threading.Lock()
        self.est = []   # (stamp, p)
        self.gt = []    # (stamp, p)
        self.map_points = None
        self.globe = None
        self.diag = {}
        self.last_odom_wall = None
        self.first_odom_wall = None
        self.odom_count = 0
        rospy.Subscriber(rospy.get_param("~odom_topic", "/eskf/odom"), Odometry, self.on_odom, queue_size=100)
        rospy.Subscriber(rospy.get_param("~gt_topic", "/ground_truth/pose"), PoseStamped, self.on_gt, queue_size=100)
        rospy.Subscriber(rospy.get_param("~map_topic", "/eskf/map"), PointCloud2, self.on_map, queue_size=2)
        rospy.Subscriber(rospy.get_param("~globe_topic", "/globe/info"), String, self.on_globe, queue_size=2)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=20)

    def on_odom(self, msg):
        p = msg.pose.pose.position
        with self.lock:
            self.est.append((msg.header.stamp.to_sec(), np.array([p.x, p.y, p.z])))
            now = time.time()
            self.last_odom_wall = now
            if self.first_odom_wall is None:
                self.first_odom_wall = now
            self.odom_count += 1

    def on_gt(self, msg):
        p = msg.pose.position
        with self.lock:
            self.gt.append((msg.header.stamp.to_sec(), np.array([p.x, p.y, p.z])))

    def on_map(self, msg):
        pts = np.array([[x, y, z] for x, y, z in point_cloud2.read_points(msg, ("x", "y", "z"), skip_nans=True)])
        with self.lock:
            self.map_points = pts

    def on_globe(self, msg):
        with self.lock:
            self.globe = yaml.safe_load(msg.data)

    def on_diag(self, msg):
        with self.lock:
            for st in msg.status:
                self.diag[st.name] = {kv.key: kv.value for kv in st.values}

    def wait_for_end(self, idle_timeout, max_wall):
        start = time.time()
        while not rospy.is_shutdown() and time.time() - start < max_wall:
            with self.lock:
                last = self.last_odom_wall
            if last is not None and time.time() - last > idle_timeout:
                return True
            time.sleep(0.2)
        return False

    def globe_geometry(self):
        if rospy.has_param("~sphere_radius"):
            return rospy.get_param("~sphere_centre", [0.0, 0.0, 0.0]), float(rospy.get_param("~sphere_radius"))
        if self.globe is not None:
            return self.globe["centre"], float(self.globe["radius"])
        return None, None

    def results(self):
        with self.lock:
            est, gt, map_points = list(self.est), list(self.gt), self.map_points
            odom_count, diag = self.odom_count, dict(self.diag)
            wall = (self.last_odom_wall - self.first_odom_wall) if self.odom_count > 1 else 0.0
        res = {"odom_messages": odom_count, "gt_messages": len(gt)}
        if odom_count > 1 and est[-1][0] > est[0][0]:
            res["odom_rate_sim_hz"] = (odom_count - 1) / (est[-1][0] - est[0][0])
        if wall > 0:
            res["odom_rate_wall_hz"] = (odom_count - 1) / wall
        pairs = ev.associate([s for s, _ in est], [s for s, _ in gt], max_dt=0.006)
        if len(pairs) >= 3:
            e = np.array([est[i][1] for i, _ in pairs])
            g = np.array([gt[j][1] for _, j in pairs])
            ate = ev.trajectory_error(e, g)
            dist = ev.path_length(g)
            res.update({"poses_compared": len(pairs), "ate_rmse_m": ate["rmse"], "ate_max_m": ate["max"],
                        "distance_travelled_m": dist,
                        "ate_fraction_of_distance": ate["rmse"] / dist if dist > 0 else float("inf")})
            centre, radius = self.globe_geometry()
            if map_points is not None and len(map_points) > 0:
                res["map_points"] = int(len(map_points))
                if radius is not None:
                    rms, med = ev.sphere_error(map_points, ate["R"], ate["t"], centre, radius)
                    res["map_rms_to_sphere_m"] = rms
                    res["map_median_abs_to_sphere_m"] = med
        res["diagnostics"] = {k: v for k, v in diag.items() if "hapi" in k.lower() or "eskf" in k.lower()
                              or "frontend" in k.lower()}
        return res


def report(res):
    out = rospy.get_param("~output", "")
    text = yaml.safe_dump(res, default_flow_style=False, sort_keys=True)
    print("==== HAPI run evaluation ====\n" + text + "=============================", flush=True)
    if out:
        with open(out, "w") as f:
            f.write(text)


class PipelineAccuracyTest(unittest.TestCase):
    collector = None

    def test_pipeline_accuracy(self):
        c = PipelineAccuracyTest.collector
        ended = c.wait_for_end(rospy.get_param("~idle_timeout", 5.0), rospy.get_param("~max_wall_time", 300.0))
        res = c.results()
        report(res)
        self.assertTrue(ended, "odometry never went quiet (bag did not end?)")
        self.assertGreater(res["odom_messages"], 0, "no odometry")
        self.assertIn("ate_rmse_m", res, "no odometry matched the ground truth")
        self.assertLessEqual(res["ate_fraction_of_distance"], rospy.get_param("~max_ate_fraction", 0.02))
        self.assertGreater(res.get("map_points", 0), 0, "empty map")
        self.assertIn("map_rms_to_sphere_m", res, "globe geometry unknown")
        self.assertLessEqual(res["map_rms_to_sphere_m"], rospy.get_param("~max_map_rms", 0.01))


def main():
    rospy.init_node("hapi_evaluate_run")
    collector = RunCollector()
    if rospy.get_param("~test", False):
        import rostest
        PipelineAccuracyTest.collector = collector
        rostest.rosrun("hapi_slam", "pipeline_accuracy", PipelineAccuracyTest, sys.argv)
        return
    collector.wait_for_end(rospy.get_param("~idle_timeout", 5.0), rospy.get_param("~max_wall_time", 600.0))
    report(collector.results())
    if rospy.get_param("~shutdown_when_done", True):
        rospy.signal_shutdown("evaluation done")


if __name__ == "__main__":
    main()
