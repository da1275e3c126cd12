#!/usr/bin/env python3
"""Back-end comparison (docs/BACKENDS.md): every SLAM back end on the same
recorded landmark streams, Kock 2021's metrics per time step and per landmark,
a Markdown table and PNG plots.

    compare_backends.py [--streams S1,S2,...] [--variants eskf,seif,...] [--set KEY=VALUE ...]
                        [--out DIR] [--frames N] [--truth-offset S] [--refine] [--plot-only]

A stream is a file written by tools/eval/accuracy.py (.data/sim/*_stream.txt),
or `synthetic-orbit` (compare_backends' ROS-free version of Kock's scenario).
A variant is `LABEL` (= an algorithm: eskf, seif, graph, fastslam2) or
`LABEL=ALGORITHM[:key=value:...]`, e.g. `seif_exact=seif:seif_max_active_landmarks=0`.
--set applies to every run (e.g. max_landmarks=1000 max_new_landmarks=50 for
Kock's pool of 1000 and 50 additions per step). The truth clock offset of a
simulated stream is read from the bag next to it (accuracy.py's time_offset)
or given by --truth-offset; `synthetic-orbit`'s truth is on its frames' clock
(offset 0 whatever --truth-offset says).
--refine: the eskf and graph runs also batch-refine their graph at the end
(the ES-EKF's run recorded as a graph, Graph SLAM's own); DIR/refined.md
compares the trajectory and map before and after on the same frames and
landmarks.
Each run: `compare_backends STREAM --algorithm A --label STREAM__LABEL --out DIR ...`
(DIR/STREAM__LABEL_steps.csv, _landmarks.csv, _summary.txt); then DIR/table.md
and DIR/<stream>_errors.png, _nees.png, _time.png, _landmarks.png.
Needs a built workspace (source devel/setup.bash) and python3-matplotlib.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CHI2_3_95 = 7.81  # 95 % quantile of chi^2(3): the consistency bound of a 3-dof NEES


def tool_path():
    for p in (os.path.join(REPO, ".ws", "devel", "lib", "hapi_eskf", "compare_backends"),
              os.path.join(REPO, "build", "hapi_eskf", "tools", "compare_backends")):
        if os.path.exists(p):
            return p
    sys.exit("compare_backends not built (catkin: make -C .ws/build compare_backends)")


def stream_name(stream):
    if stream == "synthetic-orbit":
        return "synthetic_orbit"
    return os.path.basename(stream).replace("_stream.txt", "")


def truth_offset(stream, given=None):
    if stream == "synthetic-orbit":
        return 0.0  # generated with its truth on the frames' clock
    if given is not None:
        return given
    bag = stream.replace("_stream.txt", ".bag")
    if not os.path.exists(bag):
        return 0.0
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import accuracy  # noqa: E402 (needs rosbag)
    return accuracy.time_offset(bag)


def parse_variant(v):
    label, _, spec = v.partition("=")
    parts = (spec or label).split(":")
    return label, parts[0], parts[1:]


REFINABLE = ("eskf", "graph")  # the back ends with a graph to refine (compare_backends --refine)


def run(stream, variant, settings, out, frames, offset=None, refine=False, tool=None):
    label, algorithm, extra = parse_variant(variant)
    src = "--synthetic-orbit" if stream == "synthetic-orbit" else stream
    cmd = [tool or tool_path(), src, "--algorithm", algorithm, "--label", stream_name(stream) + "__" + label,
           "--out", out,
           "--truth-offset", repr(truth_offset(stream, offset))] + (["--frames", str(frames)] if frames else []) + \
        (["--refine"] if refine and algorithm in REFINABLE else []) + list(settings) + extra
    print("$ " + " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) if k != "status" else r[k] for r in rows] for k in rows[0]} if rows else {}


def read_summary(path):
    out = {}
    with open(path) as f:
        for line in f:
            k, _, v = line.strip().partition(" ")
            out[k] = v
    return out


def summaries(streams, labels, out):
    """(stream name, label, summary) of every completed run, in table order."""
    for s in streams:
        for lab in labels:
            p = os.path.join(out, f"{stream_name(s)}__{lab}_summary.txt")
            if os.path.exists(p):
                yield stream_name(s), lab, read_summary(p)


def table(streams, labels, out):
    lines = ["| stream | back end | MAE position mm | MAE rotation rad | MAE map mm | NEES position | NEES rotation "
             "| NEES map | ms/frame mean / p99 | frames (errors) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for name, lab, m in summaries(streams, labels, out):
        def f(key, scale=1.0, fmt="%.2f"):
            x = float(m[key]) * scale
            return "n/a" if math.isnan(x) else fmt % x
        lines.append(f"| {name} | {lab} | {f('mae_pos_m', 1e3)} | {f('mae_rot_rad', 1, '%.4f')} | "
                     f"{f('mae_map_m', 1e3)} | {f('mean_nees_pos')} | {f('mean_nees_rot')} | "
                     f"{f('mean_nees_map')} | {f('ms_mean', 1, '%.1f')} / {f('ms_p99', 1, '%.1f')} | "
                     f"{m['frames']} ({m['errors']}) |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "table.md"), "w") as fh:
        fh.write(text)
    print(text)


def refined_table(streams, labels, out):
    """After-the-fact figures of the runs made with --refine: every recorded
    frame and every landmark of the graph, before and after the batch."""
    lines = ["| stream | back end | frames | landmarks | MAE position mm before / after | MAE rotation rad "
             "before / after | MAE map mm before / after | refinement s |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for name, lab, m in summaries(streams, labels, out):
        if "refine_s" not in m:
            continue

        def ba(key, scale=1.0, fmt="%.2f"):
            return " / ".join(fmt % (float(m[f"refine_{w}_{key}"]) * scale) for w in ("before", "after"))
        lines.append(f"| {name} | {lab} | {m['refine_frames']} | {m['refine_landmarks']} | "
                     f"{ba('pos_m', 1e3)} | {ba('rot_rad', 1, '%.4f')} | {ba('map_m', 1e3)} | "
                     f"{float(m['refine_s']):.1f} |")
    if len(lines) == 2:
        return
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "refined.md"), "w") as fh:
        fh.write(text)
    print(text)


def plots(stream, labels, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    name = stream_name(stream)
    runs = {}
    for lab in labels:
        p = os.path.join(out, f"{name}__{lab}_steps.csv")
        if os.path.exists(os.path.join(out, f"{name}__{lab}_summary.txt")):  # the run completed
            runs[lab] = (read_csv(p), read_csv(os.path.join(out, f"{name}__{lab}_landmarks.csv")))
    if not runs:
        return
    panels = [("pos_err", "position error [mm]", 1e3), ("rot_err", "rotation error [rad]", 1.0),
              ("map_mae", "map MAE [mm]", 1e3)]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    for i, (key, title, scale) in enumerate(panels):
        for lab, (st, _) in runs.items():
            ax[i].plot(st["step"], [x * scale for x in st[key]], label=lab, lw=0.8)
        ax[i].set_title(title)
        ax[i].set_xlabel("step")
        ax[i].legend()
    fig.suptitle(f"{name}: absolute errors per time step")
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"{name}_errors.png"), dpi=90)
    plt.close(fig)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    for i, (key, title) in enumerate([("nees_pos", "position NEES"), ("nees_rot", "rotation NEES"),
                                      ("map_nees", "map NEES (mean over landmarks)")]):
        for lab, (st, _) in runs.items():
            ax[i].semilogy(st["step"], [max(x, 1e-3) for x in st[key]], label=lab, lw=0.8)
        ax[i].axhline(CHI2_3_95, color="k", ls="--", lw=0.8, label="chi2(3) 95 % = 7.81")
        ax[i].set_title(title)
        ax[i].set_xlabel("step")
        ax[i].legend()
    fig.suptitle(f"{name}: NEES per time step")
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"{name}_nees.png"), dpi=90)
    plt.close(fig)
    fig, ax = plt.subplots(1, 2, figsize=(12, 4))
    for lab, (st, _) in runs.items():
        ax[0].plot(st["step"], st["t_total_ms"], label=lab, lw=0.8)
        ax[1].plot(st["step"], st["landmarks"], label=lab, lw=0.8)
    ax[0].set_title("computation time per iteration [ms] (ratios only unless measured on a quiet machine)")
    ax[1].set_title("landmarks in the pool")
    for a in ax:
        a.set_xlabel("step")
        a.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"{name}_time.png"), dpi=90)
    plt.close(fig)
    fig, ax = plt.subplots(1, 2, figsize=(12, 4))
    for lab, (_, lm) in runs.items():
        if not lm:
            continue
        err = sorted(x * 1e3 for x in lm["err"])
        ax[0].plot(err, [(i + 1) / len(err) for i in range(len(err))], label=lab)
        ax[1].scatter(lm["times_observed"], lm["nees"], s=3, label=lab)
    ax[0].set_title("final map: per-landmark error CDF [mm]")
    ax[1].set_yscale("log")
    ax[1].axhline(CHI2_3_95, color="k", ls="--", lw=0.8)
    ax[1].set_title("final map: per-landmark NEES vs times observed")
    for a in ax:
        a.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"{name}_landmarks.png"), dpi=90)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--streams", default="synthetic-orbit," + os.path.join(REPO, ".data", "sim",
                                                                           "globe_orbit_s1_50s_stream.txt"))
    ap.add_argument("--variants", default="eskf,seif")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--out", default=os.path.join(REPO, ".ws", "backends"))
    ap.add_argument("--frames", type=int, default=0)
    ap.add_argument("--truth-offset", type=float, default=None,
                    help="t_truth = t_frame + S for every recorded stream (default: from the bag next to the "
                         "stream, else 0; synthetic-orbit: always 0)")
    ap.add_argument("--refine", action="store_true",
                    help="eskf and graph runs: batch-refine the run's graph at the end (DIR/refined.md)")
    ap.add_argument("--plot-only", action="store_true", help="tables and plots of the runs already in --out")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    streams = [s for s in a.streams.split(",") if s]
    variants = [v for v in a.variants.split(",") if v]
    if not a.plot_only:
        for s in streams:
            for v in variants:
                run(s, v, a.set, a.out, a.frames, a.truth_offset, a.refine)
    labels = [parse_variant(v)[0] for v in variants]
    table(streams, labels, a.out)
    refined_table(streams, labels, a.out)
    for s in streams:
        plots(s, labels, a.out)


if __name__ == "__main__":
    main()
