#!/usr/bin/python3
"""Offline evaluation of a trajectory estimate against a ground truth.

    evaluate.py --estimate est.txt --truth gt.{txt,csv} [--t-bs sensor.yaml|16 numbers]
                [--covariance cov.txt] [--scene scene.yaml] [--map map.ply]
                [--max-dt 0.006] [--interpolate] --out DIR

est.txt: TUM (t x y z qx qy qz qw) of the left camera. gt: TUM, or an ASL
ground truth CSV (body pose; --t-bs moves it to the camera: T_W_cam = T_W_B
T_BS, e.g. mav0/cam0/sensor.yaml). --covariance: the 6x6 pose covariances
the live run writes next to its estimate (NEES). --scene: the YAML scene
description (or a globe info {centre, radius}) for the map error of --map.
Writes DIR/report.yaml and the PNG plots (plots.py); prints the report.
Exit status: 0 done, 1 input missing or unreadable.
"""
import argparse
import os
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plots  # noqa: E402
import run_analysis  # noqa: E402
import scene_geometry  # noqa: E402
import trajectory_io as tio  # noqa: E402


def read_scene(path):
    with open(path) as f:
        text = f.read()
    doc = yaml.safe_load(text)
    if isinstance(doc, dict) and "surfaces" in doc:
        return scene_geometry.parse_scene(text)
    return scene_geometry.parse_globe_info(text)


def write_report(rep, series, out_dir):
    """report.yaml and the plots in out_dir; returns the report text."""
    os.makedirs(out_dir, exist_ok=True)
    reason = plots.available()
    if reason is None:
        rep["plots"] = [os.path.basename(p) for p in plots.write_plots(series, out_dir)]
    else:
        rep["plots_missing"] = reason
    text = yaml.safe_dump(run_analysis.to_plain(rep), default_flow_style=False, sort_keys=True)
    with open(os.path.join(out_dir, "report.yaml"), "w") as f:
        f.write(text)
    return text


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--estimate", required=True)
    ap.add_argument("--truth", required=True)
    ap.add_argument("--t-bs", dest="t_bs")
    ap.add_argument("--covariance")
    ap.add_argument("--scene")
    ap.add_argument("--map", dest="map_ply")
    ap.add_argument("--max-dt", type=float, default=0.006, help="[s] association tolerance")
    ap.add_argument("--interpolate", action="store_true",
                    help="interpolate the truth at the estimate's stamps (neighbours at most --max-dt apart)")
    ap.add_argument("--out", required=True)
    a = ap.parse_args(argv)
    try:
        est = tio.read_tum(a.estimate)
        gt = tio.read_trajectory(a.truth, tio.read_t_bs(a.t_bs) if a.t_bs else None)
        if a.covariance:
            ct, cov = tio.read_covariances(a.covariance)
            if len(ct) != len(est["t"]) or np.abs(ct - est["t"]).max() > 1e-6:
                raise ValueError("covariance stamps differ from the estimate's")
            est["cov"] = cov
        scene = read_scene(a.scene) if a.scene else None
        map_points = tio.read_ply_points(a.map_ply) if a.map_ply else None
    except (OSError, ValueError, KeyError) as e:
        print(f"[evaluate] ERROR: {e}", file=sys.stderr)
        return 1
    rep, series = run_analysis.analyse(est, gt, a.max_dt, a.interpolate, scene, map_points)
    rep["estimate_poses"], rep["truth_poses"] = int(len(est["t"])), int(len(gt["t"]))
    print(write_report(rep, series, a.out), end="")
    if rep["poses_compared"] < 3:
        print("[evaluate] ERROR: fewer than 3 poses matched the truth (stamps, --max-dt?)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
