#!/usr/bin/python3
"""Watches a running HAPI system for a while and writes what it saw as JSON.

  ros_probe.py --duration 30 --out phase.json [--odom /eskf/odom]

Records every odometry message (wall time of arrival, stamp, position) and
the latest /diagnostics status of every component, so the reliability
scripts (two_hosts.sh, soak.sh) can judge a phase afterwards: was odometry
published, at what rate, did the pose jump, did a time jump reset the
filter, how many messages were rejected or dropped.
"""
import argparse
import json
import math
import signal
import struct
import sys
import threading
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from nav_msgs.msg import Odometry


class Probe(object):
    def __init__(self, odom_topic, input_topic=None):
        self.lock = threading.Lock()
        self.odom = []   # [wall, stamp, x, y, z]
        self.input = []  # [wall, stamp]
        self.diag = {}   # status name -> {"level":, "message":, "values": {}}
        self.diag_series = []  # [wall, status name, {values}] of every status received
        rospy.Subscriber(odom_topic, Odometry, self.on_odom, queue_size=1000)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=100)
        if input_topic:
            rospy.Subscriber(input_topic, rospy.AnyMsg, self.on_input, queue_size=1000)

    def on_odom(self, msg):
        p = msg.pose.pose.position
        with self.lock:
            self.odom.append([time.time(), msg.header.stamp.to_sec(), p.x, p.y, p.z])

    def on_input(self, msg):
        # Any message with a std_msgs/Header first: seq (uint32), then the stamp.
        sec, nsec = struct.unpack_from("<II", msg._buff, 4)
        with self.lock:
            self.input.append([time.time(), sec + 1e-9 * nsec])

    def on_diag(self, msg):
        with self.lock:
            for st in msg.status:
                self.diag[st.name] = {"level": ord(st.level) if isinstance(st.level, (bytes, str)) else int(st.level),
                                      "message": st.message,
                                      "values": {kv.key: kv.value for kv in st.values}}
                self.diag_series.append([time.time(), st.name, self.diag[st.name]["values"]])


def summarise(odom, start_wall):
    """Rate, largest position step and the resets seen as stamps going backwards."""
    s = {"odom_count": len(odom)}
    if not odom:
        return s
    s["odom_first_wall"] = odom[0][0] - start_wall
    s["odom_last_wall"] = odom[-1][0] - start_wall
    span = odom[-1][0] - odom[0][0]
    s["odom_rate_hz"] = (len(odom) - 1) / span if span > 0 else 0.0
    steps, jumps = [], []
    for a, b in zip(odom, odom[1:]):
        if b[1] < a[1]:
            # Stamp went backwards: the first pose of the new timeline (the
            # filter restarts at the origin = its first camera pose).
            jumps.append({"wall": b[0] - start_wall, "from_stamp": a[1], "to_stamp": b[1],
                          "first_position_norm": math.sqrt(b[2] ** 2 + b[3] ** 2 + b[4] ** 2)})
            continue
        steps.append(math.sqrt((b[2] - a[2]) ** 2 + (b[3] - a[3]) ** 2 + (b[4] - a[4]) ** 2))
    s["max_step_m"] = max(steps) if steps else 0.0
    s["stamp_jumps"] = jumps
    gaps = [b[0] - a[0] for a, b in zip(odom, odom[1:])]
    s["max_gap_s"] = max(gaps) if gaps else 0.0
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--duration", type=float, required=True, help="seconds to watch (wall time)")
    ap.add_argument("--out", required=True, help="JSON file to write")
    ap.add_argument("--odom", default="/eskf/odom")
    ap.add_argument("--input", default="", help="a stamped topic the bag player publishes (optional)")
    args = ap.parse_args(rospy.myargv()[1:])
    rospy.init_node("hapi_ros_probe", anonymous=True, disable_signals=True)
    # SIGTERM/SIGINT end the watch early (the caller knows when its phase
    # is over); what was seen so far is still written.
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    probe = Probe(args.odom, args.input)
    start = time.time()
    while time.time() - start < args.duration and not rospy.is_shutdown() and not stop:
        time.sleep(0.1)
    with probe.lock:
        odom, diag, series = list(probe.odom), dict(probe.diag), list(probe.diag_series)
        inputs = list(probe.input)
    out = summarise(odom, start)
    out["duration_s"] = time.time() - start
    out["diagnostics"] = diag
    out["odom"] = [[round(o[0] - start, 3), o[1], o[2], o[3], o[4]] for o in odom]
    out["input"] = [[round(i[0] - start, 3), i[1]] for i in inputs]
    out["diagnostics_series"] = [[round(d[0] - start, 3), d[1], d[2]] for d in series]
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)
    print("[probe] %d odometry messages (%.1f Hz), max step %.4f m, %d stamp jumps, %d diagnostic statuses"
          % (out["odom_count"], out.get("odom_rate_hz", 0.0), out.get("max_step_m", 0.0),
             len(out.get("stamp_jumps", [])), len(diag)))
    rospy.signal_shutdown("done")
    return 0


if __name__ == "__main__":
    sys.exit(main())
