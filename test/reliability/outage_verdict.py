#!/usr/bin/python3
"""Verdict of two_hosts.sh's outage scenario (HAPI_SCENARIO=outage).

  outage_verdict.py --probe outage.json --down-wall 8.1 --up-wall 38.2 \
      --manager-pids PID0 PID1 --rss-kib S0 R0 S1 R1 S2 R2 [--link TEXT] [--link-json link.json]

The link between robot and server was out of service from --down-wall to
--up-wall (seconds since the probe started). Checks, each printed with its
figures:
  * odometry before the outage, and again within --max-recovery s after it;
  * the back end relocalised against its map (diagnostics relocalisations)
    rather than dead-reckoning through the gap (its input re-subscriptions
    during the silence are printed);
  * nothing piled up: after the first --settle s past the return, every
    odometry message is at most --max-lag s behind the bag's clock (a queue
    of old frames would show as a growing lag), and the old frames that TCP
    delivered late are counted. Where the probe recorded one of the
    player's own topics (ros_probe.py --input), the lag is counted from that
    input's arrival, so a player that the machine stalled (its frames sent
    late, all at once) is not taken for a backlog of the system; the
    player's own largest lag is printed;
  * memory flat: neither manager's RSS grew by more than --max-rss-growth
    MiB while the link was down (nothing accumulates for the absent peer),
    nor the robot's over the whole run; the server's growth after the return
    is reported with its map size (its covariance pages are touched as the
    map grows: docs/RELIABILITY.md "Soak");
  * the back end's manager is the same process at the start and the end.
Exit 0 when every check passes, 1 otherwise.
"""
import argparse
import json
import sys


def player_lags(inputs, walls, before_wall):
    """How late the player was delivering the bag at each wall time of
    `walls`: the lag of its newest message by then ([wall, stamp] of
    ros_probe.py --input) against its least delayed message before
    before_wall. Zeros without such a record."""
    early = [i for i in inputs if i[0] < before_wall]
    if not early:
        return [0.0] * len(walls)
    offset = min(i[0] - i[1] for i in early)
    out, k, newest = [], 0, None
    for w in walls:  # walls ascending, inputs in arrival order
        while k < len(inputs) and inputs[k][0] <= w:
            newest = inputs[k]
            k += 1
        out.append(max(0.0, (newest[0] - newest[1]) - offset) if newest else 0.0)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--probe", required=True)
    ap.add_argument("--down-wall", type=float, required=True)
    ap.add_argument("--up-wall", type=float, required=True)
    ap.add_argument("--manager-pids", nargs=2, required=True)
    ap.add_argument("--rss-kib", nargs=6, type=int, required=True,
                    help="server, robot manager RSS before the outage, at its end, after the run")
    ap.add_argument("--link", default="")
    ap.add_argument("--link-json", default="")
    ap.add_argument("--max-recovery", type=float, default=20.0)
    ap.add_argument("--settle", type=float, default=5.0)
    ap.add_argument("--max-lag", type=float, default=1.0)
    ap.add_argument("--max-rss-growth", type=float, default=20.0)
    a = ap.parse_args()
    p = json.load(open(a.probe))
    odom = p.get("odom", [])  # [wall, stamp, x, y, z]
    ok = True

    def check(cond, text):
        nonlocal ok
        ok = ok and cond
        print("[%s] %s" % ("PASS" if cond else "FAIL", text))

    print("link: %s; down %.1f s -> up %.1f s (%.1f s)" % (a.link, a.down_wall, a.up_wall, a.up_wall - a.down_wall))
    if a.link_json:
        try:
            for name, d in json.load(open(a.link_json))["directions"].items():
                print("  %s: %d packets, %d lost to the 5 %% loss, %d lost to the outage"
                      % (name, d["packets_in"], d["packets_dropped"], d.get("packets_dropped_outage", 0)))
        except (OSError, ValueError, KeyError):
            pass
    before = [o for o in odom if o[0] < a.down_wall]
    after = [o for o in odom if o[0] > a.up_wall]
    check(len(before) > 0, "odometry before the outage: %d messages" % len(before))
    recovery = after[0][0] - a.up_wall if after else float("inf")
    check(recovery <= a.max_recovery, "odometry again %.1f s after the link returned (<= %.0f s); %d messages after it"
          % (recovery, a.max_recovery, len(after)))

    filt = {}
    for name, st in p.get("diagnostics", {}).items():
        if name.endswith(": filter") and "eskf" in name:
            filt = st.get("values", {})
    relocalisations = int(filt.get("relocalisations", "0") or 0)
    check(relocalisations >= 1, "relocalised against the map after the gap: relocalisations %d, resets %s, "
          "frames_relocalising %s, filter_errors %s" % (relocalisations, filt.get("resets"),
                                                        filt.get("frames_relocalising"), filt.get("filter_errors")))
    # Informational: how often the back end re-subscribed its inputs while
    # they were silent (~input_timeout; watched_subscriber.hpp).
    print("  input re-subscriptions: %s" % filt.get("input_resubscriptions", "n/a"))

    # The bag clock against the wall clock, from the frames before the outage
    # (the player runs at rate 1): lag = how far a message is behind it.
    if before and after:
        offset = min(o[0] - o[1] for o in before)  # wall - stamp of the least delayed frame
        late = [o for o in after if o[1] < before[-1][1] + (a.up_wall - a.down_wall) - 1.0]
        settled = [o for o in after if o[0] > a.up_wall + a.settle]
        player_lag = player_lags(p.get("input", []), [o[0] for o in settled], a.down_wall)
        lags = [(o[0] - o[1]) - offset - pl for o, pl in zip(settled, player_lag)]
        max_lag = max(lags) if lags else float("inf")
        print("  old frames delivered after the return (sent before it): %d" % len(late))
        if p.get("input"):
            print("  the player's own largest lag over that span: %.2f s (subtracted)" % max(player_lag, default=0.0))
        check(bool(lags) and max_lag <= a.max_lag,
              "no backlog: %d messages from %.0f s after the return, largest lag behind the bag clock %.2f s "
              "(<= %.1f s)" % (len(lags), a.settle, max_lag, a.max_lag))
    else:
        check(False, "no backlog: not judged (no odometry on one side of the outage)")

    s0, r0, s1, r1, s2, r2 = [v / 1024.0 for v in a.rss_kib]
    check(s0 > 0 and s1 - s0 <= a.max_rss_growth,
          "server manager RSS %.1f MiB before the outage, %.1f at its end (growth <= %.0f MiB); %.1f after the run "
          "with %s landmarks in the map" % (s0, s1, a.max_rss_growth, s2, filt.get("landmarks", "?")))
    check(r0 > 0 and max(r1, r2) - r0 <= a.max_rss_growth,
          "robot manager RSS %.1f MiB before the outage, %.1f at its end, %.1f after the run (growth <= %.0f MiB)"
          % (r0, r1, r2, a.max_rss_growth))
    check(a.manager_pids[0] == a.manager_pids[1] and a.manager_pids[0] != "",
          "back end manager pid %s at the start and %s at the end" % tuple(a.manager_pids))
    print("VERDICT: %s" % ("PASS" if ok else "FAIL"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
