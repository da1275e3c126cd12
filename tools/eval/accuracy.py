#!/usr/bin/python3
"""Accuracy of the back end's motion models on the simulation scenarios or a recording.

For every scenario (scene x trajectory of hapi_sim's make_sim_bag) and every
motion model it runs the system offline and scores the result against the
simulator's ground truth (docs/ACCURACY.md records the figures):

  make_sim_bag --scene S --trajectory T --seed N      the scenario (cached in --data)
  frontend_replay                                     the front end on every stereo pair
  dump_frames.py                                      landmarks, IMU, extrinsic, truth -> text
  eskf_replay motion_model=M imu_time_offset=<bag's>  the back end, as the nodelet runs it
  run_analysis.analyse                                ATE (SE(3), Sim(3)), RPE 1 s, rotation,
                                                      NEES, IMU-rate velocity errors

    accuracy.py [--scenarios skin:handheld,globe:smooth,...] [--models constant_velocity,gyro,inertial]
                [--seeds 1] [--duration 30] [--realism ideal|real] [--data DIR] [--out DIR] [--markdown FILE]
                [--set key=value ...] [--starts N] [--eskf-replay PATH]
    accuracy.py --nees-seeds 20 --scenarios skin:handheld --models inertial --duration 10
    accuracy.py --recording DIR [--rate-divisor auto|N] [--models ...] [--data DIR] ...

--recording: an ASL/EuRoC recording (the folder holding mav0/, or mav0)
instead of the scenarios, converted to a bag as the main job does
(scripts/run_dataset.sh --convert-only: asl_to_bag, the same stereo rate
rule and cache key; the cache in --data, by default the main job's), then
the same offline path and table; its scenario name is the recording's
folder name.

Needs a built workspace's environment (source devel/setup.bash). The front end
runs with config/frontend.yaml's values except where FRONTEND_BY_SCENE says
otherwise (the low-contrast skin needs a lower FAST threshold and a looser
sub-pixel correlation, docs/ACCURACY.md says why). Stamps: the filter runs on
the camera clock, the truth is on the IMU clock (the bag's
/ground_truth/calibration time_offset_s, t_imu = t_cam + offset); estimates
are moved to the truth's clock before they are compared. --realism real:
make_sim_bag's real-like profile; the filter gets the bag's believed time
offset (/calibration) and extrinsic (/tf_static), the evaluation the truth.

A run "diverged" when its ATE exceeds 5 % of the distance travelled, its
largest error exceeds 0.2 m, or the replay failed. A truth that stands still
(run_analysis.is_standstill: its net travel) is scored by the estimate's
drift from its first pose instead of ATE % and the aligned rotation error.
"""
import argparse
import math
import os
import subprocess
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import evaluation as ev  # noqa: E402
import recording  # noqa: E402
import run_analysis  # noqa: E402
import trajectory_metrics as tm  # noqa: E402

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DUMP_FRAMES = os.path.join(REPO, "hapi_eskf", "tools", "dump_frames.py")
SCENES = ("globe", "skin")
TRAJECTORIES = ("smooth", "handheld", "fast", "loop", "subject", "rest")
MODELS = ("constant_velocity", "gyro", "inertial")
FRONTEND_BY_SCENE = {"skin": ["fast_threshold=8", "refine_min_zncc=0.8"]}
DIVERGED_FRACTION, DIVERGED_MAX_M = 0.05, 0.2


def run(cmd, log):
    """Runs cmd, appending its output to log; returns (exit status, stdout)."""
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n" + p.stdout + "\n")
    return p.returncode, p.stdout


def landmark_stream(bag, name, frontend_args, data, log):
    """The landmark stream text of a bag (front end and dump_frames.py; cached in data as NAME_stream.txt)."""
    lm, txt = (os.path.join(data, name + ext) for ext in ("_landmarks.bag", "_stream.txt"))
    if os.path.exists(txt) and os.path.getmtime(txt) >= os.path.getmtime(bag):
        return txt
    st, _ = run(["rosrun", "hapi_frontend", "frontend_replay", bag, lm] + frontend_args, log)
    if st != 0:
        raise RuntimeError(f"frontend_replay failed for {name} (see {log})")
    st, _ = run(["/usr/bin/python3", DUMP_FRAMES, lm, txt + ".tmp"], log)
    if st != 0:
        raise RuntimeError(f"dump_frames.py failed for {name} (see {log})")
    os.replace(txt + ".tmp", txt)
    return txt


def stream_for(scene, traj, seed, duration, data, log, realism="ideal"):
    """The landmark stream of a scenario (generated and cached on first use)."""
    name = f"{scene}_{traj}_s{seed}_{duration:g}s" + ("" if realism == "ideal" else "_" + realism)
    bag = os.path.join(data, name + ".bag")
    if not os.path.exists(bag):
        st, _ = run(["rosrun", "hapi_sim", "make_sim_bag", "--scene", scene, "--trajectory", traj, "--seed",
                     str(seed), "--duration", str(duration), "--realism", realism, "--output", bag + ".tmp"], log)
        if st != 0:
            raise RuntimeError(f"make_sim_bag failed for {name} (see {log})")
        os.replace(bag + ".tmp", bag)
    return name, bag, landmark_stream(bag, name, FRONTEND_BY_SCENE.get(scene, []), data, log)


def recording_stream(folder, rate_divisor, data, log):
    """The landmark stream of an ASL/EuRoC recording: converted to a bag by
    scripts/run_dataset.sh --convert-only (its key; in data, or without data
    in its own cache), the stream cached next to the bag."""
    bag = recording.convert(folder, rate_divisor, data, log)
    stem = os.path.splitext(os.path.basename(bag))[0]
    return recording.name(bag), bag, landmark_stream(bag, stem, [], os.path.dirname(bag), log)


def time_offset(bag, topic="/ground_truth/calibration", default=0.0):
    """t_imu = t_cam + offset, from the bag's calibration topic (default without): /ground_truth/calibration
    the truth, /calibration (make_sim_bag --realism real) what the filter is told."""
    import rosbag
    with rosbag.Bag(bag) as b:
        for _, msg, _ in b.read_messages(topics=[topic]):
            return float(yaml.safe_load(msg.data).get("time_offset_s", 0.0))
    return default


def read_stream_truth(txt):
    """Truth poses, truth twists (camera frame) and the landmarks per frame of a stream file."""
    gt, tw, n_meas = [], [], []
    with open(txt) as f:
        for line in f:
            if line.startswith("gt "):
                gt.append([float(x) for x in line.split()[1:]])
            elif line.startswith("gtvel "):
                tw.append([float(x) for x in line.split()[1:]])
            elif line.startswith("frame "):
                n_meas.append(int(line.split()[2]))
    gt, tw = np.array(gt).reshape(-1, 8), np.array(tw).reshape(-1, 7)
    return ({"t": gt[:, 0], "p": gt[:, 1:4], "q": gt[:, 4:8]},
            {"t": tw[:, 0], "twist": tw[:, 1:7]} if len(tw) else None, float(np.mean(n_meas)) if n_meas else 0.0)


def load_rows(path):
    rows = [r for r in (line.split() for line in open(path)) if r and not r[0].startswith("#")]
    return np.array([[float(x) for x in r] for r in rows]) if rows else np.zeros((0, 1))


# The back end's replay: the workspace's, or --eskf-replay's binary (another
# build of the ROS-free core, e.g. a baseline commit: variants compared in one run).
REPLAY = ["rosrun", "hapi_eskf", "eskf_replay"]


def replay(txt, model, offset, prefix, log, settings=(), start_frame=0):
    """eskf_replay (settings: extra key=value filter settings; from the stream's
    frame start_frame on); returns (exit status, its event counts)."""
    st, out = run(REPLAY + [txt, "motion_model=" + model, "imu_time_offset=%r" % offset, "--out", prefix]
                  + (["--start-frame", str(start_frame)] if start_frame else []) + list(settings), log)
    events = {}
    for line in out.splitlines():
        if line.startswith("events:"):
            w = line.replace(",", "").replace("(", "").split()
            events = {"relocalisations": int(w[1]), "vision_led_frames": int(w[3]),
                      "scene_moving_frames": int(w[6]), "rejected_frames": int(w[9])}
    return st, events


def anchor_pose(prefix, offset, truth):
    """(est_p0, est_r0, ref_p0, ref_r0) where the filter defined its world (its
    first processed frame, eskf_replay's PREFIX_anchor.txt) and the truth
    interpolated there; None without."""
    a = load_rows(prefix + "_anchor.txt")
    if not len(a) or a.shape[1] < 8:
        return None
    ia, a_p, a_r = tm.interpolate_poses(truth["t"], truth["p"], tm.rotations_from_quats(truth["q"]),
                                        a[:1, 0] + offset, max_gap=0.2)
    if not len(ia):
        return None
    return a[0, 1:4], tm.rotations_from_quats(a[:1, 4:8])[0], a_p[0], a_r[0]


def evaluate(prefix, model, offset, truth, truth_twist):
    """Metrics of one replay against the truth, on the truth's clock. The pose
    NEES is anchored (trajectory_metrics.anchored_pose_nees): the frames tied
    where the filter defines its world, the truth interpolated there."""
    est = load_rows(prefix + "_estimate.tum")
    cov = load_rows(prefix + "_covariance.txt")
    if len(est) < 3:
        return None, None
    e = {"t": est[:, 0] + offset, "p": est[:, 1:4], "q": est[:, 4:8]}
    anchor = anchor_pose(prefix, offset, truth)
    if anchor is not None and len(cov) == len(est):
        e["cov"] = cov[:, 1:].reshape(-1, 6, 6)
    rep, series = run_analysis.analyse(e, truth, max_dt=0.006, anchor=anchor)
    # Velocity output: at the IMU rate for the IMU models (the nodelet's
    # IMU-rate odometry), per frame for constant_velocity (the state's v, w).
    rate_file = prefix + "_imu_rate.txt" if model != "constant_velocity" else prefix + "_frame_twist.txt"
    if truth_twist is not None and os.path.exists(rate_file):
        r = load_rows(rate_file)
        if len(r):
            tw = r[:, 8:14] if r.shape[1] >= 14 else r[:, 1:7]
            pairs = ev.associate(r[:, 0] + offset, truth_twist["t"], 0.0026)
            if pairs:
                ie = [i for i, _ in pairs]
                ig = [j for _, j in pairs]
                w_rms, v_rms = tm.velocity_errors(tw[ie], truth_twist["twist"][ig])
                rep.update({"angular_velocity_rms_rad_s": w_rms, "linear_velocity_rms_m_s": v_rms,
                            "velocity_samples": len(pairs)})
    return rep, series


def diverged(rep, status):
    if status != 0 or rep is None or rep.get("poses_compared", 0) < 3:
        return True
    if "standstill_drift_m" in rep:
        return rep["standstill_drift_m"] > DIVERGED_MAX_M
    return rep["ate_fraction_of_distance"] > DIVERGED_FRACTION or rep["ate_max_m"] > DIVERGED_MAX_M


def fmt(x, scale=1.0, digits=2):
    return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x * scale:.{digits}f}"


def table(results):
    head = ("| scenario | model | landmarks/frame | ATE % | ATE cm | RPE 1 s cm / deg | max cm | rot RMS deg | "
            "diverged | relocalised / vision-led frames | w RMS rad/s | v RMS m/s | NEES pos / rot |")
    lines = [head, "|" + " --- |" * 13]
    for r in results:
        m = r["metrics"] or {}
        nees = (fmt(m.get("nees_position", {}).get("mean")) + " / " + fmt(m.get("nees_rotation", {}).get("mean"))
                if m.get("nees_position") else "-")
        lines.append("| {} | {} | {:.0f} | {} | {} | {} / {} | {} | {} | {} | {} / {} | {} | {} | {} |".format(
            r["scenario"], r["model"], r["landmarks_per_frame"], fmt(m.get("ate_fraction_of_distance"), 100),
            fmt(m.get("ate_rmse_m"), 100), fmt(m.get("rpe_1s_translation_rmse_m"), 100),
            fmt(m.get("rpe_1s_rotation_rmse_deg")), fmt(m.get("ate_max_m"), 100), fmt(m.get("rotation_rmse_deg")),
            "yes" if r["diverged"] else "no", r["events"].get("relocalisations", "-"),
            r["events"].get("vision_led_frames", "-"), fmt(m.get("angular_velocity_rms_rad_s"), 1, 3),
            fmt(m.get("linear_velocity_rms_m_s"), 1, 3), nees))
    drift = [f"{r['scenario']} {r['model']}: {fmt(r['metrics']['standstill_drift_m'], 1000)} mm, "
             f"{fmt(r['metrics']['standstill_rotation_drift_deg'], 1, 3)} deg"
             for r in results if r["metrics"] and "standstill_drift_m" in r["metrics"]]
    if drift:
        lines += ["", "Standing still, largest distance of the estimate from its start: " + "; ".join(drift)]
    return "\n".join(lines)


def anees(results):
    """Average pose NEES over the seeds per frame (Bar-Shalom's ANEES), its 95 % band, the fraction inside."""
    per_frame = {}
    for r in results:
        s = r.get("series") or {}
        for key in ("nees_position", "nees_rotation"):
            if key in s:
                per_frame.setdefault(key, []).append(np.asarray(s[key]))
    out = {}
    for key, runs in per_frame.items():
        n = min(len(v) for v in runs)
        a = np.mean([v[:n] for v in runs], axis=0)
        lo, hi = tm.chi2_bounds_of_mean(3, len(runs))
        out[key] = {"runs": len(runs), "frames": int(n), "mean": float(np.mean(a)), "band_95": [float(lo), float(hi)],
                    "fraction_of_frames_inside": float(np.mean((a >= lo) & (a <= hi))),
                    # the trend over the run: the mean of each fifth of the frames
                    "mean_by_fifth": [float(np.mean(part)) for part in np.array_split(a, 5)]}
    return out


def score_stream(label, bag, txt, models, seed, out, log, settings, starts=1):
    """Every motion model's replay of one landmark stream, scored: the table's
    rows; with starts > 1 one row per start frame 0..starts-1 (label "@k")."""
    offset = time_offset(bag)
    told = time_offset(bag, "/calibration", default=offset)  # what the filter is told (make_sim_bag --realism real)
    truth, truth_twist, lm_per_frame = read_stream_truth(txt)
    rows = []
    for model in models:
        for k in range(starts):
            name = f"{os.path.basename(txt)[:-len('_stream.txt')]}_{model}" + (f"_start{k}" if k else "")
            prefix = os.path.join(out, name)
            status, events = replay(txt, model, told, prefix, log, settings, k)
            rep, series = evaluate(prefix, model, offset, truth, truth_twist) if status == 0 else (None, None)
            r = {"scenario": label + (f" @{k}" if starts > 1 else ""), "model": model, "seed": seed, "start_frame": k,
                 "landmarks_per_frame": lm_per_frame, "metrics": rep, "events": events,
                 "diverged": diverged(rep, status), "series": series}
            rows.append(r)
            print(table([r]).splitlines()[2], flush=True)
    return rows


def start_spread(results):
    """Per model, over the rows of several start frames: the median and the
    largest standstill drift (or ATE), the figure's dependence on where the
    filter started."""
    by_model = {}
    for r in results:
        if r.get("start_frame") is None or not r["metrics"]:
            continue
        m = r["metrics"]
        if "standstill_drift_m" in m:
            by_model.setdefault(r["model"], []).append((m["standstill_drift_m"] * 1000,
                                                        m["standstill_rotation_drift_deg"], "mm", "deg"))
        elif "ate_rmse_m" in m:
            by_model.setdefault(r["model"], []).append((m["ate_rmse_m"] * 100, m["rotation_rmse_deg"], "cm", "deg"))
    parts = []
    for model, v in by_model.items():
        if len(v) < 2:
            continue
        a, b = np.array([x[0] for x in v]), np.array([x[1] for x in v])
        parts.append(f"{model}: {np.median(a):.2f} {v[0][2]} (max {a.max():.2f}), {np.median(b):.3f} {v[0][3]} "
                     f"(max {b.max():.3f}) over {len(v)} starts")
    return ("Median and largest over the start frames (standing still: drift; moving: ATE and rotation RMS): "
            + "; ".join(parts)) if parts else ""


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenarios", default=",".join(f"{s}:{t}" for s in SCENES for t in TRAJECTORIES))
    ap.add_argument("--recording", metavar="DIR",
                    help="an ASL/EuRoC recording (the folder holding mav0/, or mav0) instead of the scenarios")
    ap.add_argument("--rate-divisor", default="auto",
                    help="with --recording: every N-th stereo frame, or auto (scripts/run_dataset.sh's rule)")
    ap.add_argument("--models", default=",".join(MODELS))
    ap.add_argument("--seeds", type=int, default=1, help="seeds 1..N per scenario")
    ap.add_argument("--nees-seeds", type=int, default=0, help="ANEES over seeds 1..N (one scenario, one model)")
    ap.add_argument("--duration", type=float, default=30.0)
    ap.add_argument("--realism", choices=("ideal", "real"), default="ideal",
                    help="make_sim_bag's sensor/calibration profile (real: the filter is told a wrong calibration)")
    ap.add_argument("--data", help="cache of the generated or converted bags and their landmark streams "
                                   "(default: .data/sim; with --recording scripts/run_dataset.sh's cache)")
    ap.add_argument("--out", default="/tmp/hapi_accuracy")
    ap.add_argument("--markdown")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a filter setting for every replay (eskf_replay key=value; repeatable)")
    ap.add_argument("--starts", type=int, default=1,
                    help="replay from each of the stream's first N frames (the start's alignment and world): "
                         "one row each and their median and largest figures")
    ap.add_argument("--eskf-replay", metavar="PATH",
                    help="this eskf_replay binary instead of the workspace's (a core build of another commit)")
    return ap.parse_args(argv)


def main(argv=None):
    a = parse_args(argv)
    if a.eskf_replay:
        REPLAY[:] = [a.eskf_replay]
    if a.data is None and not a.recording:
        a.data = os.path.join(REPO, ".data", "sim")
    if a.data:
        os.makedirs(a.data, exist_ok=True)
    os.makedirs(a.out, exist_ok=True)
    log = os.path.join(a.out, "accuracy.log")
    models = a.models.split(",")
    seeds = range(1, (a.nees_seeds or a.seeds) + 1)
    results = []
    if a.recording:
        name, bag, txt = recording_stream(a.recording, a.rate_divisor, a.data, log)
        results += score_stream(name, bag, txt, models, 0, a.out, log, a.set, a.starts)
    else:
        for sc in a.scenarios.split(","):
            scene, traj = sc.split(":")
            for seed in seeds:
                _, bag, txt = stream_for(scene, traj, seed, a.duration, a.data, log, a.realism)
                label = f"{scene}/{traj}" + (f" s{seed}" if len(seeds) > 1 else "")
                results += score_stream(label, bag, txt, models, seed, a.out, log, a.set, a.starts)
    text = table(results)
    spread = start_spread(results) if a.starts > 1 else ""
    if spread:
        text += "\n\n" + spread
    report = {"command": " ".join(sys.argv), "duration_s": None if a.recording else a.duration,
              "realism": None if a.recording else a.realism,
              "runs": [{k: v for k, v in r.items() if k != "series"} for r in results]}
    if a.nees_seeds:
        report["anees"] = run_analysis.to_plain(anees(results))
        text += "\n\nANEES over %d seeds: %s" % (a.nees_seeds, yaml.safe_dump(report["anees"], sort_keys=True))
    run_analysis.write_report(os.path.join(a.out, "accuracy.yaml"), report, text, a.markdown)
    return 0


if __name__ == "__main__":
    sys.exit(main())
