#!/usr/bin/env python3
"""Pixel checks of screenshots of the web viewer (tests/cli/viewer_test.sh), standard library only.

  viewer_check.py halves SHOT.png [--seams] [--cones] [--highlight]
      Both halves of the picture (the surface left, the texture layout right; the bar at the top
      left out) show the checkerboard: enough pixels off the background, dark (blue) and light
      squares both, and many changes between them along the rows. --seams: orange seam lines in
      the layout; --cones: red cone dots in the layout; --highlight: the hovered face's yellow in
      both halves.
  viewer_check.py differ A.png B.png MIN_LEFT MAX_RIGHT
      At least MIN_LEFT pixels of the left halves differ (by more than 40 in a channel) and at
      most MAX_RIGHT of the right halves.

Prints one line per failed check and exits 1 when one failed; prints the measures with -v.
"""

import struct
import sys
import zlib

TOP = 110  # rows of the bar and the panes' labels, left out


def read_png(path):
    """(width, height, rows of (r, g, b) tuples) of an 8-bit RGB or RGBA PNG (no interlace)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    at, idat, header = 8, [], None
    while at < len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        kind, body = data[at + 4:at + 8], data[at + 8:at + 8 + length]
        at += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace != 0:
        raise ValueError(f"{path}: only 8-bit RGB/RGBA without interlace (got {header})")
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    previous = bytearray(stride)
    rows = []
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            corner = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                nearest = left if pa <= pb and pa <= pc else up if pb <= pc else corner
                line[i] = (line[i] + nearest) & 255
        rows.append([tuple(line[x * channels:x * channels + 3]) for x in range(width)])
        previous = line
    return width, height, rows


def half_measures(rows, x0, x1, background):
    """Counts over the columns [x0, x1) below the bar (the pane border left out)."""
    m = {"pixels": 0, "off_background": 0, "dark": 0, "light": 0, "changes": 0,
         "seam": 0, "cone": 0, "highlight": 0}
    colours = set()
    br, bg, bb = background
    for row in rows[TOP:]:
        last = None
        for r, g, b in row[x0 + 2:x1 - 2]:
            off = max(abs(r - br), abs(g - bg), abs(b - bb))
            if off > 24:
                m["off_background"] += 1
            # Checker squares, shaded or not: blue ones, and grey ones off the background.
            if b > 110 and b - r > 60:
                kind = "dark"
            elif min(r, g, b) > 120 and max(r, g, b) - min(r, g, b) < 30 and off > 3:
                kind = "light"
            else:
                kind = None
            if kind:
                m[kind] += 1
                if last and kind != last:
                    m["changes"] += 1
                last = kind
            if r > 200 and 70 < g < 150 and b < 80:
                m["seam"] += 1  # orange
            elif r > 170 and g < 90 and b < 90:
                m["cone"] += 1  # red
            elif r > 190 and g > 170 and b < 125 and g - b > 80 and r - g < 50:
                m["highlight"] += 1  # yellow
            colours.add((r >> 3, g >> 3, b >> 3))
    m["pixels"] = (len(rows) - TOP) * max(x1 - x0 - 4, 0)
    m["colours"] = len(colours)
    return m


def halves(path, flags, verbose):
    width, height, rows = read_png(path)
    problems = []
    for name, x0, x1, background in (("surface (left)", 0, width // 2, (255, 255, 255)),
                                     ("layout (right)", width // 2, width, (247, 247, 245))):
        m = half_measures(rows, x0, x1, background)
        if verbose:
            print(f"{path} {name}: {m}")
        share = lambda key: m[key] / max(m["pixels"], 1)
        if share("off_background") < 0.05:
            problems.append(f"{name}: only {share('off_background'):.1%} off the background")
        for key in ("dark", "light"):
            if share(key) < 0.01:
                problems.append(f"{name}: {key} checker squares on {share(key):.2%} of the pixels")
        if m["changes"] < 40:
            problems.append(f"{name}: {m['changes']} dark/light changes along the rows (no checker)")
        if m["colours"] < 8:
            problems.append(f"{name}: {m['colours']} colours")
        if "--highlight" in flags and m["highlight"] < 3:
            problems.append(f"{name}: no highlighted face ({m['highlight']} yellow pixels)")
        if name.startswith("layout"):
            if "--seams" in flags and m["seam"] < 20:
                problems.append(f"{name}: no seams ({m['seam']} orange pixels)")
            if "--cones" in flags and m["cone"] < 20:
                problems.append(f"{name}: no cone dots ({m['cone']} red pixels)")
    return problems


def differ(path_a, path_b, min_left, max_right, verbose):
    wa, ha, a = read_png(path_a)
    wb, hb, b = read_png(path_b)
    if (wa, ha) != (wb, hb):
        return [f"{path_a} is {wa} x {ha} but {path_b} is {wb} x {hb}"]
    counts = [0, 0]
    for y in range(TOP, ha):
        for x in range(wa):
            if max(abs(a[y][x][i] - b[y][x][i]) for i in range(3)) > 40:
                counts[0 if x < wa // 2 else 1] += 1
    if verbose:
        print(f"differing pixels: left {counts[0]}, right {counts[1]}")
    problems = []
    if counts[0] < min_left:
        problems.append(f"left halves differ in {counts[0]} pixels, expected at least {min_left}")
    if counts[1] > max_right:
        problems.append(f"right halves differ in {counts[1]} pixels, expected at most {max_right}")
    return problems


def main(argv):
    verbose = "-v" in argv
    argv = [a for a in argv if a != "-v"]
    if len(argv) >= 2 and argv[0] == "halves":
        problems = halves(argv[1], set(argv[2:]), verbose)
    elif len(argv) == 5 and argv[0] == "differ":
        problems = differ(argv[1], argv[2], int(argv[3]), int(argv[4]), verbose)
    else:
        print(__doc__)
        return 2
    for problem in problems:
        print(problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
