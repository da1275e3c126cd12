#!/usr/bin/env python3
"""The role folders of hapi_eskf include only downwards (docs/DESIGN.md
"Architecture"): backend/ (the interface and what every algorithm shares)
includes no algorithm and no storage, covariance/ no algorithm, and each
algorithm folder only what lies below it. src/slam_backend_factory.cpp, at
the top, is the one file that may include every algorithm.

Checked on both include/hapi_eskf/<role>/ and src/<role>/ (src/ros is the
nodelet layer above everything). Exits 1 naming every offending include.

  include_layers_test.py [HAPI_ESKF_DIR]
"""
import pathlib
import re
import sys

# What each role may include besides the top-level vocabulary (types,
# status, settings, so3, ...) and itself.
ALLOWED = {
    "backend": set(),
    "covariance": {"backend"},
    "eskf": {"backend", "covariance", "keyframes"},
    "seif": {"backend", "covariance", "eskf"},
    "graph": {"backend", "covariance", "eskf"},
    "fastslam": {"backend"},
    "surface_motion": set(),
    "keyframes": {"backend"},
    "map_file": {"keyframes"},
    "session": {"backend", "covariance", "eskf", "keyframes", "map_file"},
}
# The top: the factory and the settings that compose every part's table
# (settings.hpp) sit above every folder; the rest of the top-level
# vocabulary (types, status, so3, field tables) includes no role folder.
TOP_COMPOSITION = {"slam_backend_factory.cpp", "slam_backend_factory.hpp", "settings.hpp", "settings.cpp"}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]hapi_eskf/([a-z_]+)/')
SUFFIXES = {".hpp", ".cpp", ".cu", ".cuh", ".def", ".h"}


def role_of(path, root):
    """The role folder of a file, or "top" for the vocabulary, None for others."""
    rel = path.relative_to(root).parts
    if rel[0] == "include":
        rel = rel[2:]  # include/hapi_eskf/...
    elif rel[0] == "src":
        rel = rel[1:]
    else:
        return None
    if len(rel) == 1:
        return "top"
    return rel[0] if rel[0] in ALLOWED else None


def offences(root):
    found = []
    for path in sorted(list((root / "include").rglob("*")) + list((root / "src").rglob("*"))):
        if path.suffix not in SUFFIXES or not path.is_file():
            continue
        role = role_of(path, root)
        if role is None:
            continue
        if role == "top" and path.name in TOP_COMPOSITION:
            continue  # above every folder by design
        for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = m.group(1)
            if target == role:
                continue
            if role == "top":
                ok = False
            else:
                ok = target in ALLOWED[role]
            if not ok:
                found.append(f"{path.relative_to(root)}:{n}: {role}/ includes {target}/: {line.strip()}")
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parents[1])
    bad = offences(root)
    for b in bad:
        print(b)
    if bad:
        print(f"FAIL: {len(bad)} include(s) against the layering")
        return 1
    files = sum(1 for p in list((root / "include").rglob("*")) + list((root / "src").rglob("*"))
                if p.suffix in SUFFIXES and role_of(p, root) is not None)
    print(f"ok: {files} files of hapi_eskf include only downwards")
    return 0


if __name__ == "__main__":
    sys.exit(main())
