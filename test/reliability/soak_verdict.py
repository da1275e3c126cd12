#!/usr/bin/python3
"""Verdict of soak.sh from its samples.csv (manager RSS) and probe.json.

  soak_verdict.py --out DIR --warmup 120 --max-growth 20 [--max-gap 2] [--full-pool 1 --max-landmarks 2000]

Always: a table of RSS and odometry per sample, RSS growth and least-squares
slope after the warm-up (both bounded by --max-growth MiB over the run), and
odometry throughout (no silence longer than --max-gap s). With --full-pool 1 (a long non-repeating bag played
once): the back end's map stays at the pool size (landmarks ==
--max-landmarks) in every diagnostics sample after the warm-up, the slope
of the per-frame filter time (t_total_ms) is reported in ms per minute
(informational: timed figures depend on the machine), and the frame
accounting must close with no loss other than the newest-wins mailbox
(accepted == processed + dropped + stale + failed, rejected and
filter_errors 0).
"""
import argparse
import csv
import json
import sys


def slope_per_min(pts):
    n = len(pts)
    if n < 2:
        return 0.0
    mt = sum(p[0] for p in pts) / n
    mv = sum(p[1] for p in pts) / n
    den = sum((p[0] - mt) ** 2 for p in pts) or 1.0
    return sum((p[0] - mt) * (p[1] - mv) for p in pts) / den * 60.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--warmup", type=float, default=120.0)
    ap.add_argument("--max-growth", type=float, default=20.0)
    ap.add_argument("--full-pool", type=int, default=0)
    ap.add_argument("--max-landmarks", type=int, default=0)
    ap.add_argument("--max-gap", type=float, default=2.0,
                    help="[s, wall] longest odometry silence: 20 frames of the 10 Hz stream (a bag loop's reset "
                         "takes a few tenths of a second)")
    a = ap.parse_args()
    rows = [(float(r["t_s"]), float(r["rss_mib"]), int(r["threads"])) for r in csv.DictReader(open(a.out + "/samples.csv"))]
    probe = json.load(open(a.out + "/probe.json"))
    odom_t = [o[0] for o in probe["odom"]]
    print("%8s %10s %8s %12s" % ("t [s]", "RSS [MiB]", "threads", "odom/period"))
    prev = None
    for t, rss, thr in rows:
        n = sum(1 for x in odom_t if (prev if prev is not None else -1e9) < x <= t)
        print("%8.0f %10.1f %8d %12d" % (t, rss, thr, n))
        prev = t
    after = [r for r in rows if r[0] >= a.warmup]
    ok = len(after) >= 2
    if ok:
        slope = slope_per_min([(r[0], r[1]) for r in after])
        growth = after[-1][1] - after[0][1]
        print("after %.0f s warm-up: RSS %.1f -> %.1f MiB (%+.1f MiB), slope %+.2f MiB/min, peak %.1f MiB" % (
            a.warmup, after[0][1], after[-1][1], growth, slope, max(r[1] for r in rows)))
        ok = growth <= a.max_growth and slope * (rows[-1][0] - a.warmup) / 60.0 <= a.max_growth
    else:
        print("fewer than 2 RSS samples after the %.0f s warm-up: growth not judged" % a.warmup)
    be = {}
    for name, st in probe["diagnostics"].items():
        if "eskf" in name and name.endswith("filter"):
            be = st["values"]
    get = lambda k: float(be.get(k, "nan") or "nan")  # noqa: E731
    print("odometry: %d messages (%.1f Hz), max gap %.2f s; back end: received %s accepted %s processed %s dropped %s "
          "stale %s failed %s rejected %s time_jumps %s filter_errors %s" % (
              probe["odom_count"], probe.get("odom_rate_hz", 0), probe.get("max_gap_s", 0),
              *(be.get(k, "?") for k in ("frames_received", "frames_accepted", "frames_processed", "frames_dropped",
                                         "frames_stale_after_reset", "frames_failed", "rejected_total", "time_jumps",
                                         "filter_errors"))))
    alive = probe["odom_count"] > 0 and probe.get("max_gap_s", 1e9) <= a.max_gap
    full = True
    if a.full_pool:
        series = [(t, v) for t, name, v in probe.get("diagnostics_series", [])
                  if "eskf" in name and name.endswith("filter") and t >= a.warmup]
        sizes = [int(float(v.get("landmarks", "0"))) for _, v in series]
        at_pool = sum(1 for k in sizes if k == a.max_landmarks)
        times = [(t, float(v["t_total_ms"])) for t, v in series if float(v.get("frames_in_period", "0")) > 0]
        print("full pool: map size %s..%s in %d diagnostics samples after the warm-up, %d at the pool size %d" % (
            min(sizes) if sizes else "?", max(sizes) if sizes else "?", len(sizes), at_pool, a.max_landmarks))
        if times:
            print("per-frame filter time after the warm-up: mean %.2f ms, slope %+.3f ms/min (first %.2f, last %.2f ms)"
                  % (sum(v for _, v in times) / len(times), slope_per_min(times), times[0][1], times[-1][1]))
        closes = get("frames_accepted") == get("frames_processed") + get("frames_dropped") + \
            get("frames_stale_after_reset") + get("frames_failed")
        print("frame accounting closes (accepted = processed + dropped + stale + failed): %s; dropped %.0f of %.0f "
              "(newest-wins mailbox)" % ("yes" if closes else "no", get("frames_dropped"), get("frames_accepted")))
        full = bool(sizes) and at_pool == len(sizes) and get("rejected_total") == 0 and get("filter_errors") == 0 \
            and get("time_jumps") == 0
        full = full and closes
    print("VERDICT: %s (bounded growth <= %.0f MiB after warm-up: %s; odometry throughout, no gap > %.1f s: %s%s)" % (
        "PASS" if ok and alive and full else "FAIL", a.max_growth, "yes" if ok else "no", a.max_gap,
        "yes" if alive else "no",
        "; map at the pool size, accounting closed: %s" % ("yes" if full else "no") if a.full_pool else ""))
    return 0 if ok and alive and full else 1


if __name__ == "__main__":
    sys.exit(main())
