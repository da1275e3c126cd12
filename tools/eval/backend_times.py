#!/usr/bin/env python3
"""Time-per-frame benchmark of every SLAM back end (docs/BACKENDS.md "Time
per frame at pool 1000"): runs the comparison harness (compare_backends.py)
on the synthetic orbit at Kock's full pool for every back end and compares
each back end's ms per frame (mean and p99) with its recorded figure in
tools/eval/backend_times.json. A back end slower than its record by more
than the margin is flagged and the exit status is 1. Part of changing a back
end: run it before and after, on a quiet machine (wall-clock figures of a
loaded machine say nothing), and record the new figures with --record.

    backend_times.py [--margin 0.25] [--out DIR] [--frames N] [--tool PATH] [--record]

--record writes this run's figures into the file with the commit (git
describe of the checkout, "-dirty" if it has changes), machine, date and load
average; commit that file with the change. Not a test: speed figures never
fail the ctest suite.
"""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare_backends as cb  # noqa: E402

RECORD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "backend_times.json")
VARIANTS = ["eskf", "seif", "graph", "fastslam2"]
KEYS = ("ms_mean", "ms_p99")


def machine():
    model = ""
    try:
        with open("/proc/cpuinfo") as f:
            model = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), "")
    except OSError:
        pass
    return f"{platform.node()}, {os.cpu_count()} cores, {model}".strip(", ")


def commit():
    def git(*args):
        return subprocess.run(["git", "-C", cb.REPO] + list(args), capture_output=True, text=True).stdout.strip()
    return git("rev-parse", "--short", "HEAD") + ("-dirty" if git("status", "--porcelain", "-uno") else "")


def verdict(over, frames):
    if frames:
        return "not compared (--frames)"
    return "SLOWER: " + ", ".join(over) if over else "ok"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--margin", type=float, default=None,
                    help="allowed excess over the record, as a fraction (default: the file's)")
    ap.add_argument("--out", default=os.path.join(cb.REPO, ".ws", "backend_times"))
    ap.add_argument("--frames", type=int, default=0, help="fewer frames (a quick look; not comparable with the record)")
    ap.add_argument("--tool", default=None, help="the compare_backends executable (default: the workspace's)")
    ap.add_argument("--record", action="store_true", help="write this run's figures into " + RECORD)
    a = ap.parse_args()
    with open(RECORD) as f:
        rec = json.load(f)
    margin = rec["margin"] if a.margin is None else a.margin
    os.makedirs(a.out, exist_ok=True)
    load_before = os.getloadavg()[0]
    for v in VARIANTS:
        cb.run(rec["stream"], v, rec["settings"], a.out, a.frames, tool=a.tool)
    measured = {lab: m for _, lab, m in cb.summaries([rec["stream"]], VARIANTS, a.out)}

    print(f"\nload average before the run {load_before:.2f}; margin {margin:.0%}; record: commit "
          f"{rec['commit']}, {rec['machine']}, {rec['date']}")
    print("| back end | ms/frame mean (record) | p99 (record) | MAE position mm | NEES position | verdict |")
    print("| --- | --- | --- | --- | --- | --- |")
    slower = []
    for v in VARIANTS:
        m, r = measured.get(v), rec["backends"].get(v)
        if m is None:
            slower.append(v)
            print(f"| {v} | no result | | | | FAILED TO RUN |")
            continue
        over = [k for k in KEYS if r and a.frames == 0 and float(m[k]) > (1.0 + margin) * r[k]]
        if over:
            slower.append(v)
        print(f"| {v} | {float(m['ms_mean']):.1f} ({r['ms_mean'] if r else '-'}) | "
              f"{float(m['ms_p99']):.1f} ({r['ms_p99'] if r else '-'}) | {1e3 * float(m['mae_pos_m']):.2f} | "
              f"{float(m['mean_nees_pos']):.2f} | {verdict(over, a.frames)} |")
    if a.record:
        if a.frames:
            sys.exit("--record needs the full stream (no --frames)")
        rec.update(commit=commit(), machine=machine(), date=datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"),
                   load_before=round(load_before, 2),
                   backends={v: {k: round(float(measured[v][k]), 1) for k in KEYS} for v in VARIANTS if v in measured})
        with open(RECORD, "w") as f:
            json.dump(rec, f, indent=2)
            f.write("\n")
        print("recorded in " + RECORD)
    if slower:
        print("slower than recorded (or failed): " + ", ".join(slower))
    sys.exit(1 if slower else 0)


if __name__ == "__main__":
    main()
