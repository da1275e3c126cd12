#!/usr/bin/python3
"""Live evaluation of a pipeline run against the globe bag's ground truth.

Collects the back end's odometry (pose, covariance, twist), the ground-truth
camera pose (and twist, /ground_truth/odometry, when the bag has it), the
scene geometry (/ground_truth/scene, or the globe bags' /globe/info) and the
last landmark map while a bag plays; when the odometry has been silent for
~idle_timeout wall seconds (the bag ended) or ~max_wall_time passed, it prints
the metrics of run_analysis.py (ATE SE(3) and Sim(3), rotation error, RPE
over 1 s, NEES, velocity error, map error to the nearest true surface), the
rates, and the per-stage timings the nodelets report in /diagnostics. Writes
the same as YAML to ~output and, next to it, the trajectories
(estimate.tum, ground_truth.tum, estimate_covariance.txt: the inputs of the
offline tools/eval/evaluate.py) and the PNG plots (plots.py). With ~surface
(hapi_surface/SurfaceNodelet running) it saves the surface to mesh.ply next
to ~output before the launch ends, scores it against the truth and draws
mesh.png (surface_run.py), in the report's `surface` section.

The report gives the largest step of the bag player's /clock
(input_largest_clock_step_s, input_stall.py): seconds of the bag delivered
late and in a burst because the machine stalled the player.

With ~test:=true it is a rostest test node: it fails when a metric is outside
the bounds given as parameters, or when the run did not cover the bag (a back
end that died or stalled also leaves the odometry silent): fewer than
~min_pose_coverage of the ground-truth poses matched by an estimate, the last
odometry more than ~max_end_gap bag seconds before the last ground-truth pose,
or a node of ~watch_nodes (the nodelet manager) no longer answering. With
~expect_failures (a list of check names, see failed_checks) it passes only
when at least those checks fail: the test of the checks themselves
(test/system/backend_dies.test). Under rostest's retry, an attempt that
failed with a real-time input ends the test: only a stalled input
(input_stall.STALL_S) earns the retry (input_stall.AttemptRecord).

Clocks: the back end runs on the camera clock; a simulated bag's truth is on
the IMU clock, and /ground_truth/calibration (time_offset_s, t_imu = t_cam +
offset) says how far apart they are. The estimates are moved onto the
truth's clock before they are compared (as tools/eval/accuracy.py does):
3 ms on a hand-held scan's angular acceleration is a few hundredths of a
rad/s in the twist.
"""
import os
import sys
import threading
import time
import unittest

import numpy as np
import rosnode
import rospy
import yaml
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import String

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import input_stall  # noqa: E402
import plots  # noqa: E402
import run_analysis  # noqa: E402
import scene_geometry  # noqa: E402
import surface_motion_run  # noqa: E402
import surface_run  # noqa: E402
import trajectory_io as tio  # noqa: E402


MAX_DT = 0.006  # [s] an estimate and a truth pose this close in time are compared


def truth_coverage(est_t, gt_t, max_dt):
    """Fraction of the ground-truth poses (one a frame) that have an estimate
    within max_dt (the odometry may come at the IMU's rate: several
    estimates near one frame count once)."""
    gt_t = np.asarray(gt_t, dtype=float)
    est_t = np.sort(np.asarray(est_t, dtype=float))
    if not len(gt_t) or not len(est_t):
        return 0.0
    i = np.searchsorted(est_t, gt_t)
    before, after = est_t[np.clip(i - 1, 0, len(est_t) - 1)], est_t[np.clip(i, 0, len(est_t) - 1)]
    nearest = np.minimum(np.abs(before - gt_t), np.abs(after - gt_t))
    return float(np.mean(nearest <= max_dt))


class RunCollector:
    def __init__(self):
        self.lock = threading.Lock()
        self.est = []   # (stamp, p, q, 6x6 pose covariance, twist (linear, angular))
        self.gt = []    # (stamp, p, q)
        self.gt_twist = []  # (stamp, twist)
        self.map_points = None
        self.globe = None
        self.scene_text = None
        self.time_offset = 0.0  # t_truth = t_estimate + time_offset
        self.diag = {}
        self.last_odom_wall = None
        self.first_odom_wall = None
        self.odom_count = 0
        # Odometry (and its TF) must have strictly increasing stamps: TF
        # rejects a repeated one as TF_REPEATED_DATA.
        self.last_odom_stamp = None
        self.odom_stamps_not_increasing = 0
        rospy.Subscriber(rospy.get_param("~odom_topic", "/eskf/odom"), Odometry, self.on_odom, queue_size=100)
        rospy.Subscriber(rospy.get_param("~gt_topic", "/ground_truth/pose"), PoseStamped, self.on_gt, queue_size=100)
        rospy.Subscriber(rospy.get_param("~map_topic", "/eskf/map"), PointCloud2, self.on_map, queue_size=2)
        rospy.Subscriber(rospy.get_param("~globe_topic", "/globe/info"), String, self.on_globe, queue_size=2)
        rospy.Subscriber(rospy.get_param("~scene_topic", "/ground_truth/scene"), String, self.on_scene, queue_size=2)
        rospy.Subscriber(rospy.get_param("~gt_odom_topic", "/ground_truth/odometry"), Odometry, self.on_gt_odom,
                         queue_size=400)
        rospy.Subscriber(rospy.get_param("~calibration_topic", "/ground_truth/calibration"), String,
                         self.on_calibration, queue_size=2)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=20)
        self.clock_watch = input_stall.ClockWatch()
        self.player_node = rospy.get_param("~player_node", "/player")
        try:
            self.surface_motion = surface_motion_run.SurfaceMotionCollector()
        except ImportError as e:  # hapi_msgs' Python messages not built or not on the path
            rospy.logerr("surface motion not evaluated: %s", e)
            self.surface_motion = None
        self.surface = None
        if rospy.get_param("~surface", False):
            try:
                self.surface = surface_run.SurfaceCollector()
            except ImportError as e:  # hapi_msgs' Python services not built or not on the path
                rospy.logerr("surface not evaluated: %s", e)

    def player_registered(self):
        """The bag player has not finished: still registered with the master
        (a frozen player does not answer, but stays registered)."""
        try:
            return self.player_node in rosnode.get_node_names()
        except rosnode.ROSNodeIOException:
            return False

    def on_odom(self, msg):
        p, o = msg.pose.pose.position, msg.pose.pose.orientation
        v, w = msg.twist.twist.linear, msg.twist.twist.angular
        sample = (msg.header.stamp.to_sec(), np.array([p.x, p.y, p.z]), np.array([o.x, o.y, o.z, o.w]),
                  np.array(msg.pose.covariance).reshape(6, 6), np.array([v.x, v.y, v.z, w.x, w.y, w.z]))
        with self.lock:
            if self.last_odom_stamp is not None and msg.header.stamp <= self.last_odom_stamp:
                self.odom_stamps_not_increasing += 1
            self.last_odom_stamp = msg.header.stamp
            self.est.append(sample)
            now = time.time()
            self.last_odom_wall = now
            if self.first_odom_wall is None:
                self.first_odom_wall = now
            self.odom_count += 1

    def on_gt(self, msg):
        p, o = msg.pose.position, msg.pose.orientation
        with self.lock:
            self.gt.append((msg.header.stamp.to_sec(), np.array([p.x, p.y, p.z]), np.array([o.x, o.y, o.z, o.w])))

    def on_gt_odom(self, msg):
        v, w = msg.twist.twist.linear, msg.twist.twist.angular
        with self.lock:
            self.gt_twist.append((msg.header.stamp.to_sec(), np.array([v.x, v.y, v.z, w.x, w.y, w.z])))

    def on_calibration(self, msg):
        try:
            offset = float((yaml.safe_load(msg.data) or {}).get("time_offset_s", 0.0))
        except (ValueError, TypeError, AttributeError, yaml.YAMLError) as e:
            rospy.logerr("ground-truth calibration unusable: %s", e)
            return
        with self.lock:
            self.time_offset = offset

    def on_scene(self, msg):
        with self.lock:
            self.scene_text = msg.data

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

    def scene(self):
        """(name, surfaces) of the known geometry, None when unknown (a real recording)."""
        if rospy.has_param("~sphere_radius"):
            return "globe", [scene_geometry.Sphere(rospy.get_param("~sphere_centre", [0.0, 0.0, 0.0]),
                                                   float(rospy.get_param("~sphere_radius")))]
        with self.lock:
            scene_text, globe = self.scene_text, self.globe
        try:
            if scene_text is not None:
                return scene_geometry.parse_scene(scene_text)
            if globe is not None:
                return "globe", [scene_geometry.Sphere(globe["centre"], globe["radius"])]
        except (ValueError, KeyError, TypeError) as e:
            rospy.logerr("scene description unusable: %s", e)
        return None

    def trajectories(self):
        with self.lock:
            est, gt, gt_twist = list(self.est), list(self.gt), list(self.gt_twist)
            offset = self.time_offset
        e = {"t": np.array([s[0] for s in est]) + offset, "p": np.array([s[1] for s in est]).reshape(-1, 3),
             "q": np.array([s[2] for s in est]).reshape(-1, 4), "cov": np.array([s[3] for s in est]).reshape(-1, 6, 6),
             "twist": np.array([s[4] for s in est]).reshape(-1, 6)}
        # An all-zero covariance is "not given" (a filter without one): no NEES.
        if not np.any(e["cov"]):
            e["cov"] = None
        g = {"t": np.array([s[0] for s in gt]), "p": np.array([s[1] for s in gt]).reshape(-1, 3),
             "q": np.array([s[2] for s in gt]).reshape(-1, 4)}
        gtw = {"t": np.array([s[0] for s in gt_twist]), "twist": np.array([s[1] for s in gt_twist]).reshape(-1, 6)}
        return e, g, gtw

    def results(self):
        with self.lock:
            map_points = self.map_points
            odom_count, diag = self.odom_count, dict(self.diag)
            not_increasing = self.odom_stamps_not_increasing
            wall = (self.last_odom_wall - self.first_odom_wall) if self.odom_count > 1 else 0.0
        est, gt, gt_twist = self.trajectories()
        res = {"odom_messages": odom_count, "gt_messages": len(gt["t"]), "odom_stamps_not_increasing": not_increasing}
        if odom_count > 1 and est["t"][-1] > est["t"][0]:
            res["odom_rate_sim_hz"] = (odom_count - 1) / (est["t"][-1] - est["t"][0])
        if wall > 0:
            res["odom_rate_wall_hz"] = (odom_count - 1) / wall
        metrics, series = run_analysis.analyse(est, gt, max_dt=MAX_DT, scene=self.scene(), map_points=map_points,
                                               gt_twist=gt_twist if len(gt_twist["t"]) else None)
        res.update(metrics)
        scene = self.scene()
        with self.lock:
            offset = self.time_offset
        sm_rep, sm_series = (self.surface_motion.results(offset, gt, gt_twist if len(gt_twist["t"]) else None,
                                                         scene[1] if scene else None)
                             if self.surface_motion is not None else (None, None))
        if sm_rep is not None:
            res["surface_motion"] = sm_rep
        if sm_series is not None:
            series["surface_motion"] = sm_series
        # Coverage of the bag: the truth has one pose per frame, over the whole bag.
        if len(gt["t"]):
            res["pose_coverage"] = truth_coverage(est["t"], gt["t"], MAX_DT)
            if len(est["t"]):
                res["odom_end_gap_s"] = float(np.max(gt["t"]) - np.max(est["t"]))
        if "map_points" not in res and map_points is not None and len(map_points) > 0:
            res["map_points"] = int(len(map_points))
        ours = ("hapi", "eskf", "frontend", "surface", "imaging flow", "dense depth")
        res["diagnostics"] = {k: v for k, v in diag.items() if any(w in k.lower() for w in ours)}
        latency = latency_summary(res["diagnostics"])
        if latency:
            res["latency"] = latency
        stall, at = self.clock_watch.largest_step(player_running=self.player_registered())
        res["input_largest_clock_step_s"] = stall
        if at is not None:
            res["input_largest_clock_step_at_s"] = at - (float(gt["t"][0]) if len(gt["t"]) else 0.0)
        return res, series, est, gt


def latency_summary(diag):
    """Image stamp to output latencies over the run, from the nodelets' last
    /diagnostics (ROS clock: the bag's /clock in a replay): to the front
    end's landmarks, to the back end's odometry carrying the frame's
    correction (front end, transport and back end together), and from an
    imaging frame to the first surface-motion output carrying its flow."""
    out = {}
    keys = {"image_to_landmarks_ms": "latency stamp to landmarks %s [ms]", "image_to_odometry_ms": "latency_%s_ms",
            "imaging_to_surface_motion_ms": "flow_latency_%s_ms"}
    for values in diag.values():
        for name, pattern in keys.items():
            try:
                out[name] = {q: float(values[pattern % q]) for q in ("p50", "p99", "max")}
            except (KeyError, ValueError):
                continue
    return out


def write_run_files(out_dir, res, series, est, gt):
    """Trajectories and plots next to the report (the offline evaluator's inputs)."""
    if len(est["t"]):
        tio.write_tum(os.path.join(out_dir, "estimate.tum"), est["t"], est["p"], est["q"])
        if est["cov"] is not None:
            tio.write_covariances(os.path.join(out_dir, "estimate_covariance.txt"), est["t"], est["cov"])
    if len(gt["t"]):
        tio.write_tum(os.path.join(out_dir, "ground_truth.tum"), gt["t"], gt["p"], gt["q"])
    reason = plots.available()
    if reason is not None:
        res["plots_missing"] = reason
        return
    try:
        res["plots"] = [os.path.basename(p) for p in plots.write_plots(series, out_dir)]
    except Exception as e:  # a plot must never cost the report
        res["plots_missing"] = f"plotting failed: {e}"


def report(collected, collector):
    res, series, est, gt = collected
    out = rospy.get_param("~output", "")
    if out and collector.surface is not None:
        res["surface"] = collector.surface.save_and_score(os.path.dirname(os.path.abspath(out)),
                                                          series.get("alignment"), collector.scene(), gt,
                                                          res.get("diagnostics", {}), est=est)
    if out:
        write_run_files(os.path.dirname(os.path.abspath(out)), res, series, est, gt)
    text = yaml.safe_dump(run_analysis.to_plain(res), default_flow_style=False, sort_keys=True)
    print("==== HAPI run evaluation ====\n" + text + "=============================", flush=True)
    if out:
        with open(out, "w") as f:
            f.write(text)


def nodes_not_answering(names):
    """The nodes of `names` that no longer answer over XML-RPC (a crashed
    process stays registered with the master, but its API is gone)."""
    return [n for n in names if not rosnode.rosnode_ping(n, max_count=1, verbose=False)]


def failed_checks(res, bounds):
    """{check name: why} of every check of a run that failed. bounds: the
    test's parameters (max_ate_fraction, max_position_error (optional),
    max_map_rms, min_pose_coverage, max_end_gap; max_drift [m] and
    max_drift_deg, optional, bound a standstill's drift instead of the ATE;
    max_surface_velocity_rms [mm/s], optional, bounds the surface motion's
    error against its truth)."""
    f = {}
    if not res.get("ended", False):
        f["ended"] = "odometry never went quiet (bag did not end?)"
    if res.get("odom_messages", 0) == 0:
        f["odometry"] = "no odometry"
    if res.get("odom_stamps_not_increasing", 0):
        f["stamps"] = "odometry stamps repeated or went back"
    if res.get("pose_coverage", 0.0) < bounds["min_pose_coverage"]:
        f["coverage"] = "%d of %d ground-truth poses matched (< %.0f %%)" % (
            res.get("poses_compared", 0), res.get("gt_messages", 0), 100 * bounds["min_pose_coverage"])
    if res.get("odom_end_gap_s", float("inf")) > bounds["max_end_gap"]:
        f["end"] = "last odometry %s s before the bag's last ground-truth pose (> %s s)" % (
            res.get("odom_end_gap_s"), bounds["max_end_gap"])
    if res.get("nodes_not_answering"):
        f["nodes"] = "not answering: %s" % ", ".join(res["nodes_not_answering"])
    if "ate_rmse_m" not in res:
        f["ate"] = "no odometry matched the ground truth"
    elif res.get("standstill"):
        d_m, d_deg = res["standstill_drift_m"], res["standstill_rotation_drift_deg"]
        max_m = bounds.get("max_drift", run_analysis.STANDSTILL_MAX_DRIFT_M)
        max_deg = bounds.get("max_drift_deg", run_analysis.STANDSTILL_MAX_DRIFT_DEG)
        if d_m > max_m or d_deg > max_deg:
            f["ate"] = "standing still, drift %.4g m, %.4g deg > %.4g m, %.4g deg" % (d_m, d_deg, max_m, max_deg)
    elif res["ate_fraction_of_distance"] > bounds["max_ate_fraction"]:
        f["ate"] = "ATE %.4g of the distance > %.4g" % (res["ate_fraction_of_distance"], bounds["max_ate_fraction"])
    elif bounds.get("max_position_error") is not None and res["ate_max_m"] > bounds["max_position_error"]:
        f["ate"] = "largest position error %.4g m > %.4g m (diverged)" % (res["ate_max_m"],
                                                                         bounds["max_position_error"])
    if res.get("map_points", 0) == 0:
        f["map"] = "empty map"
    # Both nodelets report the image-stamp latency (values are benchmark
    # figures, not bounds).
    for key in ("image_to_landmarks_ms", "image_to_odometry_ms"):
        lat = res.get("latency", {}).get(key)
        if lat is None or not 0.0 <= lat["p50"] <= lat["p99"]:
            f["latency"] = "no valid %s latency in /diagnostics: %s" % (key, lat)
    if bounds.get("max_surface_velocity_rms") is not None:
        sm = res.get("surface_motion", {})
        if "rms_mm_s" not in sm:
            f["surface_motion"] = "no surface motion scored against the truth: %s" % sm
        elif sm["rms_mm_s"] > bounds["max_surface_velocity_rms"]:
            f["surface_motion"] = "surface velocity error %.4g mm/s RMS > %.4g mm/s" % (
                sm["rms_mm_s"], bounds["max_surface_velocity_rms"])
    f.update(surface_checks(res.get("surface"), bounds))
    rms = res.get("map_rms_to_sphere_m", res.get("map_rms_to_surface_m"))
    if rms is None:
        f["map_rms"] = "scene geometry unknown"
    elif rms > bounds["max_map_rms"]:
        f["map_rms"] = "map %.4g m RMS from the true surface > %.4g m" % (rms, bounds["max_map_rms"])
    return f


def surface_checks(surface, bounds):
    """{check: why} of the surface's bounds (max_surface_rms_mm,
    min_surface_completeness [%]; each optional)."""
    if bounds.get("max_surface_rms_mm") is None and bounds.get("min_surface_completeness") is None:
        return {}
    surface = surface or {}
    if "rms_mm" not in surface:
        return {"surface": "no surface scored: %s" % surface}
    f = {}
    if surface.get("mesh_messages") == 0:
        f["surface_mesh"] = "no ~mesh marker with triangles received"
    if bounds.get("max_surface_rms_mm") is not None and surface["rms_mm"] > bounds["max_surface_rms_mm"]:
        f["surface_rms"] = "mesh %.4g mm RMS from the true surface > %.4g mm" % (surface["rms_mm"],
                                                                                  bounds["max_surface_rms_mm"])
    if bounds.get("min_surface_completeness") is not None and not (
            surface.get("completeness_pct", 0.0) >= bounds["min_surface_completeness"]):
        f["surface_completeness"] = "completeness %s %% < %.4g %%" % (surface.get("completeness_pct"),
                                                                     bounds["min_surface_completeness"])
    return f


class PipelineAccuracyTest(unittest.TestCase):
    collector = None

    def test_pipeline_accuracy(self):
        attempt = input_stall.AttemptRecord(sys.argv)
        earlier = attempt.previous_failure()
        if earlier:
            self.fail("the previous attempt failed with a real-time input (a retry is for a stalled input "
                      "only): %s" % earlier)
        c = PipelineAccuracyTest.collector
        ended = c.wait_for_end(rospy.get_param("~idle_timeout", 5.0), rospy.get_param("~max_wall_time", 300.0))
        collected = c.results()
        res = collected[0]
        res["ended"] = ended
        res["nodes_not_answering"] = nodes_not_answering(rospy.get_param("~watch_nodes", []))
        report(collected, c)
        bounds = {"max_ate_fraction": rospy.get_param("~max_ate_fraction", 0.02),
                  "max_position_error": rospy.get_param("~max_position_error", None),
                  "max_map_rms": rospy.get_param("~max_map_rms", 0.01),
                  "min_pose_coverage": rospy.get_param("~min_pose_coverage", 0.5),
                  "max_end_gap": rospy.get_param("~max_end_gap", 1.0),
                  "max_drift": rospy.get_param("~max_drift", run_analysis.STANDSTILL_MAX_DRIFT_M),
                  "max_drift_deg": rospy.get_param("~max_drift_deg", run_analysis.STANDSTILL_MAX_DRIFT_DEG),
                  "max_surface_velocity_rms": rospy.get_param("~max_surface_velocity_rms", None),
                  "max_surface_rms_mm": rospy.get_param("~max_surface_rms_mm", None),
                  "min_surface_completeness": rospy.get_param("~min_surface_completeness", None)}
        failed = failed_checks(res, bounds)
        attempt.write(res["input_largest_clock_step_s"], failed)
        if failed and res["input_largest_clock_step_s"] >= input_stall.STALL_S:
            print("the bag player's clock stood still for %.1f s at %.1f s into the bag: the machine stalled the "
                  "input (rostest retries a test so stalled)" % (res["input_largest_clock_step_s"],
                                                                 res.get("input_largest_clock_step_at_s", -1.0)),
                  flush=True)
        expected = rospy.get_param("~expect_failures", [])
        if expected:
            self.assertEqual(sorted(set(expected) - set(failed)), [], "checks failed: %s" % failed)
        else:
            self.assertEqual(failed, {})


def main():
    rospy.init_node("hapi_evaluate_run")
    collector = RunCollector()
    if rospy.get_param("~test", False):
        import rostest
        PipelineAccuracyTest.collector = collector
        rostest.rosrun("hapi_slam", "pipeline_accuracy", PipelineAccuracyTest, sys.argv)
        return
    collector.wait_for_end(rospy.get_param("~idle_timeout", 5.0), rospy.get_param("~max_wall_time", 600.0))
    report(collector.results(), collector)
    if rospy.get_param("~shutdown_when_done", True):
        rospy.signal_shutdown("evaluation done")


if __name__ == "__main__":
    main()
