#!/usr/bin/python3
"""Two sessions' surfaces of the same skin compared (docs/DESIGN.md "Map
file": the second session relocalised in the first one's map, so both
meshes are in the same map frame). Input: hapi_surface's PLY (~save_surface:
x y z, nx ny nz, red green blue, value per vertex, triangles).

    session_compare.py FIRST.ply SECOND.ply OUT_PREFIX [--max-gap M]

For every vertex of SECOND, its nearest vertex of FIRST: the surface
distance is the point-to-plane distance to that vertex's tangent plane
(|(b - a) . n_a|; the nearest-vertex distance |b - a| is reported too: it
also holds the two meshes' vertex spacing), and the value difference is
value(b) - value(a) where both have one. Only vertices within --max-gap of
FIRST (default 5 mm) are in the overlap; the rest are counted, not measured.
Writes OUT_PREFIX.ply (SECOND's mesh, value = the difference, coloured by
it: blue below zero, red above, grey outside the overlap or without
values; without values anywhere, the signed surface distance instead),
OUT_PREFIX.png (its picture) and OUT_PREFIX.json (the figures), and prints
the figures.
"""
import argparse
import json
import os
import struct
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import render_mesh  # noqa: E402
import trajectory_io as tio  # noqa: E402

DEFAULT_MAX_GAP = 0.005  # [m]: farther from the first surface = not seen by it


def read_surface(path):
    """{'v': (N, 3), 'n': (N, 3) or None, 'value': (N,) or None, 'faces': (F, 3)} of a PLY file."""
    ply = tio.read_ply(path)
    v = ply.get("vertex", {})
    out = {"v": tio.read_ply_points(path), "n": None, "value": None}
    if all(k in v for k in ("nx", "ny", "nz")):
        out["n"] = np.column_stack([np.asarray(v[k], dtype=float) for k in ("nx", "ny", "nz")])
    if "value" in v:
        out["value"] = np.asarray(v["value"], dtype=float)
    out["faces"] = np.array(ply.get("face", {}).get("vertex_indices", []), dtype=np.int64).reshape(-1, 3)
    return out


def vertex_normals(vertices, faces):
    """Area-weighted vertex normals of a mesh (for a PLY without normals)."""
    n = np.zeros_like(vertices)
    tri = vertices[faces]
    fn = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    for k in range(3):
        np.add.at(n, faces[:, k], fn)
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)


def spread(x):
    """RMS, p95 of |x| and the mean of x (NaN when empty)."""
    if not len(x):
        return {"rms": float("nan"), "p95": float("nan"), "mean": float("nan"), "count": 0}
    return {"rms": float(np.sqrt(np.mean(x ** 2))), "p95": float(np.percentile(np.abs(x), 95)),
            "mean": float(np.mean(x)), "count": int(len(x))}


def compare(first, second, max_gap=DEFAULT_MAX_GAP):
    """Per-vertex comparison of SECOND against FIRST: (figures, signed
    point-to-plane distance per vertex of SECOND, value difference per
    vertex of SECOND; NaN outside the overlap / without values)."""
    normals = first["n"] if first["n"] is not None else vertex_normals(first["v"], first["faces"])
    gap, idx = cKDTree(first["v"]).query(second["v"])
    overlap = gap <= max_gap
    signed = np.einsum("ij,ij->i", second["v"] - first["v"][idx], normals[idx])
    signed[~overlap] = np.nan
    diff = np.full(len(second["v"]), np.nan)
    if first["value"] is not None and second["value"] is not None:
        diff = second["value"] - first["value"][idx]
        diff[~overlap] = np.nan
    seen = np.isfinite(diff)
    figures = {
        "vertices_first": int(len(first["v"])), "vertices_second": int(len(second["v"])),
        "overlap_fraction": float(overlap.mean()) if len(overlap) else 0.0, "max_gap_m": max_gap,
        "point_to_plane_m": spread(signed[overlap]), "nearest_vertex_m": spread(gap[overlap]),
        "value_difference": spread(diff[seen]),
    }
    return figures, signed, diff


def difference_colours(x):
    """uchar RGB per vertex: blue (-) .. white (0) .. red (+), scaled to the
    largest |x| (its 99th percentile); grey where x is NaN."""
    rgb = np.full((len(x), 3), 128, dtype=np.uint8)
    seen = np.isfinite(x)
    if seen.any():
        scale = max(np.percentile(np.abs(x[seen]), 99), 1e-30)
        t = np.clip(x[seen] / scale, -1, 1)
        r = np.where(t > 0, 1.0, 1.0 + t)
        b = np.where(t < 0, 1.0, 1.0 - t)
        g = 1.0 - np.abs(t)
        rgb[seen] = np.round(255 * np.column_stack([r, g, b])).astype(np.uint8)
    return rgb


def write_ply(path, vertices, normals, rgb, values, faces):
    """hapi_surface's PLY layout (binary little endian, value_weight 1)."""
    n = len(vertices)
    normals = normals if normals is not None else np.zeros((n, 3))
    head = ("ply\nformat binary_little_endian 1.0\ncomment session_compare: value = second - first (NaN: none)\n"
            "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\n"
            "property float value\nproperty float value_weight\n"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (n, len(faces)))
    vdt = np.dtype([("p", "<f4", 3), ("n", "<f4", 3), ("c", "u1", 3), ("value", "<f4"), ("w", "<f4")])
    rows = np.zeros(n, dtype=vdt)
    rows["p"], rows["n"], rows["c"], rows["value"], rows["w"] = vertices, normals, rgb, values, 1.0
    fdt = np.dtype([("k", "u1"), ("i", "<i4", 3)])
    frows = np.zeros(len(faces), dtype=fdt)
    frows["k"], frows["i"] = 3, faces
    with open(path, "wb") as f:
        f.write(head.encode("ascii"))
        f.write(rows.tobytes())
        f.write(frows.tobytes())
    return path


def write_outputs(prefix, second, figures, signed, diff):
    """OUT_PREFIX.ply, .png and .json (module docstring)."""
    shown = diff if np.isfinite(diff).any() else signed
    what = "value difference" if shown is diff else "signed surface distance [m]"
    write_ply(prefix + ".ply", second["v"], second["n"], difference_colours(shown), shown, second["faces"])
    d, s = figures["point_to_plane_m"], figures["value_difference"]
    title = ("second - first: %s; overlap %.0f %%, surface distance RMS %.2f mm p95 %.2f mm, value difference "
             "RMS %.3g p95 %.3g" % (what, 100 * figures["overlap_fraction"], 1e3 * d["rms"], 1e3 * d["p95"],
                                    s["rms"], s["p95"]))
    if len(second["faces"]):
        render_mesh.render(second["v"], second["faces"], prefix + ".png", values=shown, normals=second["n"],
                           title=title)
    with open(prefix + ".json", "w") as f:
        json.dump(figures, f, indent=1)
    return title


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("first")
    ap.add_argument("second")
    ap.add_argument("out_prefix")
    ap.add_argument("--max-gap", type=float, default=DEFAULT_MAX_GAP, help="[m] (default %(default)s)")
    a = ap.parse_args(argv[1:])
    if not a.max_gap > 0:
        ap.error("--max-gap must be > 0")
    first, second = read_surface(a.first), read_surface(a.second)
    if not len(first["v"]) or not len(second["v"]):
        print("error: a mesh without vertices", file=sys.stderr)
        return 1
    figures, signed, diff = compare(first, second, a.max_gap)
    print(write_outputs(a.out_prefix, second, figures, signed, diff))
    print(json.dumps(figures, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
