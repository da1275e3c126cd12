#!/usr/bin/python3
"""Follow-up scans over many seeds (docs/DESIGN.md "Map file"): per seed,
session 1 scans the simulated arm, session 2 scans it again placed
elsewhere (a rigid move, --scene-offset) under other light
(--lighting-gain), and a third session scans another skin
(--skin-texture-seed); test/system/map_sessions_test.py runs them through
the whole system and reports relocalisation, pose error and the false
relocalisation check (and with --surfaces the two surfaces' overlay).

    session_study.py --seeds N --out DIR [--first-seed S] [--surfaces]
                     [--offset X,Y,Z,YAW_DEG] [--lighting-gain G] [--motion-model M]

Bags go to DIR/bags (made with make_sim_bag when missing), each seed's
figures to DIR/seed<N>.json and its log to DIR/seed<N>.log; the table of
all seeds is printed as markdown and written to DIR/study.md. Needs the
workspace's environment (rosrun, roslaunch).
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
SESSION_TEST = os.path.join(REPO, "test", "system", "map_sessions_test.py")


def make_bag(path, args):
    if os.path.exists(path):
        return
    subprocess.run(["rosrun", "hapi_sim", "make_sim_bag", "--output", path + ".tmp"] + args, check=True,
                   stdout=subprocess.DEVNULL)
    os.replace(path + ".tmp", path)


def seed_bags(bags, seed, a):
    """The three bags of one seed: session 1 (6 s), session 2 (5 s, moved, other light), another skin (4 s)."""
    common = ["--scene", "skin", "--trajectory", "handheld"]
    first = os.path.join(bags, "s%d_session1.bag" % seed)
    second = os.path.join(bags, "s%d_session2.bag" % seed)
    other = os.path.join(bags, "s%d_other.bag" % seed)
    make_bag(first, common + ["--seed", str(2 * seed + 1), "--duration", "6"])
    make_bag(second, common + ["--seed", str(2 * seed + 2), "--duration", "5", "--scene-offset", a.offset,
                               "--lighting-gain", str(a.lighting_gain)])
    make_bag(other, common + ["--seed", str(2 * seed + 1), "--duration", "4", "--skin-texture-seed",
                              str(100 + seed)])
    return first, second, other


def run_seed(seed, a):
    bags = os.path.join(a.out, "bags")
    os.makedirs(bags, exist_ok=True)
    first, second, other = seed_bags(bags, seed, a)
    out_json = os.path.join(a.out, "seed%d.json" % seed)
    cmd = ["/usr/bin/python3", SESSION_TEST, "--motion-model", a.motion_model, "--frontend-config",
           os.path.join(REPO, "config", "frontend_skin.yaml"), "--json", out_json]
    if a.surfaces:
        cmd += ["--surfaces", os.path.join(a.out, "surfaces%d" % seed)]
    with open(os.path.join(a.out, "seed%d.log" % seed), "w") as log:
        status = subprocess.call(cmd + [first, second, other], stdout=log, stderr=subprocess.STDOUT)
    if not os.path.exists(out_json):
        return {"seed": seed, "failures": ["map_sessions_test.py wrote no figures (exit %d)" % status]}
    with open(out_json) as f:
        figures = json.load(f)
    figures["seed"] = seed
    return figures


def row(f, surfaces):
    s2, other, surf = f.get("session2", {}), f.get("other", {}), f.get("surfaces", {})
    cells = [str(f["seed"]), "%.0f" % (1e3 * f.get("start_offset_m", float("nan")))]
    if s2.get("relocalised"):
        cells += ["%.2f" % s2["relocalised_after_s"],
                  "%.1f / %.1f" % (1e3 * s2["position_error_median_m"], 1e3 * s2["position_error_max_m"]),
                  "%.3f / %.3f" % (s2["rotation_error_median_deg"], s2["rotation_error_max_deg"])]
    else:
        cells += ["never", "-", "-"]
    cells.append("yes" if other.get("relocalised") else "no (%d held)" % other.get("frames_held", 0)
                 if other else "-")
    if surfaces:
        p2p = surf.get("point_to_plane_m")
        cells.append("%.2f / %.2f (%.1f %%)" % (1e3 * p2p["rms"], 1e3 * p2p["p95"], 100 * surf["overlap_fraction"])
                     if p2p else "-")
    cells.append("; ".join(f.get("failures", [])) or "pass")
    return "| " + " | ".join(cells) + " |"


def summary(results, surfaces):
    reloc = [r["session2"] for r in results if r.get("session2", {}).get("relocalised")]
    lines = ["relocalised: %d of %d seeds" % (len(reloc), len(results))]
    if reloc:
        t = np.array([r["relocalised_after_s"] for r in reloc])
        med = np.array([r["position_error_median_m"] for r in reloc]) * 1e3
        mx = np.array([r["position_error_max_m"] for r in reloc]) * 1e3
        rot = np.array([r["rotation_error_median_deg"] for r in reloc])
        lines.append("time into session 2's bag: median %.2f s, max %.2f s" % (np.median(t), t.max()))
        lines.append("position error: per-seed median %.1f-%.1f mm (median of medians %.1f), max %.1f mm"
                     % (med.min(), med.max(), np.median(med), mx.max()))
        lines.append("rotation error: per-seed median %.3f-%.3f deg" % (rot.min(), rot.max()))
    others = [r["other"] for r in results if "other" in r]
    lines.append("false relocalisations on another skin: %d of %d"
                 % (sum(1 for o in others if o.get("relocalised")), len(others)))
    if surfaces:
        rms = [1e3 * r["surfaces"]["point_to_plane_m"]["rms"] for r in results if "surfaces" in r]
        if rms:
            lines.append("surface overlay point-to-plane RMS: %.2f-%.2f mm (median %.2f) over %d seeds"
                         % (min(rms), max(rms), float(np.median(rms)), len(rms)))
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, required=True)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--out", required=True)
    ap.add_argument("--surfaces", action="store_true", help="also the dense depth and the surfaces, compared")
    ap.add_argument("--offset", default="0.1,0,0,20", help="session 2's --scene-offset X,Y,Z,YAW_DEG")
    ap.add_argument("--lighting-gain", type=float, default=0.7)
    ap.add_argument("--motion-model", default="inertial")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    header = ["seed", "start offset [mm]", "relocalised after [s]", "position error median / max [mm]",
              "rotation error median / max [deg]", "other skin relocalised"]
    if a.surfaces:
        header.append("surface distance RMS / p95 [mm] (overlap)")
    header.append("verdict")
    results = []
    for seed in range(a.first_seed, a.first_seed + a.seeds):
        results.append(run_seed(seed, a))
        print(row(results[-1], a.surfaces), flush=True)
    table = ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)] + [row(r, a.surfaces) for r in results]
    lines = table + [""] + summary(results, a.surfaces)
    with open(os.path.join(a.out, "study.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0 if all(not r.get("failures") for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
