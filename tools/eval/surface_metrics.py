"""Accuracy of a reconstructed skin surface and of the perfusion image
projected onto it (docs/DESIGN.md "Dense depth", evaluation), against the
simulator's truth (pure numpy/scipy, no ROS):

  * accuracy: distance of the mesh's vertices to the true surface
    (scene_geometry), RMS and 95th percentile [mm];
  * completeness: of the true surface seen in >= MIN_FRAMES keyframes, the
    percentage within COMPLETE_TOL of the mesh. "Seen" is approximated from
    the camera trajectory: a pinhole camera (no distortion) casts a ray
    through every `step`-th pixel of each keyframe; the first hit of the true
    scene within the depth range is a seen point (other surfaces occlude);
    hits are pooled in cubes of `cell` and a cube counts the keyframes that
    hit it;
  * registration: where the projected pattern's steps lie against the true
    edges of the perfusion pattern (/ground_truth/perfusion, below), in mm
    across each edge.

The perfusion pattern (hapi_sim/perfusion_pattern.hpp, one YAML schema):

    unit: PU
    origin: [x, y, z]; along: [..]; up: [..]     # s = (X - origin).along, t = (X - origin).up
    base: b; wave_amplitude: a; wave_length: L  # b + a cos(2 pi s / L) cos(2 pi t / L)
    bands: [{axis: s|t, from: f, to: g, value: v}]   # + v where f <= s (or t) < g
    discs: [{s: sc, t: tc, radius: r, value: v}]     # + v inside the circle
"""
import numpy as np
import yaml
from scipy.spatial import cKDTree

import scene_geometry as sg

MIN_FRAMES = 3          # keyframes that must see a point of the true surface
COMPLETE_TOL = 0.001    # m, a seen point this close to the mesh is covered
EDGE_HALF_WIDTH = 0.005  # m, vertices this close to an edge (either side) locate it
EDGE_BINS = 10          # bins across an edge (coverage check of a piece)
EDGE_SEGMENT = 0.01     # m, length of the edge pieces scored one by one (bands; discs: 30 deg arcs)
EDGE_MIN_FILLED = 0.8   # fraction of the bins that must hold a vertex for a piece to count
EDGE_MIN_VERTICES = 3 * EDGE_BINS  # and vertices it must hold (a piece cut off at the mesh's border has few)


# ---------------------------------------------------------------- the pattern
class PerfusionPattern:
    def __init__(self, doc):
        try:
            self.origin = sg._vec(doc["origin"], "origin")
            self.along = sg._unit(doc["along"], "along")
            self.up = sg._unit(doc["up"], "up")
            self.base, self.amplitude = float(doc["base"]), float(doc["wave_amplitude"])
            self.wave_length = sg._positive(doc["wave_length"], "wave_length")
            self.bands = [(0 if b["axis"] == "s" else 1, float(b["from"]), float(b["to"]), float(b["value"]))
                          for b in doc.get("bands") or []]
            self.discs = [(float(d["s"]), float(d["t"]), sg._positive(d["radius"], "disc radius"), float(d["value"]))
                          for d in doc.get("discs") or []]
        except (KeyError, TypeError) as e:
            raise ValueError(f"perfusion pattern lacks or mangles {e}") from None

    def coordinates(self, points):
        """(s, t) [m] of (N, 3) points."""
        d = np.asarray(points, dtype=float).reshape(-1, 3) - self.origin
        return d @ self.along, d @ self.up

    def _smooth(self, s, t):
        k = 2 * np.pi / self.wave_length
        return self.base + self.amplitude * np.cos(k * s) * np.cos(k * t)

    def _band_in(self, band, s, t):
        axis, lo, hi, _ = band
        c = s if axis == 0 else t
        return (c >= lo) & (c < hi)

    def _disc_in(self, disc, s, t):
        sc, tc, r, _ = disc
        return (s - sc) ** 2 + (t - tc) ** 2 < r * r

    def value(self, points):
        """The pattern [PU] at (N, 3) points of the surface."""
        s, t = self.coordinates(points)
        v = self._smooth(s, t)
        for b in self.bands:
            v = v + b[3] * self._band_in(b, s, t)
        for d in self.discs:
            v = v + d[3] * self._disc_in(d, s, t)
        return v

    def edges(self):
        """Every step as (height [PU], inside(s, t) -> bool array, signed
        distance(s, t) [m] positive inside, along-edge coordinate(s, t) [m],
        piece length along it [m])."""
        out = []
        for b in self.bands:
            axis, lo, hi, h = b
            for edge, sign in ((lo, 1.0), (hi, -1.0)):
                def across(s, t, axis=axis, edge=edge, sign=sign):
                    return sign * ((s if axis == 0 else t) - edge)

                def along(s, t, axis=axis):
                    return t if axis == 0 else s
                out.append((h, lambda s, t, b=b: self._band_in(b, s, t), across, along, EDGE_SEGMENT))
        for d in self.discs:
            sc, tc, r, h = d
            out.append((h, lambda s, t, d=d: self._disc_in(d, s, t),
                        lambda s, t, sc=sc, tc=tc, r=r: r - np.hypot(s - sc, t - tc),
                        lambda s, t, sc=sc, tc=tc, r=r: r * np.arctan2(t - tc, s - sc), r * np.pi / 6))
        return out


def parse_perfusion(text):
    doc = yaml.safe_load(text)
    if not isinstance(doc, dict):
        raise ValueError("perfusion YAML must be a mapping")
    return PerfusionPattern(doc)


# ---------------------------------------------------------------- the mesh
def _closest_on_triangles(p, a, b, c):
    """Closest points on triangles (a, b, c) to points p, all (N, 3)
    (Ericson, Real-Time Collision Detection 5.1.5), vectorised."""
    ab, ac, ap = b - a, c - a, p - a
    bp, cp = p - b, p - c
    dot = lambda x, y: np.einsum("ij,ij->i", x, y)  # noqa: E731
    d1, d2, d3, d4, d5, d6 = dot(ab, ap), dot(ac, ap), dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    vc, vb, va = d1 * d4 - d3 * d2, d5 * d2 - d1 * d6, d3 * d6 - d5 * d4
    with np.errstate(divide="ignore", invalid="ignore"):
        on_ab = a + ab * np.nan_to_num(d1 / (d1 - d3))[:, None]
        on_ac = a + ac * np.nan_to_num(d2 / (d2 - d6))[:, None]
        on_bc = b + (c - b) * np.nan_to_num((d4 - d3) / ((d4 - d3) + (d5 - d6)))[:, None]
        denom = 1.0 / (va + vb + vc)
        inside = a + ab * np.nan_to_num(vb * denom)[:, None] + ac * np.nan_to_num(vc * denom)[:, None]
    conds = [(d1 <= 0) & (d2 <= 0), (d3 >= 0) & (d4 <= d3), (vc <= 0) & (d1 >= 0) & (d3 <= 0),
             (d6 >= 0) & (d5 <= d6), (vb <= 0) & (d2 >= 0) & (d6 <= 0),
             (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)]
    out = inside.copy()
    for cond, q in reversed(list(zip(conds, [a, b, on_ab, c, on_ac, on_bc]))):
        out[cond] = q[cond]
    return out


def distance_to_mesh(points, vertices, faces, candidates=16):
    """Unsigned distance [m] of (N, 3) points to a triangle mesh: exact to the
    nearest of the `candidates` triangles whose centroids are nearest."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    tri = vertices[faces]  # (F, 3, 3)
    k = min(candidates, len(faces))
    _, idx = cKDTree(tri.mean(axis=1)).query(pts, k=k)
    idx = idx.reshape(len(pts), k)
    best = np.full(len(pts), np.inf)
    for j in range(k):
        t = tri[idx[:, j]]
        q = _closest_on_triangles(pts, t[:, 0], t[:, 1], t[:, 2])
        best = np.minimum(best, np.linalg.norm(pts - q, axis=1))
    return best


def accuracy(vertices, surfaces):
    """RMS and 95th percentile [mm] of the vertices' distance to the true scene."""
    if len(vertices) == 0:
        raise ValueError("empty mesh")
    d = sg.distance_to_scene(vertices, surfaces)
    return {"rms_mm": 1e3 * float(np.sqrt(np.mean(d ** 2))), "p95_mm": 1e3 * float(np.percentile(d, 95)),
            "vertices": int(len(vertices))}


# ---------------------------------------------------------------- what was seen
def _first_hits(surfaces, o, dirs):
    """Distance along each unit ray o + t d (dirs (N, 3)) to the nearest surface, inf on a miss."""
    best = np.full(len(dirs), np.inf)
    for s in surfaces:
        best = np.minimum(best, _hits(s, o, dirs))
    return best


def _nearest_positive(t1, t2, ok):
    t1 = np.where(ok & (t1 > 1e-9), t1, np.inf)
    t2 = np.where(ok & (t2 > 1e-9), t2, np.inf)
    return t1, t2


def _hits(s, o, d):
    """Vectorised scene_geometry hit distances (inf on a miss) of rays o + t d."""
    if isinstance(s, sg.Plane):
        den = d @ s.normal
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ((s.point - o) @ s.normal) / den
        x = o + t[:, None] * d - s.point
        r = np.linalg.norm(x - np.outer(x @ s.normal, s.normal), axis=1)
        return np.where((np.abs(den) > 1e-12) & (t > 1e-9) & (r <= s.half_extent), t, np.inf)
    if isinstance(s, sg.Sphere):
        oc = o - s.centre
        b, c = d @ oc, oc @ oc - s.radius ** 2
        disc = b * b - c
        root = np.sqrt(np.maximum(disc, 0))
        t1, t2 = _nearest_positive(-b - root, -b + root, disc >= 0)
        return np.minimum(t1, t2)
    oc = o - s.centre  # cylinder
    dp = d - np.outer(d @ s.axis, s.axis)
    op = oc - (oc @ s.axis) * s.axis
    a, b, c = np.einsum("ij,ij->i", dp, dp), dp @ op, op @ op - s.radius ** 2
    disc = b * b - a * c
    ok = (a > 1e-15) & (disc >= 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(disc, 0))
        t1, t2 = (-b - root) / a, (-b + root) / a
    best = np.full(len(d), np.inf)
    for t in (t2, t1):  # the nearer valid one wins
        x_axial = (oc @ s.axis) + t * (d @ s.axis)
        good = ok & (t > 1e-9) & (np.abs(x_axial) <= s.half_length)
        best = np.where(good & (t < best), t, best)
    return best


def seen_points(surfaces, poses, camera, min_depth, max_depth, step=4, cell=0.002):
    """(centres (M, 3), keyframe counts (M,)) of the true surface seen from the
    keyframe poses (4x4 T_world_camera, optical frame) by the pinhole camera
    (fx, fy, cx, cy, width, height): the module's "seen" approximation."""
    fx, fy, cx, cy, w, h = camera
    u, v = np.meshgrid(np.arange(0, w, step, dtype=float), np.arange(0, h, step, dtype=float))
    rays = np.column_stack([(u.ravel() - cx) / fx, (v.ravel() - cy) / fy, np.ones(u.size)])
    rays /= np.linalg.norm(rays, axis=1)[:, None]
    counts, sums = {}, {}
    for T in poses:
        d = rays @ T[:3, :3].T
        t = _first_hits(surfaces, T[:3, 3], d)
        z = t * rays[:, 2]  # depth along the optical axis
        keep = np.isfinite(t) & (z >= min_depth) & (z <= max_depth)
        pts = T[:3, 3] + t[keep, None] * d[keep]
        keys = np.floor(pts / cell).astype(np.int64)
        uniq, inv = np.unique(keys, axis=0, return_inverse=True)
        inv = inv.ravel()
        mean = np.zeros((len(uniq), 3))
        np.add.at(mean, inv, pts)
        mean /= np.bincount(inv)[:, None]
        for k, m in zip(map(tuple, uniq), mean):
            counts[k] = counts.get(k, 0) + 1
            sums[k] = sums.get(k, 0) + m
    keys = list(counts)
    if not keys:
        return np.zeros((0, 3)), np.zeros(0, dtype=int)
    n = np.array([counts[k] for k in keys])
    return np.array([sums[k] for k in keys]) / n[:, None], n


def completeness(vertices, faces, seen, counts, min_frames=MIN_FRAMES, tol=COMPLETE_TOL):
    """Percentage of the seen points (seen in >= min_frames keyframes) within
    tol of the mesh, and how many points that is out of."""
    pts = seen[counts >= min_frames]
    if len(pts) == 0:
        raise ValueError(f"no true surface seen in >= {min_frames} keyframes")
    if len(faces) == 0:
        return {"completeness_pct": 0.0, "seen_points": int(len(pts))}
    d = distance_to_mesh(pts, vertices, faces)
    return {"completeness_pct": 100.0 * float(np.mean(d <= tol)), "seen_points": int(len(pts))}


# ---------------------------------------------------------------- registration
def _step_fit(n, v, w):
    """Offset in [-w, w] of the step that best explains the values v at
    signed distances n: least squares of v = a + b n + h H(n - delta) over
    delta on a 0.05 mm grid (a, b, h linear), so the smooth field's slope
    across the edge does not move the step, and a symmetric blur of the step
    leaves it where it was."""
    A = np.column_stack([np.ones_like(n), n, np.zeros_like(n)])
    deltas = np.arange(-w, w + 1e-12, 5e-5)
    sse = np.empty(len(deltas))
    for i, delta in enumerate(deltas):
        A[:, 2] = n > delta
        coef, *_ = np.linalg.lstsq(A, v, rcond=None)
        sse[i] = np.sum((A @ coef - v) ** 2)
    # Every delta between the same two vertices fits equally: their middle.
    return float(np.mean(deltas[sse <= sse.min() * (1 + 1e-9) + 1e-12]))


def edge_offsets(vertices, values, pattern):
    """Offset [m] of the projected pattern's steps from the true edges, one
    per edge piece with enough vertices, positive where the projected step
    lies on the edge's inside: a step fitted (_step_fit) to the values of the
    vertices within EDGE_HALF_WIDTH of the edge, each piece holding at least
    EDGE_MIN_VERTICES of them in EDGE_MIN_FILLED of EDGE_BINS bins across it. Unseen vertices (NaN) are left out."""
    ok = np.isfinite(values)
    X, val = vertices[ok], values[ok]
    s, t = pattern.coordinates(X)
    w = EDGE_HALF_WIDTH
    offsets = []
    for _height, _inside, across, along, piece in pattern.edges():
        n = across(s, t)
        near = np.abs(n) < w
        if not np.any(near):
            continue
        n_near, v_near = n[near], val[near]
        bins = np.minimum(((n_near + w) / (2 * w) * EDGE_BINS).astype(int), EDGE_BINS - 1)
        pieces = np.floor(along(s[near], t[near]) / piece).astype(int)
        for p in np.unique(pieces):
            sel = pieces == p
            if np.count_nonzero(sel) >= EDGE_MIN_VERTICES and len(np.unique(bins[sel])) >= EDGE_MIN_FILLED * EDGE_BINS:
                offsets.append(_step_fit(n_near[sel], v_near[sel], w))
    return np.array(offsets)


def registration(vertices, values, pattern):
    """RMS and 95th percentile [mm] of |edge offset| over the scored edge pieces."""
    off = edge_offsets(vertices, values, pattern)
    if len(off) == 0:
        return {"registration_rms_mm": float("nan"), "registration_p95_mm": float("nan"), "edge_pieces": 0}
    return {"registration_rms_mm": 1e3 * float(np.sqrt(np.mean(off ** 2))),
            "registration_p95_mm": 1e3 * float(np.percentile(np.abs(off), 95)), "edge_pieces": int(len(off))}


# ---------------------------------------------------------------- all of it
# [m] the dense depth's default range (hapi_surface dense_depth_settings.def)
DEFAULT_DEPTH_RANGE = (0.15, 0.5)


def pose_alignment(est_rotations, est_positions, ref_rotations, ref_positions):
    """Rotation R and translation t of the rigid transform that takes the
    estimated world to the reference one, from whole poses: R is the
    rotation nearest to sum(R_ref_i R_est_i^T) (chordal mean), t the mean of
    p_ref_i - R p_est_i. A hand-held scan's positions span a few centimetres
    in one direction at most, so the positions-only (ATE) alignment leaves
    the world's rotation uncertain by ~position noise / extent (0.7 deg in
    the skin scan); the filter's orientations fix it to their own error, and
    the surface 20 cm from the camera moves by the lever arm of that angle.
    (N, 3, 3) rotations, (N, 3) positions."""
    m = np.einsum("nij,nkj->ik", np.asarray(ref_rotations, float), np.asarray(est_rotations, float))
    u, _, vt = np.linalg.svd(m)
    d = np.eye(3)
    d[2, 2] = np.sign(np.linalg.det(u @ vt))
    r = u @ d @ vt
    t = np.mean(np.asarray(ref_positions, float) - np.asarray(est_positions, float) @ r.T, axis=0)
    return r, t


def evaluate_surface(vertices, faces, surfaces, values=None, pattern=None, poses=None, camera=None,
                     depth_range=DEFAULT_DEPTH_RANGE, T_world_mesh=None):
    """Every figure that the inputs allow: accuracy always, completeness with
    poses and camera, registration with values and pattern. vertices (N, 3)
    and faces (F, 3) in the mesh's frame, T_world_mesh (4x4) moving it into
    the truth's world frame (identity when None)."""
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if T_world_mesh is not None:
        v = v @ np.asarray(T_world_mesh)[:3, :3].T + np.asarray(T_world_mesh)[:3, 3]
    out = accuracy(v, surfaces)
    if poses is not None and camera is not None:
        seen, counts = seen_points(surfaces, poses, camera, *depth_range)
        out.update(completeness(v, f, seen, counts))
    if values is not None and pattern is not None:
        out.update(registration(v, np.asarray(values, dtype=float), pattern))
    return out
