#!/usr/bin/env bash
# `ricci match` and `ricci morph` end to end (issue 29): a rotated, scaled and renumbered copy of
# a sphere matched by landmarks (every vertex onto its copy), the map file's shape, the report,
# the reverse map, signatures of genus-2 surfaces, a morph's frames and strip, and the refusals
# (different topologies, a genus-2 pair without --signature, a bad landmarks line), each with
# exit code 2 and no output.
#
# Usage: RICCI=/path/to/ricci bash tests/cli/match_test.sh [SCRATCH_DIR]
set -u

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# shellcheck source=check_framework.sh
source "$here/check_framework.sh" match "${1:-}"

"$RICCI" generate icosphere --resolution 3 -o a.obj >/dev/null || exit 2
"$RICCI" generate torus -o torus.obj >/dev/null || exit 2
"$RICCI" generate surface --genus 2 -o g2.obj >/dev/null || exit 2
# B: A rotated, scaled and moved, its vertices listed in reverse order (B's vertex n-1-v is A's v).
"$PYTHON" - <<'PY' || exit 2
import math
V, F = [], []
for line in open("a.obj"):
    t = line.split()
    if t and t[0] == "v": V.append(tuple(map(float, t[1:4])))
    if t and t[0] == "f": F.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
n = len(V)
c, s = 0.6, 0.8
with open("b.obj", "w") as out:
    for x, y, z in reversed(V):
        out.write("v %.17g %.17g %.17g\n" % (2 * (c * x - s * z) + 1, 2 * y, 2 * (s * x + c * z) - 3))
    for f in F:
        out.write("f %d %d %d\n" % tuple(n - 1 - i + 1 for i in f))
with open("landmarks.txt", "w") as out:
    out.write("# vertex of A, vertex of B\n")
    for v in (0, 7, 200, 500):
        out.write("%d %d\n" % (v, n - 1 - v))
PY

if "$RICCI" match a.obj b.obj -o map.txt --reverse back.txt --landmarks landmarks.txt \
    --report report.json >out.txt 2>err.txt; then ok; else fail "match" "exit $? $(cat err.txt)"; fi
"$PYTHON" - <<'PY' && ok || fail "map" "the map file or the report is wrong"
import json
n = sum(1 for l in open("a.obj") if l.startswith("v "))
faces = [[int(x) - 1 for x in l.split()[1:4]] for l in open("b.obj") if l.startswith("f ")]
B = [tuple(map(float, l.split()[1:4])) for l in open("b.obj") if l.startswith("v ")]
rows = [l.split() for l in open("map.txt") if not l.startswith("#")]
assert len(rows) == n, (len(rows), n)
worst = 0
for v, row in enumerate(rows):
    f, w = int(row[0]), list(map(float, row[1:4]))
    assert abs(sum(w) - 1) < 1e-12 and min(w) >= 0
    p = [sum(w[k] * B[faces[f][k]][c] for k in range(3)) for c in range(3)]
    q = B[n - 1 - v]
    worst = max(worst, max(abs(p[c] - q[c]) for c in range(3)))
assert worst < 1e-6, worst
back = [l for l in open("back.txt") if not l.startswith("#")]
assert len(back) == n
r = json.load(open("report.json"))
assert r["domain"] == "sphere" and r["alignment"]["method"] == "landmarks", r
assert r["landmarks"]["count"] == 4 and r["landmarks"]["max"] < 1e-6, r["landmarks"]
assert r["distortion"]["flipped_faces"] == 0 and r["distortion"]["angle_distortion_mean"] < 1 + 1e-6
PY

# Signatures: the same genus-2 surface twice gives the same traces; a torus its modulus.
if "$RICCI" match g2.obj g2.obj --signature >sig.json 2>err.txt; then ok; else fail "signature" "$(cat err.txt)"; fi
"$PYTHON" -c '
import json; s = json.load(open("sig.json"))
a, b = s["signature_a"]["fuchsian_traces"], s["signature_b"]["fuchsian_traces"]
assert len(a) == 4 and all(t > 2 for t in a) and a == b, s' && ok || fail "signature" "traces"
"$RICCI" match torus.obj torus.obj --signature >sigt.json 2>err.txt && "$PYTHON" -c '
import json; m = json.load(open("sigt.json"))["signature_a"]["modulus"]
assert m[1] >= 1 and abs(m[0]) <= 0.5, m' && ok || fail "torus signature" "$(cat err.txt)"

# Morph: frames and the strip.
if "$RICCI" morph a.obj b.obj --frames 4 --landmarks landmarks.txt -o morph >out.txt 2>err.txt &&
  [[ -f morph/frame_000.obj && -f morph/frame_003.obj && ! -e morph/frame_004.obj ]]; then
  ok
else
  fail "morph" "$(cat err.txt)"
fi
if "$RICCI" --help | grep -q "render"; then
  [[ -s morph/strip.png ]] && ok || fail "morph strip" "no strip.png"
fi

# Refusals: exit 2, a message naming the problem, no output.
expect_refusal() {  # NAME PATTERN OUTPUT ARGS...
  local name="$1" pattern="$2" output="$3"
  shift 3
  "$RICCI" "$@" >out.txt 2>err.txt
  local code=$?
  if [[ $code -ne 2 ]]; then fail "$name" "exit $code, expected 2"; return; fi
  if ! grep -q -- "$pattern" err.txt; then fail "$name" "message: $(cat err.txt)"; return; fi
  if [[ -e "$output" ]]; then fail "$name" "wrote $output"; return; fi
  ok
}
expect_refusal "different topologies" "different domains\|same topology" x1.txt match a.obj torus.obj -o x1.txt
expect_refusal "genus 2" "try: ricci match A B --signature" x2.txt match g2.obj g2.obj -o x2.txt
printf '0 1\n3 x\n' >bad_landmarks.txt
expect_refusal "bad landmarks" "bad_landmarks.txt:2" x3.txt match a.obj b.obj -o x3.txt --landmarks bad_landmarks.txt
printf '0 99999\n' >far_landmarks.txt
expect_refusal "landmark out of range" "far_landmarks.txt:1: vertex 99999" x4.txt match a.obj b.obj -o x4.txt --landmarks far_landmarks.txt
expect_refusal "one frame" "at least 2" morph1 morph a.obj b.obj --frames 1 -o morph1

finish
