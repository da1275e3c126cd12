#!/usr/bin/python3
"""Judges a two_hosts.sh run from what ros_probe.py saw in each phase.

  two_hosts_verdict.py --out DIR --bag-len S --link TEXT --link-kind netem|tun|iptables \
                       --kill-wall S --restart-wall S --manager-pids PID_START PID_END

Prints a report (link losses, per-phase odometry and both hosts' diagnostics
counters, front end restart recovery time) and one PASS/FAIL line per check;
exit 0 when all pass. Times are wall seconds from the start of the phase's
probe (the same clock as ros_probe.py's "odom" entries).
"""
import argparse
import json
import math
import os
import re
import sys


def status(phase, needle):
    """Key/values of the first diagnostics status whose name contains needle."""
    for name, st in phase["diagnostics"].items():
        if needle in name:
            return st["values"]
    return {}


def num(d, k):
    try:
        return float(d.get(k, "nan"))
    except ValueError:
        return float("nan")


def link_stats(out, kind):
    """Per-direction packet counters of the impaired link, or {} when unknown."""
    if kind in ("tun", "iptables") and os.path.exists(out + "/link.json"):
        return json.load(open(out + "/link.json"))["directions"]
    if kind == "netem" and os.path.exists(out + "/netem_stats.txt"):
        d = {}
        for block in open(out + "/netem_stats.txt").read().split("== ")[1:]:
            ns = block.split("\n", 1)[0].strip()
            m = re.search(r"Sent \d+ bytes (\d+) pkt \(dropped (\d+)", block)
            if m:
                sent, drop = int(m.group(1)), int(m.group(2))
                d["from " + ns] = {"packets_in": sent + drop, "packets_dropped": drop, "packets_out": sent,
                                   "loss_measured_pct": 100.0 * drop / max(1, sent + drop)}
        return d
    return {}


def ground_truth(bag_path):
    """Ground-truth positions of the bag by stamp (0.1 s grid), or {} without rosbag."""
    try:
        import rosbag
    except ImportError:
        return {}
    gt = {}
    with rosbag.Bag(bag_path) as bag:
        for _, m, _ in bag.read_messages(topics=["/ground_truth/pose"]):
            p = m.pose.position
            gt[round(m.header.stamp.to_sec(), 1)] = (p.x, p.y, p.z)
    return gt


def step_errors(odom, gt):
    """|estimated - true| distance between consecutive odometry messages of one
    timeline (frame-free: the filter's map frame starts at its first pose)."""
    out = []
    for a, b in zip(odom, odom[1:]):
        ka, kb = round(a[1], 1), round(b[1], 1)
        if b[1] >= a[1] and ka in gt and kb in gt:
            out.append(abs(math.dist(a[2:5], b[2:5]) - math.dist(gt[ka], gt[kb])))
    return out


MOTION_SPAN_S = 1.0


def motion_error(odom, gt, span=MOTION_SPAN_S):
    """How far the estimated motion is from the true one, relative to the true
    motion: over baselines of `span` bag seconds (each odometry message to the
    first one >= span later on the same timeline), the sum of |estimated -
    true distance| divided by the sum of the true distances. 0 for a perfect
    track, 1 for a frozen pose, 9 for dead-reckoning at 10x the speed; NaN
    without a baseline that has ground truth at both ends."""
    segments, seg = [], []
    for o in odom:  # a stamp going back (bag loop) starts a new timeline
        if seg and o[1] < seg[-1][1]:
            segments.append(seg)
            seg = []
        seg.append(o)
    segments.append(seg)
    err = true = 0.0
    for seg in segments:
        j = 0
        for a in seg:
            while j < len(seg) and seg[j][1] < a[1] + span:
                j += 1
            if j == len(seg):
                break
            ka, kb = round(a[1], 1), round(seg[j][1], 1)
            if ka in gt and kb in gt:
                d_true = math.dist(gt[ka], gt[kb])
                err += abs(math.dist(a[2:5], seg[j][2:5]) - d_true)
                true += d_true
    return err / true if true > 0 else float("nan")


def restart_consistency(odom, gt, kill_wall, restart_wall):
    """The step across the front end outage (estimated vs true distance), the
    largest per-frame step error and the relative motion error
    (motion_error) after it; "looped" when the bag wrapped during the outage
    (the filter then reset instead of bridging the gap)."""
    before = [o for o in odom if o[0] <= kill_wall]
    after = [o for o in odom if o[0] > restart_wall]
    if not before or not after:
        return {}
    a, b = before[-1], after[0]
    out = {"after_max_abs_err": max(step_errors(after, gt) or [float("nan")]),
           "after_motion_error": motion_error(after, gt)}
    if b[1] < a[1]:
        out["looped"] = True
    elif round(a[1], 1) in gt and round(b[1], 1) in gt:
        out["gap"] = (b[1] - a[1], math.dist(a[2:5], b[2:5]), math.dist(gt[round(a[1], 1)], gt[round(b[1], 1)]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--bag-len", type=float, required=True)
    ap.add_argument("--link", required=True)
    ap.add_argument("--link-kind", required=True)
    ap.add_argument("--kill-wall", type=float, required=True)
    ap.add_argument("--restart-wall", type=float, required=True)
    ap.add_argument("--manager-pids", nargs=2, required=True)
    ap.add_argument("--bag", help="the played bag: its ground truth gives the pose error across the restart")
    ap.add_argument("--max-motion-error", type=float, default=0.25,
                    help="largest motion error after the restart, relative to the true motion over 1 s baselines "
                         "(motion_error: a frozen pose scores 1, dead-reckoning at twice the speed 1)")
    a = ap.parse_args()
    ph = [json.load(open("%s/phase%d.json" % (a.out, i))) for i in (1, 2, 3)]
    ok = [True]

    def check(cond, text):
        ok[0] &= bool(cond)
        print("  [%s] %s" % ("PASS" if cond else "FAIL", text))

    print("two_hosts: link = %s" % a.link)
    if os.path.exists(a.out + "/ping.txt"):
        print("  ping over the link: " + " / ".join(l.strip() for l in open(a.out + "/ping.txt")))
    links = link_stats(a.out, a.link_kind)
    for d, s in sorted(links.items()):
        print("  link %s: %d packets, %d dropped (%.2f %%)" % (d, s["packets_in"], s["packets_dropped"],
                                                             s["loss_measured_pct"]))
    for i, p in enumerate(ph, 1):
        be, fe = status(p, "eskf"), status(p, "frontend")
        print("phase %d: %d odometry (%.1f Hz), max gap %.2f s, max step %.3f m, stamp jumps %d" % (
            i, p["odom_count"], p.get("odom_rate_hz", 0), p.get("max_gap_s", 0), p.get("max_step_m", 0),
            len(p.get("stamp_jumps", []))))
        print("   back end : received %s accepted %s processed %s dropped %s stale %s rejected %s time_jumps %s "
              "resets %s filter_errors %s" % tuple(be.get(k, "?") for k in (
                  "frames_received", "frames_accepted", "frames_processed", "frames_dropped",
                  "frames_stale_after_reset", "rejected_total", "time_jumps", "resets", "filter_errors")))
        print("   front end: processed %s rejected %s dropped %s time resets %s" % tuple(
            fe.get(k, "?") for k in ("frames processed", "rejected total", "dropped total", "time resets")))

    frames = a.bag_len * 10
    p1, p2, p3 = ph
    be1, be2, be3 = status(p1, "eskf"), status(p2, "eskf"), status(p3, "eskf")
    fe1 = status(p1, "frontend")
    # Phase 1: running across the link, losses reported.
    check(p1["odom_count"] >= 0.3 * frames,
          "phase 1: odometry for >= 30 %% of the %d frames across the link (%d)" % (frames, p1["odom_count"]))
    check(bool(be1) and bool(fe1), "phase 1: diagnostics of both hosts seen on the server")
    if a.link_kind in ("netem", "tun", "iptables"):
        dropped = sum(s["packets_dropped"] for s in links.values())
        check(dropped > 0, "link losses counted: %d packets dropped by the link" % dropped)
    sent, got = num(fe1, "frames processed"), num(be1, "frames_received")
    if not (math.isnan(sent) or math.isnan(got)):
        # TCPROS retransmits lost segments, so link loss shows up as latency;
        # whole messages are lost only where a queue overflows.
        print("  phase 1 messages: front end published %d landmark frames, back end received %d (%d lost in "
              "transit), dropped %s in its newest-wins mailbox (CPU-bound), processed %s" % (
                  sent, got, sent - got, be1.get("frames_dropped", "?"), be1.get("frames_processed", "?")))
    # Phase 2: replay = time jump; front end restart recovers, back end untouched.
    check(num(be2, "time_jumps") >= num(be1, "time_jumps") + 1, "phase 2: replay detected as a time jump (filter reset)")
    after = [o for o in p2["odom"] if o[0] > a.restart_wall]
    before = [o for o in p2["odom"] if o[0] <= a.kill_wall]
    if after:
        rec = after[0][0] - a.restart_wall
        outage = after[0][0] - (before[-1][0] if before else a.kill_wall)
        print("  phase 2: front end killed at %.1f s, restart issued at %.1f s, first odometry after it at %.1f s: "
              "recovery %.1f s after the restart command, odometry gap %.1f s" % (
                  a.kill_wall, a.restart_wall, after[0][0], rec, outage))
    gt = ground_truth(a.bag) if a.bag else {}
    rc = restart_consistency(p2["odom"], gt, a.kill_wall, a.restart_wall) if gt else {}
    if rc:
        # Informational: how well the back end bridged the outage (constant-
        # velocity prediction over the gap, then re-association), next to the
        # per-frame figure of the undisturbed phase 1.
        base = max(step_errors(p1["odom"], gt) or [float("nan")])
        base_motion = motion_error(p1["odom"], gt)
        if "gap" in rc:
            print("  phase 2: across the %.1f s without frames the pose moved %.3f m, ground truth %.3f m" % rc["gap"])
        elif rc.get("looped"):
            print("  phase 2: the bag looped during the outage (filter reset, no gap to bridge)")
        print("  phase 2: after the restart the per-frame step error was at most %.3f m (phase 1, undisturbed: "
              "%.3f m), the motion error over %.0f s %.3f of the true motion (phase 1: %.3f)" % (
                  rc["after_max_abs_err"], base, MOTION_SPAN_S, rc["after_motion_error"], base_motion))
    if rc:
        # Recovery means tracking again, not just publishing: a filter that
        # lost its landmarks dead-reckons at whatever velocity it had.
        check(rc["after_motion_error"] <= a.max_motion_error,
              "phase 2: after the restart the odometry follows the ground truth (motion error %.3f of the true "
              "motion <= %.2f)" % (rc["after_motion_error"], a.max_motion_error))
    check(len(before) >= 10, "phase 2: the system ran before the front end was killed (%d odometry messages)"
          % len(before))
    check(len(after) >= 10, "phase 2: odometry resumed after the front end restart (%d messages)" % len(after))
    check(a.manager_pids[0] != "" and a.manager_pids[0] == a.manager_pids[1],
          "back end never restarted (manager pid %s at start, %s at end)" % tuple(a.manager_pids))
    # Phase 3: clean reset at the loop point.
    check(num(be3, "time_jumps") >= num(be2, "time_jumps") + 1, "phase 3: the loop point reset the filter")
    j3 = p3.get("stamp_jumps", [])
    check(len(j3) >= 1 and all(j["first_position_norm"] < 0.05 for j in j3),
          "phase 3: first pose after each loop at the origin (%s)" % ", ".join(
              "%.3f m" % j["first_position_norm"] for j in j3))
    tail = [o for o in p3["odom"] if j3 and o[0] > j3[-1]["wall"] + 2]
    check(len(tail) >= 10, "phase 3: odometry continues after the loop (%d messages)" % len(tail))
    check(all(all(math.isfinite(v) for v in o[1:]) for p in ph for o in p["odom"]), "no NaN/Inf in any odometry")
    check(num(be3, "filter_errors") == 0, "no filter errors (%s)" % be3.get("last_filter_error", ""))
    print("VERDICT: %s" % ("PASS" if ok[0] else "FAIL"))
    return 0 if ok[0] else 1


if __name__ == "__main__":
    sys.exit(main())
