#!/usr/bin/python3
"""Full-pool soak of the filter alone, through the ROS-free replay path
(docs/RELIABILITY.md "Full-pool soak"): eskf_replay on a long frame stream
(dump_frames.py of the front end's landmarks from a `make_globe_bag --orbit
spiral` bag, or the synthetic orbit, which needs no bag), e.g. with the CUDA
backend on a GPU machine without ROS.

  replay_soak.py --replay PATH/eskf_replay --stream frames.txt [--warmup 120] [--out PREFIX] [key=value ...]
  replay_soak.py --replay PATH/eskf_replay --stream=--synthetic-orbit=3,frames=6100,points=30000 ...

key=value pairs go to eskf_replay (backend=cuda, max_landmarks=...). Reports
the map size against the pool size after the warm-up (stream time), the
per-frame filter time's slope [ms per minute] and its p50 in the first and
last minute, the process's RSS after the warm-up (sampled from /proc every
10 frames: first and last value, slope per minute of stream time) and its
peak RSS. Exit 0 when every frame after the warm-up has the map at the pool
size and no frame failed, else 1.
"""
import argparse
import re
import resource
import subprocess
import sys

from soak_verdict import slope_per_min  # the least-squares slope of the ROS soak's verdict

LINE = re.compile(r"^t=([-0-9.]+) st=(\S+) .* K=(\d+) .* ms=([0-9.]+)")


def rss_mib(pid):
    """Resident set size of process pid [MiB] from /proc, None when gone."""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def p50(v):
    v = sorted(v)
    return v[len(v) // 2] if v else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--replay", required=True)
    ap.add_argument("--stream", required=True)
    ap.add_argument("--warmup", type=float, default=120.0, help="stream seconds before the pool must be full")
    ap.add_argument("--out", default="", help="eskf_replay --out PREFIX")
    a, settings = ap.parse_known_args()
    cmd = [a.replay, a.stream, "--verbose"] + (["--out", a.out] if a.out else []) + settings
    print("running: %s" % " ".join(cmd))
    # Read as the child writes: a pipe delivers its lines in blocks, so an
    # RSS sample belongs to the last frame read, within one block of lines.
    run = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    frames = []  # (t, status, K, ms)
    rss = []  # (stream t, MiB)
    pool = None
    lines = []
    for line in run.stdout:
        line = line.rstrip("\n")
        lines.append(line)
        m = LINE.match(line)
        if m:
            frames.append((float(m.group(1)), m.group(2), int(m.group(3)), float(m.group(4))))
            if len(frames) % 10 == 0:
                mib = rss_mib(run.pid)
                if mib is not None:
                    rss.append((frames[-1][0], mib))
        elif "max_landmarks" in line and pool is None:
            mm = re.search(r"max_landmarks[ =:]+(\d+)", line)
            if mm:
                pool = int(mm.group(1))
    for kv in settings:
        if kv.startswith("max_landmarks="):
            pool = int(kv.split("=", 1)[1])
    pool = pool or 2000
    run.wait()
    print("\n".join(lines[-6:]))
    if not frames:
        print("no per-frame lines from eskf_replay (exit %d)" % run.returncode)
        return 1
    t0 = frames[0][0]
    after = [f for f in frames if f[0] - t0 >= a.warmup]
    failed = [f for f in frames if f[1] not in ("ok", "kOk", "OK")]
    at_pool = sum(1 for f in after if f[2] == pool)
    times = [(f[0] - t0, f[3]) for f in after]
    first = [ms for t, ms in times if t < a.warmup + 60.0]
    last = [ms for t, ms in times if t >= times[-1][0] - 60.0] if times else []
    peak_mib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
    print("frames %d (%.0f s of stream), after the %.0f s warm-up %d, of which %d with the map at the pool size %d; "
          "frames not ok %d" % (len(frames), frames[-1][0] - t0, a.warmup, len(after), at_pool, pool, len(failed)))
    if times:
        print("per-frame filter time after the warm-up: slope %+.3f ms/min, p50 first minute %.2f ms, last minute %.2f ms"
              % (slope_per_min(times), p50(first), p50(last)))
    rss_after = [(t - t0, mib) for t, mib in rss if t - t0 >= a.warmup]
    if len(rss_after) >= 2:
        print("RSS after the warm-up: %.1f -> %.1f MiB, slope %+.3f MiB/min of stream (%d samples)"
              % (rss_after[0][1], rss_after[-1][1], slope_per_min(rss_after), len(rss_after)))
    print("peak RSS of eskf_replay: %.1f MiB" % peak_mib)
    ok = run.returncode == 0 and bool(after) and at_pool == len(after) and not failed
    print("VERDICT: %s" % ("PASS" if ok else "FAIL"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
