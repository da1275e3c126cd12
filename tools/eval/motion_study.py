#!/usr/bin/python3
"""The optical-flow study of the skin's surface motion (docs/MOTION.md): for
every scenario it simulates the imaging camera at 40 Hz with its truth,
runs the system offline and OpenCV's optical flow on the same frames, and
scores every method in the form of the thesis's appendix A tables.

  make_sim_bag ... --imaging-rate 40        the scenario and its imaging stream (cached in --data)
  frontend_replay, dump_frames.py            the landmarks (as accuracy.py)
  eskf_replay motion_model=inertial          IMU-rate poses and twists, map snapshots
  imaging_flow_replay                        our image-flow measurement on the imaging frames
  surface_motion_replay                      our surface motion: causal and smoothed
  Farneback, DIS, pyramidal LK (OpenCV)      the baselines, each on every consecutive frame pair

    motion_study.py [--scenarios stage_1,stage_5,...] [--seeds N] [--duration 7] [--data DIR] [--out DIR] [--set KEY=VALUE ...]
                    [--markdown FILE] [--plots DIR]

Per method and scenario (seeds pooled): the image velocity's MAE and SD in
px/frame and in % of the mean true image speed, the median per-frame
relative error over frames faster than 5 mm/s, and the on-surface velocity
error's RMS and 95th percentile in mm/s, all from 1 s after our first
output with status OK (the first landmarks near the ray). Every method is scored per frame
pair against the truth's mean over that interval; ours is also scored at
every output instant (IMU rate), and the smoothed output likewise. A
baseline's px/frame become mm/s through the true skin point and normal (its
best case: ours uses its own depth from the map). --seeds >= 2 adds the
velocity NEES (2 degrees of freedom, in the tangent plane) averaged over
seeds per output instant, with its 95 % band.

Stamps: images and the filter run on the camera clock, the truth on the IMU
clock (t_imu = t_cam + offset, the bag's /ground_truth/calibration).
Needs a built workspace's environment (source devel/setup.bash).
"""
import argparse
import os
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import accuracy  # noqa: E402
import run_analysis  # noqa: E402
import surface_motion_metrics as smm  # noqa: E402
import trajectory_metrics as tm  # noqa: E402

REPO = accuracy.REPO
IMAGING_RATE = 40.0
IMAGING_TOPIC = "/imaging/image_raw"
# name: (scene, trajectory, extra make_sim_bag arguments)
SCENARIOS = {
    "stage_1": ("patch", "stage", ["--stage-speed", "1"]),
    "stage_5": ("patch", "stage", ["--stage-speed", "5"]),
    "stage_10": ("patch", "stage", ["--stage-speed", "10"]),
    "measurement": ("skin", "measurement", []),
    "measurement_subject": ("skin", "measurement_subject", []),
    "handheld": ("skin", "handheld", []),
    "tremor": ("skin", "tremor", []),
    "fast": ("skin", "fast", []),
    "subject": ("skin", "subject", []),
    "rest": ("skin", "rest", []),
}
FRONTEND_ARGS = {"skin": accuracy.FRONTEND_BY_SCENE["skin"], "patch": accuracy.FRONTEND_BY_SCENE["skin"]}
BASELINES = ("farneback", "dis", "lk")
METHODS = BASELINES + ("ours", "ours_smoothed")
# The baselines' flow at the pixel: the median over this window [px] (half
# size); LK's features come from within BASELINE_LK_RADIUS of the pixel.
BASELINE_WINDOW = 15
BASELINE_LK_RADIUS = 60


# ---------------------------------------------------------------- inputs

def scenario_bag(name, seed, duration, data, log):
    scene, traj, extra = SCENARIOS[name]
    stem = f"motion_{name}_s{seed}_{duration:g}s"
    bag = os.path.join(data, stem + ".bag")
    if not os.path.exists(bag):
        st, _ = accuracy.run(["rosrun", "hapi_sim", "make_sim_bag", "--scene", scene, "--trajectory", traj, "--seed",
                     str(seed), "--duration", str(duration), "--imaging-rate", "%g" % IMAGING_RATE,
                     "--output", bag + ".tmp"] + extra, log)
        if st != 0:
            raise RuntimeError(f"make_sim_bag failed for {stem} (see {log})")
        os.replace(bag + ".tmp", bag)
    return stem, bag, scene


def read_imaging(bag):
    """The imaging frames (camera clock), their CameraInfo and the truth."""
    import rosbag
    frames, info, truth = [], None, []
    with rosbag.Bag(bag) as b:
        for topic, m, _ in b.read_messages(topics=[IMAGING_TOPIC, "/imaging/camera_info",
                                                   "/ground_truth/surface_motion"]):
            if topic == IMAGING_TOPIC:
                img = np.frombuffer(m.data, dtype=np.uint8).reshape(m.height, m.step)[:, :m.width]
                frames.append((m.header.stamp.to_sec(), img.copy()))
            elif topic == "/imaging/camera_info":
                if info is None:
                    info = {"K": np.array(m.K).reshape(3, 3), "width": m.width, "height": m.height}
            elif m.status == 0:
                truth.append([m.header.stamp.to_sec(), m.point.x, m.point.y, m.point.z, m.normal.x, m.normal.y,
                              m.normal.z, m.surface_velocity.x, m.surface_velocity.y, m.surface_velocity.z,
                              m.image_velocity[0], m.image_velocity[1], m.u, m.v])
    if not frames or info is None or not truth:
        raise RuntimeError(f"{bag} has no imaging stream or no surface-motion truth (make_sim_bag --imaging-rate)")
    t = np.array(truth)
    return frames, info, {"t": t[:, 0], "X": t[:, 1:4], "n": t[:, 4:7], "s": t[:, 7:10], "iv": t[:, 10:12],
                          "pixel": t[0, 12:14]}


# ---------------------------------------------------------------- baselines

def baseline_flows(frames, pixel, method):
    """Image velocity [px/frame] at the pixel for every consecutive pair, by one OpenCV method."""
    import cv2
    u, v = int(round(pixel[0])), int(round(pixel[1]))
    w = BASELINE_WINDOW
    dis = cv2.DISOpticalFlow_create(cv2.DISOPTICAL_FLOW_PRESET_MEDIUM) if method == "dis" else None
    out = []
    for (_, a), (_, b) in zip(frames[:-1], frames[1:]):
        if method == "lk":
            mask = np.zeros_like(a)
            cv2.circle(mask, (u, v), BASELINE_LK_RADIUS, 255, -1)
            p0 = cv2.goodFeaturesToTrack(a, 200, 0.01, 5, mask=mask)
            flow = np.array([np.nan, np.nan])
            if p0 is not None:
                p1, ok, _ = cv2.calcOpticalFlowPyrLK(a, b, p0, None, winSize=(21, 21), maxLevel=3)
                ok = ok.ravel() == 1
                if np.any(ok):
                    flow = np.median((p1 - p0).reshape(-1, 2)[ok], axis=0)
            out.append(flow)
            continue
        if method == "farneback":
            # Farneback's defaults as OpenCV documents them (pyramid 0.5, 3 levels, window 15).
            f = cv2.calcOpticalFlowFarneback(a, b, None, 0.5, 3, 15, 3, 5, 1.2, 0)
        else:
            f = dis.calc(a, b, None)
        patch = f[max(v - w, 0):v + w + 1, max(u - w, 0):u + w + 1].reshape(-1, 2)
        out.append(np.median(patch, axis=0))
    return np.array(out)


# ---------------------------------------------------------------- our output

def our_outputs(bag, stem, scene, info, data, out, log, settings=()):
    """eskf_replay (inertial, with the filter settings KEY=VALUE), imaging_flow_replay and surface_motion_replay
    on one bag: (causal, smoothed) rows of surface_motion_replay, on the camera clock."""
    txt = accuracy.landmark_stream(bag, stem, FRONTEND_ARGS.get(scene, []), data, log)
    told = accuracy.time_offset(bag, "/calibration", default=accuracy.time_offset(bag))
    prefix = os.path.join(out, stem + "_inertial")
    st, _ = accuracy.replay(txt, "inertial", told, prefix, log, settings)
    if st != 0:
        raise RuntimeError(f"eskf_replay failed for {stem} (see {log})")
    flow = prefix + "_flow.txt"
    st, _ = accuracy.run(["rosrun", "hapi_frontend", "imaging_flow_replay", bag, flow, "--topic", IMAGING_TOPIC], log)
    if st != 0:
        raise RuntimeError(f"imaging_flow_replay failed for {stem} (see {log})")
    K = info["K"]
    intrinsics = "%r %r %r %r %d %d %r" % (K[0, 0], K[1, 1], K[0, 2], K[1, 2], info["width"], info["height"],
                                          IMAGING_RATE)
    st, _ = accuracy.run(["rosrun", "hapi_eskf", "surface_motion_replay", "--odom", prefix + "_imu_rate.txt",
                 "--map", prefix + "_map.txt", "--flow", flow, "--intrinsics", intrinsics,
                 "--out", prefix + "_motion.txt", "--smoothed", prefix + "_motion_smoothed.txt"], log)
    if st != 0:
        raise RuntimeError(f"surface_motion_replay failed for {stem} (see {log})")
    return accuracy.load_rows(prefix + "_motion.txt"), accuracy.load_rows(prefix + "_motion_smoothed.txt")


# Columns of surface_motion_replay's output (SurfaceMotion's fields).
COL_T, COL_STATUS, COL_X, COL_N, COL_S, COL_CS, COL_IV = 0, 1, slice(2, 5), slice(5, 8), slice(8, 11), slice(12, 21), \
    slice(23, 25)


# ---------------------------------------------------------------- scoring

def per_frame_truth(truth, t0, t1):
    """The truth's mean image velocity and on-surface velocity over [t0, t1], and the skin point and normal at its middle."""
    iv = smm.interval_mean(truth["t"], truth["iv"], t0, t1)
    s = smm.interval_mean(truth["t"], truth["s"], t0, t1)
    if iv is None:
        return None
    tm_ = 0.5 * (t0 + t1)
    X = np.array([np.interp(tm_, truth["t"], truth["X"][:, j]) for j in range(3)])
    n = np.array([np.interp(tm_, truth["t"], truth["n"][:, j]) for j in range(3)])
    return iv, s, X, n / np.linalg.norm(n)


def scored_from(ours, offset):
    """The first instant scored (every method alike): smm.SETTLE_S after our first output with status OK."""
    ok = ours[:, COL_STATUS] == 0 if len(ours) else np.zeros(0, bool)
    return ours[ok, COL_T][0] + offset + smm.SETTLE_S if np.any(ok) else float("inf")


def score_run(frames, info, truth, offset, flows, ours, smoothed):
    """Per method: lists of (est px, true px, est mm/s, true mm/s) per frame pair. flows: the
    baselines' image velocities per frame pair (baseline_flows)."""
    fx, fy = info["K"][0, 0], info["K"][1, 1]
    stamps = np.array([f[0] for f in frames]) + offset
    rows = {m: [] for m in METHODS}
    start = scored_from(ours, offset)
    for k in range(1, len(frames)):
        if stamps[k - 1] < start:
            continue
        ref = per_frame_truth(truth, stamps[k - 1], stamps[k])
        if ref is None:
            continue
        iv_true, s_true, X, n = ref
        speed_true = float(np.linalg.norm(s_true))
        for m, f in flows.items():
            fl = f[k - 1]
            if not np.all(np.isfinite(fl)):
                continue
            rows[m].append((fl, iv_true, smm.surface_velocity_from_image_velocity(fl, IMAGING_RATE, X, n, fx, fy),
                            s_true, speed_true))
        for m, r in (("ours", ours), ("ours_smoothed", smoothed)):
            ok = r[:, COL_STATUS] == 0 if len(r) else np.zeros(0, bool)
            if np.sum(ok) < 2:
                continue
            t = r[ok, COL_T] + offset
            iv = smm.interval_mean(t, r[ok][:, COL_IV], stamps[k - 1], stamps[k])
            s = smm.interval_mean(t, r[ok][:, COL_S], stamps[k - 1], stamps[k])
            if iv is not None:
                rows[m].append((iv, iv_true, s, s_true, speed_true))
    return rows


def instant_errors(r, truth, offset, start):
    """Ours at every output instant with status OK from `start` on: (estimate, truth, covariance, normal) in mm/s."""
    ok = r[:, COL_STATUS] == 0 if len(r) else np.zeros(0, bool)
    t = r[ok, COL_T] + offset
    inside = (t >= max(truth["t"][0], start)) & (t <= truth["t"][-1])
    t = t[inside]
    est, cov = r[ok][inside][:, COL_S], r[ok][inside][:, COL_CS].reshape(-1, 3, 3)
    true = np.column_stack([np.interp(t, truth["t"], truth["s"][:, j]) for j in range(3)])
    n = np.column_stack([np.interp(t, truth["t"], truth["n"][:, j]) for j in range(3)])
    return t, est, true, cov, n


def figures(rows):
    """Appendix A's figures of pooled per-frame rows."""
    if not rows:
        return None
    est_px, true_px, est_s, true_s, speed = (np.array([r[i] for r in rows]) for i in range(5))
    out = smm.flow_errors(est_px, true_px, speed)
    out.update(smm.velocity_errors(est_s, true_s))
    return out


# ---------------------------------------------------------------- reporting

def fmt(x, digits=2):
    return "-" if x is None or not np.isfinite(x) else f"{x:.{digits}f}"


def table(results):
    head = ("| scenario | method | true speed mm/s | MAE px/frame (%) | SD px/frame (%) | median rel. % | "
            "RMS mm/s | p95 mm/s |")
    lines = [head, "|" + " --- |" * 8]
    for sc, res in results.items():
        for m in METHODS + ("ours_200hz", "ours_smoothed_200hz"):
            f = res["figures"].get(m)
            if not f:
                continue
            if m.endswith("200hz"):
                lines.append(f"| {sc} | {m} | {fmt(f['mean_true_speed_mm_s'])} | - | - | - | {fmt(f['rms_mm_s'])} | "
                             f"{fmt(f['p95_mm_s'])} |")
                continue
            lines.append(f"| {sc} | {m} | {fmt(f['mean_true_speed_mm_s'])} | {fmt(f['mae_px'], 3)} "
                         f"({fmt(f['mae_pct'], 1)}) | {fmt(f['sd_px'], 3)} ({fmt(f['sd_pct'], 1)}) | "
                         f"{fmt(f['median_relative_pct'], 1)} | {fmt(f['rms_mm_s'])} | {fmt(f['p95_mm_s'])} |")
    return "\n".join(lines)


def anees(nees_runs):
    """Mean over the seeds per output instant (runs cut to the shortest), its band and the fraction inside."""
    n = min(len(v) for v in nees_runs)
    a = np.mean([v[:n] for v in nees_runs], axis=0)
    lo, hi = tm.chi2_bounds_of_mean(2, len(nees_runs))
    return {"runs": len(nees_runs), "samples": int(n), "mean": float(np.mean(a)), "band_95": [float(lo), float(hi)],
            "fraction_inside": float(np.mean((a >= lo) & (a <= hi)))}


def plot(name, truth, offset, ours, frames, flows_fb, info, out_png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fx, fy = info["K"][0, 0], info["K"][1, 1]
    stamps = np.array([f[0] for f in frames]) + offset
    t0 = truth["t"][0]
    fig, axes = plt.subplots(2, 1, figsize=(9, 5), sharex=True)
    ok = ours[:, COL_STATUS] == 0 if len(ours) else np.zeros(0, bool)
    fb = []
    for k in range(1, len(frames)):
        ref = per_frame_truth(truth, stamps[k - 1], stamps[k])
        if ref is not None and np.all(np.isfinite(flows_fb[k - 1])):
            fb.append((0.5 * (stamps[k - 1] + stamps[k]),
                       smm.surface_velocity_from_image_velocity(flows_fb[k - 1], IMAGING_RATE, ref[2], ref[3], fx, fy)))
    for j, ax in enumerate(axes):
        ax.plot(truth["t"] - t0, truth["s"][:, j], "k-", lw=1.5, label="truth")
        if np.any(ok):
            ax.plot(ours[ok, COL_T] + offset - t0, ours[ok][:, COL_S][:, j], "b-", lw=0.8, label="ours (causal)")
        if fb:
            ax.plot([f[0] - t0 for f in fb], [f[1][j] for f in fb], "r.", ms=3, label="Farneback")
        ax.set_ylabel(("x", "y")[j] + " on-surface velocity [mm/s]")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=8)
    axes[0].set_title(f"{name}: the skin's velocity at the imaging pixel, camera frame")
    axes[1].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(out_png, dpi=90)
    plt.close(fig)


# ---------------------------------------------------------------- main

def study(name, seeds, duration, data, out, log, plots_dir, settings=()):
    pooled = {m: [] for m in METHODS}
    instants = {"ours_200hz": [], "ours_smoothed_200hz": []}
    nees_runs = []
    for seed in seeds:
        stem, bag, scene = scenario_bag(name, seed, duration, data, log)
        frames, info, truth = read_imaging(bag)
        offset = accuracy.time_offset(bag)
        ours, smoothed = our_outputs(bag, stem, scene, info, data, out, log, settings)
        flows = {m: baseline_flows(frames, truth["pixel"], m) for m in BASELINES}
        rows = score_run(frames, info, truth, offset, flows, ours, smoothed)
        for m in METHODS:
            pooled[m] += rows[m]
        for key, r in (("ours_200hz", ours), ("ours_smoothed_200hz", smoothed)):
            if len(r):
                _, est, true, cov, n = instant_errors(r, truth, offset, scored_from(ours, offset))
                instants[key].append((est, true))
                if key == "ours_200hz" and len(est):
                    nees_runs.append(smm.velocity_nees(est, true, cov, n))
        if plots_dir and seed == seeds[0]:
            plot(name, truth, offset, ours, frames, flows["farneback"], info,
                 os.path.join(plots_dir, f"motion_{name}.png"))
    figs = {m: figures(pooled[m]) for m in METHODS}
    for key, runs in instants.items():
        if runs:
            figs[key] = smm.velocity_errors(np.vstack([e for e, _ in runs]), np.vstack([g for _, g in runs]))
    res = {"figures": figs}
    if len(nees_runs) >= 2:
        res["velocity_anees"] = anees(nees_runs)
    return res


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenarios", default=",".join(SCENARIOS))
    ap.add_argument("--seeds", type=int, default=1, help="seeds 1..N per scenario")
    ap.add_argument("--duration", type=float, default=7.0, help="s (a HAPI measurement takes 7 s)")
    ap.add_argument("--data", default=os.path.join(REPO, ".data", "motion"))
    ap.add_argument("--out", default="/tmp/hapi_motion")
    ap.add_argument("--markdown")
    ap.add_argument("--plots", help="folder for the velocity plots (seed 1 of each scenario)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a filter setting for eskf_replay (e.g. scene_motion=true), repeatable")
    return ap.parse_args(argv)


def main(argv=None):
    a = parse_args(argv)
    for d in (a.data, a.out) + ((a.plots,) if a.plots else ()):
        os.makedirs(d, exist_ok=True)
    log = os.path.join(a.out, "motion_study.log")
    seeds = list(range(1, a.seeds + 1))
    results = {}
    for name in a.scenarios.split(","):
        if name not in SCENARIOS:
            raise SystemExit(f"unknown scenario {name} (known: {', '.join(SCENARIOS)})")
        results[name] = study(name, seeds, a.duration, a.data, a.out, log, a.plots, a.set)
        print(table({name: results[name]}), flush=True)
    text = table(results)
    nees = {k: r["velocity_anees"] for k, r in results.items() if "velocity_anees" in r}
    if nees:
        text += "\n\nVelocity ANEES over %d seeds (2 dof): %s" % (a.seeds, yaml.safe_dump(nees, sort_keys=True))
    run_analysis.write_report(os.path.join(a.out, "motion_study.yaml"),
                              {"command": " ".join(sys.argv), "results": results}, text, a.markdown)
    return 0


if __name__ == "__main__":
    sys.exit(main())
