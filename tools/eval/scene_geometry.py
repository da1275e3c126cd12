"""Known scene geometry and the map's distance to it (pure numpy, no ROS).

A scene is a list of surfaces in the ground truth's world frame [m], read from
the YAML scene description a bag carries on /ground_truth/scene:

    name: <scene name>
    surfaces:
      - {type: sphere, centre: [x, y, z], radius: r}
      - {type: cylinder, centre: [x, y, z], axis: [ux, uy, uz], radius: r, half_length: h}
      - {type: plane, point: [x, y, z], normal: [nx, ny, nz], half_extent: e}

or from the globe bags' /globe/info ({centre, radius}: one sphere). The map
error is the distance of each (aligned) map point to the nearest surface;
docs/DESIGN.md "Evaluation metrics" gives the distance of each surface type.
"""
import numpy as np
import yaml


def _vec(v, name):
    a = np.asarray(v, dtype=float).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be 3 finite numbers, got {v!r}")
    return a


def _unit(v, name):
    a = _vec(v, name)
    n = np.linalg.norm(a)
    if n < 1e-12:
        raise ValueError(f"{name} must not be zero")
    return a / n


def _positive(v, name):
    x = float(v)
    if not (x > 0 and np.isfinite(x)):
        raise ValueError(f"{name} must be positive, got {v!r}")
    return x


class Sphere:
    def __init__(self, centre, radius):
        self.centre = _vec(centre, "sphere centre")
        self.radius = _positive(radius, "sphere radius")

    def distance(self, pts):
        """Signed distance (outside > 0) of (N, 3) points to the sphere surface."""
        return np.linalg.norm(pts - self.centre, axis=1) - self.radius

    def hit(self, o, d):
        """(t, outward unit normal) of the nearest hit t > 0 of the ray o + t d (d unit), None on a miss."""
        oc = o - self.centre
        b, c = oc @ d, oc @ oc - self.radius ** 2
        disc = b * b - c
        if disc < 0:
            return None
        for t in (-b - np.sqrt(disc), -b + np.sqrt(disc)):
            if t > 0:
                return t, (o + t * d - self.centre) / self.radius
        return None


class Cylinder:
    """The lateral surface of a finite cylinder (no end caps)."""

    def __init__(self, centre, axis, radius, half_length):
        self.centre = _vec(centre, "cylinder centre")
        self.axis = _unit(axis, "cylinder axis")
        self.radius = _positive(radius, "cylinder radius")
        self.half_length = _positive(half_length, "cylinder half_length")

    def distance(self, pts):
        d = pts - self.centre
        a = d @ self.axis
        radial = np.linalg.norm(d - np.outer(a, self.axis), axis=1)
        beyond = np.maximum(np.abs(a) - self.half_length, 0.0)
        return np.where(radial >= self.radius, 1.0, -1.0) * np.hypot(radial - self.radius, beyond)

    def hit(self, o, d):
        oc = o - self.centre
        dp, op = d - (d @ self.axis) * self.axis, oc - (oc @ self.axis) * self.axis
        a, b, c = dp @ dp, op @ dp, op @ op - self.radius ** 2
        disc = b * b - a * c
        if a < 1e-15 or disc < 0:
            return None
        for t in ((-b - np.sqrt(disc)) / a, (-b + np.sqrt(disc)) / a):
            x = oc + t * d
            if t > 0 and abs(x @ self.axis) <= self.half_length:
                radial = x - (x @ self.axis) * self.axis
                return t, radial / np.linalg.norm(radial)
        return None


class Plane:
    """A finite planar patch: the disc of radius half_extent around `point`.

    The schema gives no in-plane axes, so the patch cannot be a square of
    known orientation; the disc holds the square's inscribed circle.
    """

    def __init__(self, point, normal, half_extent):
        self.point = _vec(point, "plane point")
        self.normal = _unit(normal, "plane normal")
        self.half_extent = _positive(half_extent, "plane half_extent")

    def distance(self, pts):
        d = pts - self.point
        h = d @ self.normal
        in_plane = np.linalg.norm(d - np.outer(h, self.normal), axis=1)
        beyond = np.maximum(in_plane - self.half_extent, 0.0)
        return np.where(h >= 0, 1.0, -1.0) * np.hypot(h, beyond)

    def hit(self, o, d):
        den = d @ self.normal
        if abs(den) < 1e-12:
            return None
        t = ((self.point - o) @ self.normal) / den
        x = o + t * d - self.point
        if t <= 0 or np.linalg.norm(x - (x @ self.normal) * self.normal) > self.half_extent:
            return None
        return t, self.normal


def surface_from_dict(s):
    kind = s.get("type")
    try:
        if kind == "sphere":
            return Sphere(s["centre"], s["radius"])
        if kind == "cylinder":
            return Cylinder(s["centre"], s["axis"], s["radius"], s["half_length"])
        if kind == "plane":
            return Plane(s["point"], s["normal"], s["half_extent"])
    except KeyError as e:
        raise ValueError(f"{kind} surface lacks {e}") from None
    raise ValueError(f"unknown surface type {kind!r}")


def parse_scene(text):
    """(name, [surfaces]) of a scene YAML text; ValueError when malformed."""
    doc = yaml.safe_load(text)
    if not isinstance(doc, dict) or not isinstance(doc.get("surfaces"), list) or not doc["surfaces"]:
        raise ValueError("scene YAML needs a non-empty 'surfaces' list")
    return str(doc.get("name", "")), [surface_from_dict(s) for s in doc["surfaces"]]


def parse_globe_info(text):
    """The globe bags' /globe/info: one sphere."""
    doc = yaml.safe_load(text)
    return "globe", [Sphere(doc["centre"], doc["radius"])]


def first_hit(surfaces, o, d):
    """(t, unit normal facing the ray's origin) of the nearest surface hit by o + t d, None on a miss."""
    o, d = np.asarray(o, dtype=float), np.asarray(d, dtype=float) / np.linalg.norm(d)
    hits = [h for h in (s.hit(o, d) for s in surfaces) if h is not None]
    if not hits:
        return None
    t, n = min(hits, key=lambda h: h[0])
    return t, (n if n @ d < 0 else -n)


def distance_to_scene(points, surfaces):
    """Unsigned distance [m] of (N, 3) points to the nearest surface."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    return np.min(np.abs(np.stack([s.distance(pts) for s in surfaces])), axis=0)


def map_error(points, r, t, surfaces, s=1.0):
    """RMS and median distance [m] of the aligned map (s R p + t) to the scene."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if pts.size == 0:
        raise ValueError("empty map")
    d = distance_to_scene(s * (r @ pts.T).T + t, surfaces)
    return float(np.sqrt(np.mean(d ** 2))), float(np.median(d))
