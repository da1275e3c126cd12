#!/usr/bin/python3
"""The front end's 3D measurement errors against a scene of known geometry.

The filter treats every stereo landmark measurement as z = R^T (m - p) + w
with w ~ N(0, C_z) independent from frame to frame (docs/DESIGN.md
"Measurement model"). This tool checks both halves of that claim on a
simulated stream (eskf_replay's text format, dump_frames.py), where the
camera's true pose and the surfaces are known:

* depth error: each measured point is put into the world with the TRUE
  camera pose; along its viewing ray, the distance to where the ray meets the
  true surface is the depth error e (a ray whose intersection does not
  converge is counted in rays_not_converged, not scored). Normalised by the stated depth sigma
  (sqrt(d^T C_z d), d the ray direction), e_n should have mean 0 and
  variance 1.
* persistence: measurements of one surface point in consecutive frames are
  linked (world points within --link-mm and descriptors within --link-bits);
  along the links the correlation of e_n at lag 1..5 frames says how much of
  the error a re-observation repeats.
* correlation within a frame: the rotation between consecutive frames from
  the linked bearings alone (true translation removed) is compared with the
  true one, per camera axis, and with the error the points' own spread about
  that fit would give if each point's error were independent of the others'.
  A larger error than that is shared by the frame's points, and no number of
  points averages it away.

    measurement_errors.py STREAM.txt [--offset -0.003] [--json OUT.json]

--offset: t_truth = t_camera + offset (the bag's /ground_truth/calibration
time_offset_s; accuracy.py reads it from the bag).
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_geometry as sg  # noqa: E402
import trajectory_metrics as tm  # noqa: E402


def read_stream(path):
    """(frames, truth, surfaces); frames: [(t, z (n,3), C (n,3,3), descriptors (n, bytes))]."""
    frames, gt, surfaces = [], [], None
    with open(path) as f:
        lines = iter(f)
        for line in lines:
            if line.startswith("gt "):
                gt.append([float(x) for x in line.split()[1:]])
            elif line.startswith("globe ") and surfaces is None:
                c = [float(x) for x in line.split()[1:]]
                surfaces = [sg.Sphere(c[:3], c[3])]
            elif line.startswith("scene "):
                surfaces = sg.parse_scene(line[len("scene "):])[1]
            elif line.startswith("frame "):
                w = line.split()
                t, n = float(w[1]), int(w[2])
                z, cov, desc = np.zeros((n, 3)), np.zeros((n, 3, 3)), []
                for i in range(n):
                    m = next(lines).split()
                    z[i] = [float(x) for x in m[6:9]]
                    cov[i] = np.array([float(x) for x in m[9:18]]).reshape(3, 3)
                    desc.append(np.frombuffer(bytes.fromhex(m[18]), dtype=np.uint8) if len(m) > 18 else None)
                frames.append((t, z, cov, desc))
    if surfaces is None:
        raise ValueError(f"{path}: no globe or scene line, the geometry is unknown")
    gt = np.array(gt).reshape(-1, 8)
    return frames, {"t": gt[:, 0], "p": gt[:, 1:4], "r": tm.rotations_from_quats(gt[:, 4:8])}, surfaces


def signed_distance(pts, surfaces):
    """Signed distance to the nearest surface (by absolute value)."""
    d = np.stack([s.distance(pts) for s in surfaces])
    return d[np.argmin(np.abs(d), axis=0), np.arange(pts.shape[0])]


def depth_to_surface(centre, dirs, s0, surfaces, iters=30):
    """Distance along each unit ray (centre + s dirs) to the surface, started from s0 (secant steps)."""
    s_a, s_b = s0 * 0.98, s0 * 1.02
    f_a = signed_distance(centre + s_a[:, None] * dirs, surfaces)
    f_b = signed_distance(centre + s_b[:, None] * dirs, surfaces)
    for _ in range(iters):
        den = f_b - f_a
        ok = np.abs(den) > 1e-15
        s_n = np.where(ok, s_b - f_b * (s_b - s_a) / np.where(ok, den, 1.0), s_b)
        s_a, f_a = s_b, f_b
        s_b = s_n
        f_b = signed_distance(centre + s_b[:, None] * dirs, surfaces)
    return np.where(np.abs(f_b) < 1e-7, s_b, np.nan)


def hamming(a, b):
    return int(np.unpackbits(np.bitwise_xor(a, b)).sum())


def analyse(frames, truth, surfaces, offset, link_m, link_bits):
    per_frame = []  # (world points, normalised depth errors, C_z in the world, descriptors)
    for t, z, cov, desc in frames:
        i, p, r = tm.interpolate_poses(truth["t"], truth["p"], truth["r"], np.array([t + offset]), max_gap=0.2)
        if len(i) == 0 or len(z) == 0:
            per_frame.append(None)
            continue
        R, c = r[0], p[0]
        X = (R @ z.T).T + c
        rng = np.linalg.norm(z, axis=1)
        d_cam = z / rng[:, None]
        hit = depth_to_surface(c, (R @ d_cam.T).T, rng, surfaces)
        sigma = np.sqrt(np.einsum("ni,nij,nj->n", d_cam, cov, d_cam))
        per_frame.append((X, (rng - hit) / sigma, np.einsum("ij,njk,lk->nil", R, cov, R), desc, z, R, c))
    e_all = np.concatenate([f[1] for f in per_frame if f is not None])
    # A ray whose surface intersection did not converge (depth_to_surface:
    # NaN) has no depth error; it is counted, not silently dropped.
    not_converged = int(np.count_nonzero(~np.isfinite(e_all)))
    e_all = e_all[np.isfinite(e_all)]
    # Links between consecutive frames: the nearest world point within link_m whose descriptor is within link_bits.
    links = []  # per frame k: {j in k+1: i in k}
    for k in range(len(per_frame) - 1):
        a, b = per_frame[k], per_frame[k + 1]
        lk = {}
        if a is not None and b is not None:
            for j in range(len(b[0])):
                dist = np.linalg.norm(a[0] - b[0][j], axis=1)
                i = int(np.argmin(dist))
                if dist[i] < link_m and (b[3][j] is None or hamming(a[3][i], b[3][j]) <= link_bits):
                    lk[j] = i
        links.append(lk)
    # Tracks from the links; correlation of e_n at lags 1..5 within a track.
    track, tracks = {}, []  # (frame, index) -> track number; per track [(frame, e_n)]
    for k, f in enumerate(per_frame):
        if f is None:
            continue
        for j, e in enumerate(f[1]):
            i = links[k - 1].get(j) if k > 0 else None
            n = track.get((k - 1, i)) if i is not None else None
            if n is None:
                n = len(tracks)
                tracks.append([])
            track[(k, j)] = n
            tracks[n].append((k, e))
    corr = {}
    for lag in range(1, 6):
        x, y = [], []
        for tr in tracks:
            by_frame = dict(tr)
            for k, e in tr:
                e1 = by_frame.get(k + lag)
                if e1 is not None and abs(e) <= 3 and abs(e1) <= 3:
                    x.append(e)
                    y.append(e1)
        corr[lag] = {"pairs": len(x), "correlation": float(np.corrcoef(x, y)[0, 1]) if len(x) > 10 else None}
    # Frame-to-frame rotation from the linked bearings alone (the true
    # translation removed), against the true relative rotation, per camera
    # axis; and what the spread of the points about that fit would give if
    # their errors were independent (a Wahba fit of n bearings: about x and y
    # sigma / sqrt(n), about the optical axis sigma / (rho sqrt(n)), rho the
    # RMS off-axis angle).
    resid, pred = [], []
    for k, lk in enumerate(links):
        if len(lk) < 15:
            continue
        a, b = per_frame[k], per_frame[k + 1]
        i, j = np.array(list(lk.values())), np.array(list(lk.keys()))
        t_rel = a[5].T @ (b[6] - a[6])
        ua = a[4][i] - t_rel
        ua /= np.linalg.norm(ua, axis=1)[:, None]
        ub = b[4][j] / np.linalg.norm(b[4][j], axis=1)[:, None]
        U, _, Vt = np.linalg.svd(ua.T @ ub)
        r_vis = U @ np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))]) @ Vt  # ua ~ r_vis ub
        resid.append(tm.so3_log(r_vis @ (a[5].T @ b[5]).T))
        spread = np.sqrt(np.sum((ua - (r_vis @ ub.T).T) ** 2) / (2 * (len(i) - 3)))
        rho = np.sqrt(np.mean(ub[:, 0] ** 2 + ub[:, 1] ** 2))
        pred.append(spread / np.sqrt(len(i)) * np.array([1.0, 1.0, 1.0 / rho]))
    resid, pred = np.array(resid), np.array(pred)
    return {
        "measurements": int(e_all.size),
        "rays_not_converged": not_converged,
        "rays_not_converged_fraction": not_converged / max(1, not_converged + int(e_all.size)),
        # Robust figures (gross outliers, wrong left-right matches, are the RANSAC's and the gate's job):
        # for N(0, 1), median 0, median |e| 0.674, fraction beyond 3: 0.0027.
        "depth_error_normalised": {"median": float(np.median(e_all)),
                                   "median_abs": float(np.median(np.abs(e_all))),
                                   "sigma_from_median_abs": float(np.median(np.abs(e_all)) / 0.6745),
                                   "fraction_beyond_3": float(np.mean(np.abs(e_all) > 3)),
                                   "mean_within_3": float(np.mean(e_all[np.abs(e_all) <= 3])),
                                   "variance_within_3": float(np.var(e_all[np.abs(e_all) <= 3]))},
        "links": int(sum(len(x) for x in links)),
        "track_length_mean": float(np.mean([len(t) for t in tracks])),
        "depth_error_correlation_by_lag": corr,
        "frame_pairs": int(len(resid)),
        # RMS over frame pairs [rad], camera axes x, y, z (z: the optical axis)
        "relative_rotation_error_rms": np.sqrt(np.mean(resid ** 2, axis=0)).tolist() if len(resid) else None,
        "relative_rotation_error_rms_if_independent": np.sqrt(np.mean(pred ** 2, axis=0)).tolist()
        if len(pred) else None,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("stream")
    ap.add_argument("--offset", type=float, default=0.0, help="t_truth = t_camera + offset [s]")
    ap.add_argument("--link-mm", type=float, default=3.0)
    ap.add_argument("--link-bits", type=int, default=48)
    ap.add_argument("--json")
    a = ap.parse_args()
    frames, truth, surfaces = read_stream(a.stream)
    rep = analyse(frames, truth, surfaces, a.offset, a.link_mm * 1e-3, a.link_bits)
    print(json.dumps(rep, indent=1))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rep, f, indent=1)


if __name__ == "__main__":
    main()
