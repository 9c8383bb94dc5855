#!/usr/bin/python3
"""Pictures and figures of docs/matching.md: spot (../shared/meshes/spot.obj) matched to bent
copies of itself (x rolled onto a circle about y), with and without 4 landmarks (the extremes of
its two widest axes), against the known correspondence (same vertex); the checkerboard carried
from A to B (radius 1.2, 4 landmarks) and the morph's strip.

Usage: PYTHONPATH=build/python bench/match_pictures.py RICCI OUT_DIR [MESH]
"""
import os
import subprocess
import sys

import numpy as np

import ricci

ricci_exe, out = sys.argv[1], sys.argv[2]
mesh = sys.argv[3] if len(sys.argv) > 3 else os.path.join(os.path.dirname(__file__), "..", "..", "shared", "meshes", "spot.obj")
os.makedirs(out, exist_ok=True)
VA, FA = ricci.read_mesh(mesh)[:2]


def bend(V, radius, axis=1):
    V = V.copy()
    x, h = V[:, 0].copy(), V[:, axis].copy()
    V[:, 0] = (radius - h) * np.sin(x / radius)
    V[:, axis] = radius - (radius - h) * np.cos(x / radius)
    return V


def checker(P, lo, extent, first, second):
    return np.stack([(P[:, first] - lo[first]) / extent[first], (P[:, second] - lo[second]) / extent[first]], axis=1)


def write_textured(path, V, F, uv):
    with open(path, "w") as f:
        for v in V:
            f.write("v %.17g %.17g %.17g\n" % tuple(v))
        for t in uv:
            f.write("vt %.17g %.17g\n" % tuple(t))
        for t in F:
            f.write("f %d/%d %d/%d %d/%d\n" % (t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1, t[2] + 1))


lo, hi = VA.min(axis=0), VA.max(axis=0)
extent = hi - lo
first = int(np.argmax(extent))
second = [a for a in range(3) if a != first][int(np.argmax([extent[a] for a in range(3) if a != first]))]
diagonal = np.linalg.norm(extent)
rows = []
for radius in (1e9, 4.0, 2.0, 1.2):
    VB = bend(VA, radius)
    dB = np.linalg.norm(VB.max(axis=0) - VB.min(axis=0))
    for name, landmarks in (("none", None), ("4", np.array([[v, v] for v in np.argsort(VA[:, first])[[0, -1]].tolist() + np.argsort(VA[:, second])[[0, -1]].tolist()]))):
        m = ricci.match(VA, FA, VB, FA, landmarks=landmarks, reverse=True)
        err = np.linalg.norm(m.positions - VB, axis=1) / dB
        rows.append((radius, name, m.method, err.mean(), err.max(), m.angle_distortion_mean, m.flipped_faces, m.seconds))
    if radius == 1.2:
        uvA = checker(VA, lo, extent, first, second)
        uvB = checker(m.reverse_positions, lo, extent, first, second)
        write_textured(os.path.join(out, "A.obj"), VA, FA, uvA)
        write_textured(os.path.join(out, "B.obj"), VB, FA, uvB)
        for n in ("A", "B"):
            subprocess.run([ricci_exe, "render", os.path.join(out, n + ".obj"), "-o", os.path.join(out, "spot_" + n + ".png"),
                            "--width", "480", "--height", "480", "--checker", "8", "--smooth"], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "B_plain.obj"), "w") as f:
            for v in VB:
                f.write("v %.17g %.17g %.17g\n" % tuple(v))
            for t in FA:
                f.write("f %d %d %d\n" % tuple(t + 1))
        with open(os.path.join(out, "landmarks.txt"), "w") as f:
            for i, j in landmarks:
                f.write("%d %d\n" % (i, j))
        subprocess.run([ricci_exe, "morph", mesh, os.path.join(out, "B_plain.obj"), "--frames", "5", "-o", os.path.join(out, "morph"),
                        "--landmarks", os.path.join(out, "landmarks.txt")], check=True, stdout=subprocess.DEVNULL)
print("| bend radius | landmarks | alignment | mean error | max error | map angle distortion | flipped | seconds |")
print("|---|---|---|---|---|---|---|---|")
for r in rows:
    print("| %s | %s | %s | %.4f | %.4f | %.4f | %d | %.2f |" % ("none" if r[0] > 1e8 else "%g" % r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7]))
