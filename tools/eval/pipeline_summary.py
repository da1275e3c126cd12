#!/usr/bin/python3
"""Prints the result of one pipeline run (scripts/run_pipeline.sh).

    pipeline_summary.py REPORT.yaml [DIAGNOSTICS.bag] [--max-ate-fraction 0.02] [--max-map-rms 0.01]
                        [--max-drift 0.01] [--max-drift-deg 1.0] [--map-error required|if-known]
                        [--stereo-rate-hz HZ]

REPORT.yaml is what tools/eval/evaluate_run.py wrote (ATE after rigid
alignment, map RMS to the true surfaces, rates, and the further metrics of
tools/eval/run_analysis.py, printed when present). A run whose ground truth
stands still (run_analysis.is_standstill) is scored by the estimate's drift
from its first pose instead: at most --max-drift [m] and --max-drift-deg
(run_analysis.STANDSTILL_MAX_DRIFT_M/_DEG, "did not wander"); its NEES is
anchored at the first pose. --stereo-rate-hz: the bag's stereo rate, printed
with the frames the front end dropped. --map-error if-known: a
recording without known geometry (a real data set) has no map error, which
is then not counted as missing; an empty map still is. DIAGNOSTICS.bag is /diagnostics
recorded during the run: the nodelets publish per-window mean stage timings
("time <stage> [ms]"), so the per-stage timing of the whole run is the mean of
the windows weighted by the frames each window processed (the last windows,
after the bag ended, processed nothing and must not count as zero-time frames).

Exit status: 0 all metrics present and within bounds, 1 something missing (the
run did not produce it: never guessed), 2 a metric outside its bound.
"""
import argparse
import os
import re
import sys

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_analysis  # noqa: E402

COUNTER_RE = re.compile(r"processed|updates|frames", re.IGNORECASE)
TIME_RE = re.compile(r"\[ms\]$|_ms$", re.IGNORECASE)  # "time match [ms]", "t_update_ms"
# Latencies are percentiles over the whole run, not per-window means: the
# report's `latency` section has them (evaluate_run.py), not the stage table.
LATENCY_RE = re.compile(r"^latency", re.IGNORECASE)
# Frame accounting shown next to the timings: a filter slower than the camera
# drops frames (newest wins), which explains fewer odometry messages than images.
ACCOUNT_RE = re.compile(r"^frames_(received|processed|dropped|failed)$|^(frames )?(received|processed)$"
                        r"|^(dropped|rejected)[ _]total$", re.IGNORECASE)


def to_float(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return None


def read_diagnostics(path):
    """{status name: [(stamp, {key: value str})]} of our nodelets, in order."""
    import rosbag  # only needed with a diagnostics bag
    out = {}
    with rosbag.Bag(path) as bag:
        for _, msg, t in bag.read_messages(topics=["/diagnostics"]):
            for st in msg.status:
                name = st.name
                # The self-checks (docs/CALIBRATION.md) carry no timings.
                if not re.search(r"hapi|eskf|frontend|surface|dense depth", name, re.IGNORECASE) \
                        or name.endswith("self-check"):
                    continue
                out.setdefault(name, []).append((t.to_sec(), {kv.key: kv.value for kv in st.values}))
    return out


def counter_key(samples):
    """The cumulative frame counter of one status (monotonic integer key)."""
    keys = [k for k in samples[-1][1] if COUNTER_RE.search(k) and "rate" not in k.lower()
            and "per" not in k.lower() and to_float(samples[-1][1][k]) is not None]
    for k in sorted(keys, key=lambda k: ("processed" not in k.lower(), k)):
        # Samples without the key (a nodelet's first "starting" status) are skipped.
        vals = [v for v in (to_float(s[1].get(k)) for s in samples) if v is not None]
        if all(b >= a for a, b in zip(vals, vals[1:])) and vals[-1] > 0:
            return k
    return None


def stage_timings(diag):
    """{status: {'frames': n, 'counter': key, 'stages': {key: (mean, max of window means)}}}."""
    result = {}
    for name, samples in diag.items():
        ck = counter_key(samples)
        stages = {}
        prev = 0.0
        weights = []
        for _, vals in samples:
            if ck is not None:
                c = to_float(vals.get(ck))
                if c is None:  # no counter in this sample: no frames attributed to it
                    weights.append(0.0)
                    continue
                weights.append(max(0.0, c - prev))
                prev = c
            else:
                weights.append(1.0)
        for key in samples[-1][1]:
            if not TIME_RE.search(key) or LATENCY_RE.search(key):
                continue
            num = den = 0.0
            peak = None
            for w, (_, vals) in zip(weights, samples):
                v = to_float(vals.get(key))
                if v is None or w <= 0:
                    continue
                num += w * v
                den += w
                peak = v if peak is None else max(peak, v)
            if den > 0:
                stages[key] = (num / den, peak)
        account = {k: v for k, v in samples[-1][1].items() if ACCOUNT_RE.search(k)}
        result[name] = {"counter": ck, "frames": prev if ck else len(samples), "stages": stages,
                        "account": account}
    return result


def print_further_metrics(rep):
    """The metrics beyond ATE and map error, each only when the run had its inputs."""
    if "ate_sim3_rmse_m" in rep:
        print(f"ATE (Sim(3) alignment): RMSE {rep['ate_sim3_rmse_m'] * 100:.2f} cm, scale {rep['sim3_scale']:.4f}")
    if "rotation_rmse_deg" in rep:
        print(f"rotation error        : RMS {rep['rotation_rmse_deg']:.3f} deg, max {rep['rotation_max_deg']:.3f} deg")
    if "rpe_1s_translation_rmse_m" in rep:
        print(f"RPE over 1 s          : {rep['rpe_1s_translation_rmse_m'] * 100:.2f} cm, "
              f"{rep['rpe_1s_rotation_rmse_deg']:.3f} deg RMS ({rep['rpe_1s_pairs']} pairs)")
    tied = ", anchored at the first pose" if rep.get("nees_anchored") else ""
    for key, label in (("nees_position", "position NEES"), ("nees_rotation", "rotation NEES")):
        if key in rep:
            n = rep[key]
            lo, hi = n["mean_bounds_95"]
            print(f"{label:<22s}: mean {n['mean']:.2f} (95 % bounds of the mean {lo:.2f}..{hi:.2f}, "
                  f"{n['fraction_in_95_band'] * 100:.0f} % of {n['samples']} samples in the 3-dof band{tied})")
    if "angular_velocity_rms_rad_s" in rep:
        print(f"velocity error        : angular {rep['angular_velocity_rms_rad_s']:.4f} rad/s, "
              f"linear {rep['linear_velocity_rms_m_s']:.4f} m/s RMS ({rep['velocity_samples']} samples)")
    sm = rep.get("surface_motion")
    if sm and "rms_mm_s" in sm:
        print(f"surface velocity      : error RMS {sm['rms_mm_s']:.2f} mm/s, p95 {sm['p95_mm_s']:.2f} mm/s over "
              f"{sm['samples']} outputs at {sm.get('rate_hz', float('nan')):.0f} Hz (true speed mean "
              f"{sm['mean_true_speed_mm_s']:.1f} mm/s; reporting zero: {sm['zero_output_rms_mm_s']:.1f} mm/s RMS; "
              f"NEES {sm['nees']['mean']:.2f}, 2 dof; status OK {sm['ok_fraction'] * 100:.0f} %; "
              f"skin point {sm.get('depth_median_m', float('nan')):.2f} m away, median)")
    elif sm:
        print(f"surface velocity      : {sm['outputs']} outputs, status OK {sm['ok_fraction'] * 100:.0f} % "
              f"(statuses {sm['statuses']}), not scored: no truth for it")
    if rep.get("plots"):
        print(f"plots                 : {', '.join(rep['plots'])}")
    elif rep.get("plots_missing"):
        print(f"plots                 : none ({rep['plots_missing']})")


def print_surface(sf):
    """The 3D surface's figures (evaluate_run.py's `surface` section: surface_run.py)."""
    if not sf:
        return
    kf = f"{sf['keyframes_fused']} keyframes fused" if "keyframes_fused" in sf else "keyframes unknown"
    if "depth_keyframes_published" in sf:
        kf += f" of {sf['depth_keyframes_published']} depth keyframes"
    if sf.get("keyframes_unsettled"):
        kf += (f" ({sf['keyframes_unsettled']} waited for the filter to settle: {sf.get('early_keyframes_fused', 0)}"
               f" registered and fused, {sf.get('early_keyframes_discarded', 0)} discarded)")
    if "error" in sf:
        print(f"surface               : not saved ({sf['error']}; {kf})")
        return
    print(f"surface               : {sf['mesh']}, {sf['vertices']} vertices, {sf['faces']} triangles, {kf}"
          f" ({sf.get('integration', '?')}), {sf.get('imaging_frames_projected', 0)} imaging frames projected")
    if "rms_mm" in sf:
        text = f"mesh to truth RMS {sf['rms_mm']:.3f} mm, p95 {sf['p95_mm']:.3f} mm"
        if "completeness_pct" in sf:
            text += f", completeness {sf['completeness_pct']:.1f} % (of {sf['seen_points']} seen 2 mm cells)"
        if sf.get("edge_pieces"):
            text += (f", registration RMS {sf['registration_rms_mm']:.3f} mm, p95 {sf['registration_p95_mm']:.3f} mm"
                     f" ({sf['edge_pieces']} edge pieces)")
        print(f"surface accuracy      : {text} (ATE's alignment)")
        pa = sf.get("pose_aligned", {})
        if "rms_mm" in pa:
            text = (f"mesh to truth RMS {pa['rms_mm']:.3f} mm, p95 {pa['p95_mm']:.3f} mm, completeness "
                    f"{pa.get('completeness_pct', float('nan')):.1f} %")
            if pa.get("edge_pieces"):
                text += f", registration RMS {pa['registration_rms_mm']:.3f} mm, p95 {pa['registration_p95_mm']:.3f} mm"
            print(f"surface, pose-aligned : {text} (alignment of whole poses, "
                  f"{pa.get('angle_to_ate_alignment_deg', float('nan')):.2f} deg from the ATE's)")
    else:
        print(f"surface accuracy      : not scored ({sf.get('not_scored', sf.get('score_error', '?'))})")
    print(f"surface picture       : {sf.get('picture', 'none (%s)' % sf.get('picture_missing', '?'))}")


def verdict(ok, failed, what):
    """'PASS' or 'FAIL'; a failure is appended to `failed` as `what`."""
    if not ok:
        failed.append(what)
    return "PASS" if ok else "FAIL"


def score_trajectory(rep, a, failed):
    """Prints the trajectory's score: ATE % of the distance, or the drift of a
    standstill; appends to `failed` what is outside its bound."""
    if rep.get("standstill"):
        d_m, d_deg = rep["standstill_drift_m"], rep["standstill_rotation_drift_deg"]
        ok = verdict(d_m <= a.max_drift and d_deg <= a.max_drift_deg, failed, "drift standing still")
        print(f"standing still        : the truth moves {rep['truth_net_travel_m'] * 1000:.1f} mm from its start; "
              f"the estimate drifts {d_m * 1000:.2f} mm, {d_deg:.3f} deg from its first pose "
              f"(bounds {a.max_drift * 1000:.0f} mm, {a.max_drift_deg:g} deg: {ok})")
        print(f"ATE (rigid alignment) : RMSE {rep['ate_rmse_m'] * 100:.2f} cm, max {rep['ate_max_m'] * 100:.2f} cm "
              f"(not scored standing still: no distance to relate it to)")
        return
    frac = rep["ate_fraction_of_distance"]
    ok = verdict(frac <= a.max_ate_fraction, failed, "ATE")
    print(f"ATE (rigid alignment) : RMSE {rep['ate_rmse_m'] * 100:.2f} cm, max {rep['ate_max_m'] * 100:.2f} cm "
          f"over {rep['distance_travelled_m']:.2f} m travelled = {frac * 100:.2f} % "
          f"(bound {a.max_ate_fraction * 100:.1f} %: {ok})")


def print_frame_rate(stereo_hz, timings):
    """The stereo rate of the bag and the frames each nodelet dropped (it was slower than its input)."""
    text = f"{stereo_hz:.2f} Hz in the bag" if stereo_hz else "rate of the bag unknown"
    for name, t in sorted(timings.items()):
        acc = t.get("account", {})
        dropped = acc.get("dropped total", acc.get("frames_dropped"))
        if dropped is not None:
            text += f"; {name.split(':')[0]} dropped {dropped} ({int(t['frames'])} processed)"
    print(f"stereo frames         : {text}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("report")
    ap.add_argument("diagnostics", nargs="?")
    ap.add_argument("--max-ate-fraction", type=float, default=0.02)
    ap.add_argument("--max-map-rms", type=float, default=0.01)
    ap.add_argument("--max-drift", type=float, default=run_analysis.STANDSTILL_MAX_DRIFT_M)
    ap.add_argument("--max-drift-deg", type=float, default=run_analysis.STANDSTILL_MAX_DRIFT_DEG)
    ap.add_argument("--map-error", choices=("required", "if-known"), default="required")
    ap.add_argument("--stereo-rate-hz", type=float)
    a = ap.parse_args()

    missing, failed = [], []
    try:
        with open(a.report) as f:
            rep = yaml.safe_load(f) or {}
    except OSError as e:
        print(f"[summary] MISSING: no evaluation report ({e})")
        return 1

    print("================ HAPI pipeline result ================")
    print(f"odometry messages     : {rep.get('odom_messages', 0)} "
          f"(rate {rep.get('odom_rate_sim_hz', float('nan')):.2f} Hz bag time, "
          f"{rep.get('odom_rate_wall_hz', float('nan')):.2f} Hz wall)")
    print(f"ground-truth poses    : {rep.get('gt_messages', 0)}, matched {rep.get('poses_compared', 0)}")
    if "ate_rmse_m" in rep:
        score_trajectory(rep, a, failed)
        print_further_metrics(rep)
        print_surface(rep.get("surface"))
    else:
        missing.append("ATE (no odometry matched the ground truth)")
    if "map_rms_to_surface_m" in rep or "map_rms_to_sphere_m" in rep:
        rms = rep.get("map_rms_to_surface_m", rep.get("map_rms_to_sphere_m"))
        med = rep.get("map_median_abs_to_surface_m", rep.get("map_median_abs_to_sphere_m"))
        ok = verdict(rms <= a.max_map_rms, failed, "map error")
        print(f"map error             : {rep['map_points']} points, RMS to the true surface "
              f"({rep.get('scene', 'sphere')}) {rms * 1000:.2f} mm, median |d| {med * 1000:.2f} mm "
              f"(bound {a.max_map_rms * 1000:.0f} mm: {ok})")
    elif rep.get("map_points", 0) == 0:
        missing.append("map error (no map received)")  # an empty map, known scene or not
    elif a.map_error == "if-known":
        print(f"map error             : {rep['map_points']} points, scene geometry unknown (not scored)")
    else:
        missing.append("map error (globe geometry unknown)")

    lat = rep.get("latency", {})
    for key, label in (("image_to_landmarks_ms", "latency to landmarks "), ("image_to_odometry_ms", "latency to odometry  "),
                       ("imaging_to_surface_motion_ms", "latency to skin motion")):
        if key in lat:
            v = lat[key]
            print(f"{label}: p50 {v['p50']:.1f} ms, p99 {v['p99']:.1f} ms, max {v['max']:.1f} ms "
                  f"(image stamp to output, ROS clock)")
    if "image_to_odometry_ms" not in lat:
        missing.append("latency (the back end's diagnostics carry no latency_p50_ms)")
    print("per-stage timing (mean over the frames processed, wall clock):")
    if a.diagnostics:
        try:
            timings = stage_timings(read_diagnostics(a.diagnostics))
        except Exception as e:  # a truncated bag: say so, do not invent numbers
            print(f"  cannot read {a.diagnostics}: {e}")
            timings = {}
    else:
        timings = {}
    if not timings:
        missing.append("per-stage timing (no /diagnostics from the nodelets)")
    for name, t in sorted(timings.items()):
        print(f"  {name}  ({int(t['frames'])} {t['counter'] or 'windows'})")
        if t.get("account"):
            print("    frames: " + ", ".join(f"{k} {v}" for k, v in sorted(t["account"].items())))
        if not t["stages"]:
            print("    (no timing keys)")
        for key, (mean, peak) in sorted(t["stages"].items()):
            print(f"    {key:<34s} {mean:9.2f}   (worst window {peak:.2f})")
    if not any(t["stages"] for t in timings.values()) and timings:
        missing.append("per-stage timing (diagnostics carry no 'time ... [ms]' keys)")
    print_frame_rate(a.stereo_rate_hz, timings)
    print("=======================================================")
    for m in missing:
        print(f"[summary] MISSING: {m}")
    for f_ in failed:
        print(f"[summary] FAILED: {f_} outside its bound")
    if missing:
        return 1
    return 2 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
