#!/usr/bin/python3
"""Two sessions of the whole system (launch/replay.launch) on the same
simulated scene (docs/DESIGN.md "Map file"):

  map_sessions_test.py [--motion-model M] [--frontend-config YAML] [--surfaces DIR] [--json FILE]
                       SESSION1_BAG SESSION2_BAG [OTHER_BAG]

Session 1 replays SESSION1_BAG and saves its map through /eskf/save_map.
Session 2 starts with ~map_file set to that map on SESSION2_BAG, whose
camera starts elsewhere in the scene (another trajectory), with no pose
hint. It passes when
  * the map file of session 1 holds keyframes (session 2's /diagnostics
    map_keyframes: kept while session 1 scanned, written by ~save_map),
  * /diagnostics of session 2 reports "relocalised in the loaded map at T",
  * session 2 publishes no odometry before T (nothing in the map frame
    before the camera is placed in it),
  * after T, its odometry lies within MAX_POSITION_ERROR of the truth
    expressed in session 1's map frame (the two bags' truths share the
    scene frame; session 1's map frame is its first camera pose, found from
    its first odometry), and covers most of the rest of the bag;
  * with OTHER_BAG (the same scene with another texture), a third session
    with session 1's map never relocalises and publishes no odometry.
Every session runs --motion-model (constant_velocity by default; inertial:
the bags' IMU levels each session's world and the map fit must agree with
its tilt). The truths are the camera in the scene frame, so a second
session on the scene placed elsewhere (make_sim_bag --scene-offset) and
under other lighting (--lighting-gain) compares in the same frame. With
--surfaces DIR, sessions 1 and 2 also run the dense depth and the surface
(the skin's profiles), save their surfaces (/surface/save_surface) to
DIR/session1.ply and DIR/session2.ply, and tools/eval/session_compare.py
compares them (DIR/compare.{ply,png,json}; figures printed, not checked).
--json FILE writes the figures (relocalisation time, position and rotation
errors, the other scene's verdict, the surfaces' comparison) for
tools/eval/session_study.py. Exit 0 pass, 1 fail.

A stalled bag player (tools/eval/input_stall.py: its /clock stood still for
STALL_S or more, or stopped before the bag's end) delivers frames late and
all at once; a test that failed with such an input runs once more, in a new
process. One that failed with a real-time input does not.
"""
import argparse
import bisect
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import rosbag
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from scipy.spatial.transform import Rotation
from std_srvs.srv import Trigger

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(REPO, "tools", "eval"))
import input_stall  # noqa: E402
RETRY_ENV = "HAPI_MAP_SESSIONS_RETRY"  # set in the one rerun after a stalled input

# Loose against the measured figure (docs/DESIGN.md "Map file": session 1's
# drift over its 6 s plus session 2's error), tight against a filter that
# tracks from its own start instead (the two starts are ~11 cm apart).
MAX_POSITION_ERROR = 0.02  # [m], every pose after relocalisation
MIN_COVERAGE = 0.6         # fraction of session 2's frames after T with odometry
MIN_OTHER_HELD = 20        # of the other scene's 40 frames: it was seen, and held back
RELOCALISED = re.compile(r"relocalised in the loaded map at ([0-9.]+)")


def pose_matrix(p, q):
    T = np.eye(4)
    T[:3, :3] = Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix()
    T[:3, 3] = [p.x, p.y, p.z]
    return T


def read_truth(bag_path):
    """Stamps [s] and T_world_cam of /ground_truth/odometry."""
    stamps, poses = [], []
    with rosbag.Bag(bag_path) as bag:
        for _, m, _ in bag.read_messages(["/ground_truth/odometry"]):
            stamps.append(m.header.stamp.to_sec())
            poses.append(pose_matrix(m.pose.pose.position, m.pose.pose.orientation))
    return stamps, poses


def truth_at(truth, t, tolerance=0.003):
    stamps, poses = truth
    i = bisect.bisect_left(stamps, t)
    best = min((j for j in (i - 1, i) if 0 <= j < len(stamps)), key=lambda j: abs(stamps[j] - t))
    if abs(stamps[best] - t) > tolerance:
        raise RuntimeError("no truth within %.3f s of %.3f" % (tolerance, t))
    return poses[best]


def frame_count(bag_path):
    with rosbag.Bag(bag_path) as bag:
        return bag.get_message_count("/stereo/left/image_raw")


class Watch:
    """Odometry, the relocalisation state on /diagnostics and /clock."""

    def __init__(self):
        self.odom, self.states = [], []
        self.held = 0  # the filter's frames_relocalising
        self.map_keyframes = 0  # keyframes in the loaded map file
        self.steps = input_stall.ClockSteps()  # the session's /clock
        self.largest_stall = 0.0  # [s] of every session so far
        rospy.Subscriber("/eskf/odom", Odometry, self.on_odom, queue_size=1000)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=100)
        rospy.Subscriber("/clock", Clock, self.on_clock, queue_size=10000, tcp_nodelay=True)

    def clear(self):
        self.odom, self.states = [], []
        self.held = 0
        self.map_keyframes = 0
        self.steps = input_stall.ClockSteps()

    def session_over(self, bag_end):
        """Keeps the session's largest /clock step; a clock that stopped
        more than a second before the bag's end [s] is a stall of that length."""
        stall, last = self.steps.largest, self.steps.last()
        if last is not None and bag_end - last > 1.0:
            stall = max(stall, bag_end - last)
        self.largest_stall = max(self.largest_stall, stall)

    def on_odom(self, m):
        self.odom.append((m.header.stamp.to_sec(), pose_matrix(m.pose.pose.position, m.pose.pose.orientation)))

    def on_diag(self, m):
        for s in m.status:
            for kv in s.values:
                if kv.key == "relocalisation":
                    self.states.append(kv.value)
                elif kv.key == "frames_relocalising":
                    self.held = int(kv.value)
                elif kv.key == "map_keyframes":
                    self.map_keyframes = int(kv.value)

    def on_clock(self, m):
        self.steps.add(m.clock.to_sec(), time.time())

    def bag_over(self, quiet_s=3.0):
        return self.steps.last() is not None and self.steps.still_for(time.time()) > quiet_s


def run_session(watch, bag, map_file, options, timeout_s=120.0):
    """Replays `bag`; returns the roslaunch process once the bag is over."""
    watch.clear()
    surfaces = "true" if options.surfaces else "false"
    args = ["roslaunch", "hapi_slam", "replay.launch", "bag:=" + bag, "dense_depth:=" + surfaces,
            "surface:=" + surfaces, "surface_motion:=false", "ground_truth:=false", "output:=log",
            "motion_model:=" + options.motion_model, "delay:=3.0", "map_file:=" + map_file]
    if options.frontend_config:
        args.append("frontend_config:=" + options.frontend_config)
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
    end = time.time() + timeout_s
    while time.time() < end and not watch.bag_over():
        if proc.poll() is not None:
            raise RuntimeError("roslaunch ended early (%d)" % proc.returncode)
        time.sleep(0.2)
    if not watch.bag_over():
        raise RuntimeError("the bag did not finish within %.0f s" % timeout_s)
    with rosbag.Bag(bag) as b:
        watch.session_over(b.get_end_time())
    return proc


def save_surface(path):
    """The running session's surface to `path` (PLY); its vertex count."""
    from hapi_msgs.srv import SaveSurface
    rospy.wait_for_service("/surface/save_surface", 10.0)
    res = rospy.ServiceProxy("/surface/save_surface", SaveSurface)(path)
    if not res.success:
        raise RuntimeError("~save_surface: " + res.message)
    return res.vertices


def compare_surfaces(directory):
    """session_compare.py of the two sessions' surfaces; its exit status."""
    tool = os.path.join(REPO, "tools", "eval", "session_compare.py")
    first, second = (os.path.join(directory, "session%d.ply" % i) for i in (1, 2))
    return subprocess.call(["/usr/bin/python3", tool, first, second, os.path.join(directory, "compare")])


def stop(proc):
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(30)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def pose_errors(odom, truth, T_map_world, since=-np.inf):
    """Position [m] and rotation [deg] errors of the odometry from `since`
    on against the truth moved into the map frame."""
    errors, angles = [], []
    for t, T_map_cam in odom:
        if t < since:
            continue
        T_truth = T_map_world @ truth_at(truth, t)
        errors.append(np.linalg.norm(T_map_cam[:3, 3] - T_truth[:3, 3]))
        angles.append(np.linalg.norm(Rotation.from_matrix(T_map_cam[:3, :3].T @ T_truth[:3, :3]).as_rotvec()))
    return np.array(errors), np.degrees(angles)


def check_session2(watch, truth1, truth2, T_map_world, frames, figures):
    failures = []
    # Session 1 kept keyframes while it scanned, and its map file carries them.
    figures["map_keyframes"] = watch.map_keyframes
    print("session 2 read a map with %d keyframes" % watch.map_keyframes)
    if watch.map_keyframes < 1:
        failures.append("the map file of session 1 holds no keyframes")
    relocalised = [float(m.group(1)) for m in map(RELOCALISED.match, watch.states) if m]
    print("session 2 relocalisation states:", sorted(set(watch.states)))
    figures["relocalised"] = bool(relocalised)
    if not relocalised:
        return ["session 2 never reported 'relocalised in the loaded map'"]
    t_reloc = relocalised[0]
    t_first_truth = truth2[0][0]
    figures["relocalised_after_s"] = t_reloc - t_first_truth
    print("relocalised at %.3f, %.2f s into the bag" % (t_reloc, t_reloc - t_first_truth))
    early = [t for t, _ in watch.odom if t < t_reloc - 1e-3]
    figures["odometry_before_relocalisation"] = len(early)
    if early:
        failures.append("%d odometry messages before relocalisation (first at %.3f)" % (len(early), early[0]))
    errors, angles = pose_errors(watch.odom, truth2, T_map_world, since=t_reloc - 1e-3)
    if not len(errors):
        return failures + ["no odometry after relocalisation"]
    frames_after = frames * (truth2[0][-1] - t_reloc) / (truth2[0][-1] - t_first_truth)
    figures.update({"poses": len(errors), "position_error_median_m": float(np.median(errors)),
                    "position_error_max_m": float(errors.max()), "rotation_error_median_deg": float(np.median(angles)),
                    "rotation_error_max_deg": float(angles.max())})
    print("session 2 after relocalisation: %d poses (of ~%.0f frames), position error median %.1f mm, max %.1f mm, "
          "rotation error median %.3f deg, max %.3f deg"
          % (len(errors), frames_after, 1e3 * np.median(errors), 1e3 * errors.max(), np.median(angles), angles.max()))
    if errors.max() > MAX_POSITION_ERROR:
        failures.append("position error %.1f mm > %.1f mm" % (1e3 * errors.max(), 1e3 * MAX_POSITION_ERROR))
    if len(errors) < MIN_COVERAGE * frames_after:
        failures.append("only %d poses for ~%.0f frames after relocalisation" % (len(errors), frames_after))
    return failures


def check_other_scene(watch, figures, truth, T_map_world):
    """Session 3: the map of another texture must never place the camera.
    Where it did, how far from the truth (the other scene shares the first
    one's frame) tells a wrong place from a right one on shared structure."""
    print("other scene: relocalisation states %s, %d frames held back" % (sorted(set(watch.states)), watch.held))
    figures.update({"frames_held": watch.held, "relocalised": any(RELOCALISED.match(x) for x in watch.states),
                    "odometry": len(watch.odom)})
    if watch.odom:
        errors = pose_errors(watch.odom, truth, T_map_world)[0]
        figures["position_error_median_m"] = float(np.median(errors))
        print("other scene placed: position error median %.1f mm, max %.1f mm" % (1e3 * np.median(errors),
                                                                                   1e3 * errors.max()))
    failures = []
    if watch.held < MIN_OTHER_HELD:
        failures.append("only %d frames of the other scene reached the filter" % watch.held)
    if not watch.states:
        failures.append("the other scene's session reported no relocalisation state")
    if any(RELOCALISED.match(x) for x in watch.states):
        failures.append("relocalised in the map of another texture")
    if watch.odom:
        failures.append("%d odometry messages in the map of another texture" % len(watch.odom))
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--motion-model", default="constant_velocity", choices=("constant_velocity", "gyro", "inertial"))
    ap.add_argument("--frontend-config", default="", help="the front end's YAML (skin: config/frontend_skin.yaml)")
    ap.add_argument("--surfaces", default="", help="folder: also map, save and compare the two sessions' surfaces")
    ap.add_argument("--json", default="", help="write the figures here")
    ap.add_argument("bags", nargs="+", help="SESSION1_BAG SESSION2_BAG [OTHER_BAG]")
    a = ap.parse_args()
    if len(a.bags) not in (2, 3):
        ap.error("two or three bags")
    bag1, bag2 = a.bags[:2]
    other_bag = a.bags[2] if len(a.bags) > 2 else ""
    truth1, truth2 = read_truth(bag1), read_truth(bag2)
    start_offset = np.linalg.inv(truth1[1][0]) @ truth2[1][0]
    print("session 2 starts %.1f mm and %.1f deg from session 1's start"
          % (1e3 * np.linalg.norm(start_offset[:3, 3]),
             np.degrees(np.linalg.norm(Rotation.from_matrix(start_offset[:3, :3]).as_rotvec()))))
    with socket.socket() as s:
        s.bind(("localhost", 0))
        port = s.getsockname()[1]
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % port
    core = subprocess.Popen(["roscore", "-p", str(port)], stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
    map_path = ""
    figures = {"session2": {}, "start_offset_m": float(np.linalg.norm(start_offset[:3, 3]))}
    try:
        time.sleep(3.0)
        rospy.init_node("map_sessions_test", disable_signals=True)
        watch = Watch()
        if a.surfaces:
            os.makedirs(a.surfaces, exist_ok=True)
        proc = run_session(watch, bag1, "", a)
        try:
            rospy.wait_for_service("/eskf/save_map", 10.0)
            res = rospy.ServiceProxy("/eskf/save_map", Trigger)()
            if a.surfaces:
                print("session 1 surface: %d vertices" % save_surface(os.path.join(a.surfaces, "session1.ply")))
        finally:
            stop(proc)
        if not res.success:
            print("FAIL: session 1's ~save_map: %s" % res.message)
            return 1, watch.largest_stall
        map_path = res.message
        print("session 1: %d poses, map saved to %s" % (len(watch.odom), map_path))
        if not watch.odom:
            print("FAIL: session 1 published no odometry")
            return 1, watch.largest_stall
        # Session 1's map frame (its first camera pose; inertial: levelled at
        # its first camera position): T_map_world from its first odometry.
        t1, T_map_cam1 = watch.odom[0]
        T_map_world = T_map_cam1 @ np.linalg.inv(truth_at(truth1, t1))
        proc = run_session(watch, bag2, map_path, a)
        try:
            if a.surfaces:
                print("session 2 surface: %d vertices" % save_surface(os.path.join(a.surfaces, "session2.ply")))
        finally:
            stop(proc)
        failures = check_session2(watch, truth1, truth2, T_map_world, frame_count(bag2), figures["session2"])
        if a.surfaces:
            if compare_surfaces(a.surfaces) != 0:
                failures.append("session_compare.py failed on the two surfaces")
            else:
                with open(os.path.join(a.surfaces, "compare.json")) as f:
                    figures["surfaces"] = json.load(f)
        if other_bag:
            stop(run_session(watch, other_bag, map_path, a))
            figures["other"] = {}
            failures += check_other_scene(watch, figures["other"], read_truth(other_bag), T_map_world)
    finally:
        if map_path:
            for p in (map_path, map_path[:-4] + "ply"):
                if os.path.exists(p):
                    os.remove(p)
        core.send_signal(signal.SIGINT)
        core.wait(30)
    figures["failures"] = failures
    if a.json:
        with open(a.json, "w") as f:
            json.dump(figures, f, indent=1)
    for f in failures:
        print("FAIL:", f)
    print("largest step of the bag player's /clock: %.2f s" % watch.largest_stall)
    print("PASS" if not failures else "FAILED")
    return (1 if failures else 0), watch.largest_stall


if __name__ == "__main__":
    rc, stall = main()
    if rc != 0 and stall >= input_stall.STALL_S and not os.environ.get(RETRY_ENV):
        print("a bag player stalled for %.1f s (the machine, not the system under test): running the test once more"
              % stall, flush=True)
        os.execve(sys.executable, [sys.executable] + sys.argv, dict(os.environ, **{RETRY_ENV: "1"}))
    sys.exit(rc)
