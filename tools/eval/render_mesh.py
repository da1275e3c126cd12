#!/usr/bin/python3
"""A PNG picture of a surface mesh (hapi_surface's PLY: x y z, nx ny nz,
red green blue, value per vertex), headless (matplotlib's Agg backend).

    render_mesh.py mesh.ply mesh.png

The mesh is seen along its smallest principal axis (the scan's viewing
direction for a patch of skin), from the side its normals face, and drawn
with the painter's algorithm: triangles far to near, each shaded by
Lambert's law (light from the viewer). Colour: the projected value (jet,
from its 1st to its 99th percentile, as the nodelet's display) where the
mesh has one, else the PLY's own colour (the skin's grey).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import trajectory_io as tio  # noqa: E402


def view_axes(vertices, normals):
    """3x3 rows (right, up, towards the viewer): the principal axes of the
    vertices, the last one turned to the side most normals face."""
    c = vertices - vertices.mean(axis=0)
    _, _, vt = np.linalg.svd(c[:: max(1, len(c) // 20000)], full_matrices=False)
    axes = vt.copy()
    if normals is not None and np.nanmean(normals @ axes[2]) < 0:
        axes[2] *= -1
        axes[0] *= -1  # keep a right-handed frame
    return axes


def face_colours(faces, values, rgb):
    """(F, 3) colours in [0, 1] and the value range used (None: no values)."""
    import matplotlib
    if values is not None and np.isfinite(values).any():
        lo, hi = np.percentile(values[np.isfinite(values)], [1, 99])
        fvals = values[faces]
        seen = np.isfinite(fvals)
        fv = np.where(seen, fvals, 0.0).sum(axis=1) / np.maximum(seen.sum(axis=1), 1)
        fv[~seen.any(axis=1)] = np.nan  # a triangle's value: the mean of its vertices' values
        norm = np.clip((fv - lo) / max(hi - lo, 1e-12), 0, 1)
        col = matplotlib.colormaps["jet"](norm)[:, :3]
        col[~np.isfinite(fv)] = 0.6  # grey without a value, as the nodelet's display
        return col, (lo, hi)
    if rgb is not None:
        return rgb[faces].mean(axis=1) / 255.0, None
    return np.full((len(faces), 3), 0.8), None


def render(vertices, faces, path, values=None, rgb=None, normals=None, title=None):
    """Writes the picture to path and returns path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    axes = view_axes(vertices, normals)
    p = (vertices - vertices.mean(axis=0)) @ axes.T
    tri = p[faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(n, axis=1)
    shade = np.abs(n[:, 2]) / np.maximum(length, 1e-30)
    col, vrange = face_colours(faces, values, rgb)
    col = col * (0.35 + 0.65 * shade[:, None])
    order = np.argsort(tri[:, :, 2].mean(axis=1))  # far (most negative towards the viewer) first
    fig, ax = plt.subplots(figsize=(8, 8 * max(0.3, np.ptp(p[:, 1]) / max(np.ptp(p[:, 0]), 1e-9))), dpi=110)
    ax.add_collection(PolyCollection(1000 * tri[order, :, :2], facecolors=col[order], edgecolors=col[order],
                                 linewidths=0.2))  # edges in the face colour: no seams between triangles
    ax.set_xlim(1000 * p[:, 0].min(), 1000 * p[:, 0].max())
    ax.set_ylim(1000 * p[:, 1].min(), 1000 * p[:, 1].max())
    ax.set_aspect("equal")
    ax.set_xlabel("mm (principal axis 1)")
    ax.set_ylabel("mm (principal axis 2)")
    text = title or os.path.basename(path)
    text += f"\n{len(vertices)} vertices, {len(faces)} triangles"
    text += f"; colour: projected value {vrange[0]:.4g}..{vrange[1]:.4g} (jet)" if vrange else "; colour: the mesh's own"
    ax.set_title(text, fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def render_file(ply_path, png_path):
    """Reads hapi_surface's PLY and renders it (render)."""
    ply = tio.read_ply(ply_path)
    v = ply.get("vertex", {})
    vertices = tio.read_ply_points(ply_path)
    faces = np.array(ply.get("face", {}).get("vertex_indices", []), dtype=np.int64).reshape(-1, 3)
    if not len(faces):
        raise ValueError(f"{ply_path}: no triangles")

    def columns(*names):
        return np.column_stack([np.asarray(v[k], dtype=float) for k in names]) if all(k in v for k in names) else None
    values = np.asarray(v["value"], dtype=float) if "value" in v else None
    return render(vertices, faces, png_path, values, columns("red", "green", "blue"), columns("nx", "ny", "nz"),
                  os.path.basename(ply_path))


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 1
    print(render_file(argv[1], argv[2]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
