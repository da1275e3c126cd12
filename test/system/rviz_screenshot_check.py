#!/usr/bin/python3
"""Checks that rviz's 3D view shows the landmark map in a screenshot.

    rviz_screenshot_check.py BEFORE.xwd AFTER.xwd OUT.png [--min-pixels N] [--background 48,48,48]

BEFORE.xwd and AFTER.xwd are `xwd -root` shots of the Xvfb screen with rviz
running hapi.rviz, taken before any map was published (rviz up, scene empty)
and while the pipeline runs. AFTER is converted to OUT.png (numpy + zlib, no
imaging library needed; BEFORE to OUT_before.png) and analysed:

1. The 3D view is located as the block of rows/columns dominated by rviz's
   background colour (hapi.rviz: Background Color 48; 48; 48); panels, the
   image dock and window decorations never use that colour. Both shots must
   show the same 3D view.
2. Map pixels are the pixels of the 3D view that changed between the two
   shots (any channel by more than 12), leaving out the saturated colours of
   the paths (25;255;0, 255;170;0), the pose arrow and the TF axes. The grid
   is in both shots and cancels; the map carries the camera image's colours
   (grey for the mono globe bag), never fully saturated.
3. Pass when there are at least --min-pixels map pixels. (Two shots of the
   empty scene give 0: the check can fail, and does when no map arrives.)

Exit status 0 pass, 1 fail (or unreadable input). Prints the figures.
"""
import argparse
import struct
import sys
import zlib

import numpy as np


def read_xwd(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 100:
        raise ValueError(f"{path}: not an XWD file (too short)")
    h = struct.unpack(">25I", data[:100])
    header_size, version = h[0], h[1]
    if version != 7:
        raise ValueError(f"{path}: XWD version {version}, expected 7")
    width, height = h[4], h[5]
    byte_order, bpp, bpl = h[7], h[11], h[12]
    masks = h[14:17]
    ncolors = h[19]
    if bpp not in (24, 32):
        raise ValueError(f"{path}: {bpp} bits per pixel, expected 24 or 32 (Xvfb -screen 0 WxHx24)")
    off = header_size + 12 * ncolors
    rows = np.frombuffer(data, dtype=np.uint8, count=height * bpl, offset=off).reshape(height, bpl)
    nb = bpp // 8
    b = rows[:, :width * nb].reshape(height, width, nb).astype(np.uint32)
    # Assemble each pixel's integer in the file's byte order, then apply the masks.
    order = range(nb) if byte_order == 0 else range(nb - 1, -1, -1)
    px = np.zeros((height, width), dtype=np.uint32)
    for shift, i in enumerate(order):
        px |= b[:, :, i] << np.uint32(8 * shift)
    rgb = np.empty((height, width, 3), dtype=np.uint8)
    for i, m in enumerate(masks):
        sh = (m & -m).bit_length() - 1
        rgb[:, :, i] = ((px & np.uint32(m)) >> np.uint32(sh)).astype(np.uint8)
    return rgb


def write_png(path, rgb):
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[r].tobytes() for r in range(h))

    def chunk(tag, payload):
        return struct.pack(">I", len(payload)) + tag + payload + struct.pack(">I", zlib.crc32(tag + payload) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def longest_run(flags, max_gap=12):
    """(start, stop) of the longest run of True in a 1-D bool array, bridging
    gaps of up to max_gap False entries (grid lines cross the 3D view)."""
    idx = np.flatnonzero(flags)
    if idx.size == 0:
        return 0, 0
    best, start, prev = (idx[0], idx[0] + 1), idx[0], idx[0]
    for i in list(idx[1:]) + [None]:
        if i is None or i - prev > max_gap + 1:
            if prev + 1 - start > best[1] - best[0]:
                best = (start, prev + 1)
            start = i
        prev = i if i is not None else prev
    return int(best[0]), int(best[1])


def view_region(rgb, bg):
    """Bounding box (r0, r1, c0, c1) of the 3D view, or None."""
    is_bg = np.all(rgb == np.array(bg, dtype=np.uint8), axis=2)
    if is_bg.sum() < 1000:
        return None
    cols = is_bg.mean(axis=0)
    c0, c1 = longest_run(cols > 0.25 * cols.max())
    rows = is_bg[:, c0:c1].mean(axis=1)
    r0, r1 = longest_run(rows > 0.25 * rows.max())
    return r0, r1, c0, c1


def map_pixels(before, after, region):
    r0, r1, c0, c1 = region
    b = before[r0:r1, c0:c1].astype(int)
    a = after[r0:r1, c0:c1].astype(int)
    changed = np.any(np.abs(a - b) > 12, axis=2)
    saturated = (a.max(axis=2) - a.min(axis=2) > 100) & (a.min(axis=2) < 60)
    content = changed & ~saturated
    colours = len(np.unique(a[content].reshape(-1, 3), axis=0)) if content.any() else 0
    return int(content.sum()), colours


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("png")
    ap.add_argument("--min-pixels", type=int, default=1500)
    ap.add_argument("--background", default="48,48,48")
    a = ap.parse_args()
    bg = [int(x) for x in a.background.split(",")]
    stem = a.png[:-4] if a.png.endswith(".png") else a.png
    try:
        before, after = read_xwd(a.before), read_xwd(a.after)
        write_png(a.png, after)
        write_png(stem + "_before.png", before)
    except (OSError, ValueError) as e:
        print(f"[rviz-check] FAIL: {e}")
        return 1
    rb, ra = view_region(before, bg), view_region(after, bg)
    print(f"[rviz-check] 3D view: before {rb}, after {ra} (rows r0-r1, cols c0-c1); screenshots {a.png}, "
          f"{stem}_before.png")
    if ra is None or rb is None:
        print(f"[rviz-check] FAIL: no 3D view with background {bg} in {'before' if rb is None else 'after'} "
              "(rviz not on screen?)")
        return 1
    if before.shape != after.shape or max(abs(x - y) for x, y in zip(ra, rb)) > 4:
        print("[rviz-check] FAIL: the 3D view moved between the shots; cannot compare")
        return 1
    n, colours = map_pixels(before, after, ra)
    ok = n >= a.min_pixels
    print(f"[rviz-check] {'PASS' if ok else 'FAIL'}: {n} map pixels in the 3D view ({colours} distinct colours), "
          f"need >= {a.min_pixels}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
