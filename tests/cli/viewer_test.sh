#!/usr/bin/env bash
# The web viewer in a real browser: `ricci view` and `ricci param --pictures` pages opened by
# headless Chromium (WebGL through SwiftShader, on the CPU) for a torus, a closed genus-2 surface
# with cones, a disk and the projective texture coordinates of `--faces refinement`. Each page
#   - loads without an error or warning: <html data-status="ok"> in the DOM after load (set
#     once the first frame is drawn), no data-error (uncaught exceptions and console.error,
#     three.js's shader compile errors included), no data-warnings, and no console message in
#     Chromium's log but the driver's own "GPU stall due to ReadPixels";
#   - draws both views: in a 1200 x 600 screenshot the left half (surface) and the right half
#     (layout) each show the checkerboard (viewer_check.py halves), with seams, cones and a
#     highlighted face where expected;
#   - (the disk) answers real mouse events sent through the DevTools protocol: hover, drag,
#     wheel, the checker slider and the colouring menu (viewer_check.py interact);
# and the surface divides by w: the refinement's projective page and its linear twin
# (.linear.obj: the same layout, uv interpolated linearly) draw the same layout but different
# surfaces.
#
# Usage: RICCI=build/ricci [CHROMIUM=chromium] bash tests/cli/viewer_test.sh [SCRATCH_DIR]
set -u
here="$(cd "$(dirname "$0")" && pwd)"
# The checks run in a scratch folder: a relative RICCI made absolute first.
[[ -n "${RICCI:-}" && "$RICCI" != /* && -x "$RICCI" ]] && RICCI="$PWD/$RICCI"
source "$here/check_framework.sh" viewer_test "${1:-}"

CHROMIUM="${CHROMIUM:-chromium}"
check="$here/viewer_check.py"
# SwiftShader is Chromium's CPU implementation of WebGL; as root the sandbox must be off.
browser_flags=(--headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader
               --disable-gpu-sandbox --user-data-dir="$WORK/profile" --window-size=1200,600
               --hide-scrollbars)

ricci() {
  "$RICCI" "$@" >"$WORK/out.txt" 2>"$WORK/err.txt" || {
    fail "ricci $*" "exit code $?: $(head -n 3 "$WORK/err.txt" | tr '\n' ' ')"
    return 1
  }
  ok
}

# load NAME PAGE [FRAGMENT]: the page's DOM after load is NAME.dom, the browser's log NAME.log.
load() {
  local name="$1" url="file://$WORK/$2${3:-}"
  timeout 60 "$CHROMIUM" "${browser_flags[@]}" --enable-logging=stderr --v=0 --dump-dom "$url" \
    >"$name.dom" 2>"$name.log"
  check_dom "$name" "$name.log"
}

# check_dom NAME LOG: NAME.dom says the page loaded without error or warning; LOG has no console
# message.
check_dom() {
  local name="$1" log="$2"
  local root
  root="$(grep -o -m 1 '<html[^>]*>' "$name.dom")"
  if [[ "$root" == *'data-status="ok"'* ]]; then ok; else
    fail "$name: page status" "${root:-no DOM} $(grep -o 'Uncaught[^"]*' "$log" | head -n 2)"
  fi
  if [[ "$root" == *data-error=* || "$root" == *data-warnings=* ]]; then
    fail "$name: errors or warnings" "$root"
  else ok; fi
  quiet_console "$name" "$log"
}

# quiet_console NAME LOG: no console message of the page in Chromium's log (it logs them as
# CONSOLE) but the driver's note that reading the picture back stalls the (software) GPU.
quiet_console() {
  local messages
  messages="$(grep 'CONSOLE' "$2" | grep -v 'GPU stall due to ReadPixels')"
  if [[ -z "$messages" ]]; then ok; else fail "$1: console" "$(head -c 400 <<<"$messages")"; fi
}

# shot NAME PAGE [FRAGMENT] [CHECK FLAGS...]: screenshot NAME.png, both halves checked.
# With SHOT_DOM=1 the same browser run also dumps the DOM, checked as load does (one launch of
# Chromium instead of two: each costs seconds of CPU).
shot() {
  local name="$1" page="$2" fragment="${3:-}"
  shift 3
  rm -f "$WORK/$name.png"
  if [[ "${SHOT_DOM:-0}" == 1 ]]; then
    timeout 60 "$CHROMIUM" "${browser_flags[@]}" --enable-logging=stderr --v=0 --dump-dom \
      --screenshot="$WORK/$name.png" "file://$WORK/$page$fragment" >"$name.dom" 2>"$name.shot.log"
    check_dom "$name" "$name.shot.log"
  else
    timeout 60 "$CHROMIUM" "${browser_flags[@]}" --enable-logging=stderr --v=0 \
      --screenshot="$WORK/$name.png" "file://$WORK/$page$fragment" >/dev/null 2>"$name.shot.log"
  fi
  if [[ ! -s "$WORK/$name.png" ]]; then
    fail "$name: screenshot" "none written: $(grep -v dbus "$name.shot.log" | tail -n 2)"
    return
  fi
  quiet_console "$name (screenshot)" "$name.shot.log"
  local problems
  if problems="$("$PYTHON" "$check" halves "$WORK/$name.png" "$@")"; then ok; else
    fail "$name: pixels" "$(tr '\n' ';' <<<"$problems")"
  fi
}

if ! command -v "$CHROMIUM" >/dev/null; then
  echo "viewer_test: $CHROMIUM not found" >&2
  exit 2
fi

# The meshes and their layouts.
ricci generate torus -o torus.obj
ricci generate surface --genus 2 -o genus2.obj
ricci generate disk -o disk.obj
ricci param torus.obj -o torus_uv.obj
ricci param disk.obj -o disk_uv.obj
# Genus 2 with the default (automatic) cones; the pictures' view.html comes from the result.
ricci param genus2.obj -o genus2_uv.obj --pictures genus2_pictures
# The exact map: one projective map per face of the common refinement (vt u v w).
ricci param genus2.obj --scheme vertex-scaling --faces refinement -o genus2_exact.obj \
  --pictures exact_pictures

ricci view torus_uv.obj -o torus.html
# glTF binary as param writes it: read back (seams welded again) and shown like the OBJ.
ricci param torus.obj -o torus.glb
ricci view torus.glb -o torus_glb.html
grep -q 'seam edges, 0 cones' "$WORK/out.txt" && ok || fail "view glb" "$(cat "$WORK/out.txt")"
ricci view disk_uv.obj -o disk.html --title "disk <test>"
grep -q '<title>disk &lt;test&gt;</title>' disk.html && ok || fail "view --title" "not in <title>"
ricci view genus2_uv.obj -o genus2.html --colour area
ricci view genus2_exact.obj -o exact.html --checker 64
ricci view genus2_exact.linear.obj -o linear.html --checker 64
grep -q 'projective texture coordinates' "$WORK/out.txt" && fail "view linear" "called projective" || ok
ricci view genus2_exact.obj -o exact_out.html
grep -q 'projective texture coordinates (vt u v w)' "$WORK/out.txt" && ok ||
  fail "view projective" "not reported: $(cat "$WORK/out.txt")"

# Refusals: no page, a clear message.
"$RICCI" view torus_uv.obj -o torus.png >/dev/null 2>"$WORK/err.txt"
[[ $? == 2 ]] && grep -q '.html' "$WORK/err.txt" && ok || fail "view -o .png" "not refused"
"$RICCI" view torus.obj -o plain.html >/dev/null 2>"$WORK/err.txt"
[[ $? == 2 && ! -e plain.html ]] && ok || fail "view without vt" "not refused"

# DOM and screenshot in one browser run where a page gets both.
SHOT_DOM=1 shot torus torus.html "" --seams
SHOT_DOM=1 shot torus_glb torus_glb.html "" --seams
load genus2 genus2.html
SHOT_DOM=1 shot disk disk.html "#face=700" --seams --highlight
SHOT_DOM=1 shot pictures genus2_pictures/view.html "" --seams --cones
load exact_pictures exact_pictures/view.html
# The linked face: shown, and picked back by a pointer at its centre in both views.
grep -q 'data-picked="700 700"' disk.dom && ok || fail "disk: #face=700" "$(grep -o -m 1 '<html[^>]*>' disk.dom)"
grep -q '<b>face 700</b>' disk.dom && ok || fail "disk: hover box" "no face 700"
grep -q '24 cones\|[0-9] cones' genus2.dom && ok || fail "genus2: cones" "no cones in the stats"
grep -q '"projective": true' exact_pictures/view.html && ok || fail "exact pictures" "not projective"
grep -q 'projective uv' exact_pictures.dom && ok || fail "exact pictures: stats" "not projective"

shot exact exact.html "" --seams --cones
shot linear linear.html "" --seams --cones
# Real mouse events through the DevTools protocol: hovering either view shows the face's figures
# (compared with the data block), dragging turns the surface, the wheel zooms the layout, the
# checker slider and the colouring menu redraw both.
if problems="$("$PYTHON" "$check" interact disk.html "$CHROMIUM" "${browser_flags[@]}")"; then ok
else fail "disk: interaction" "$(tr '\n' ';' <<<"$problems")"; fi

# The checks can fail: a page whose layout shader does not compile reports the error, and its
# screenshot has no layout.
sed 's/void main() { gl_FragColor = vec4(faceColour(), 1.0); }/void main() { broken; }/' \
  torus.html >broken.html
timeout 60 "$CHROMIUM" "${browser_flags[@]}" --dump-dom "file://$WORK/broken.html" \
  >broken.dom 2>/dev/null
grep -q 'data-status="error" data-error="THREE.WebGLProgram: shader error' broken.dom && ok ||
  fail "broken page" "error not reported: $(grep -o -m 1 '<html[^>]*>' broken.dom | head -c 300)"

# Same layout, different surface: the shader divides by w. (The refinement's w spans 0.57..1
# here; measured: about 170 surface pixels differ, none of the layout's.)
if [[ -s exact.png && -s linear.png ]]; then
  if problems="$("$PYTHON" "$check" differ exact.png linear.png 40 10)"; then ok; else
    fail "projective surface" "$problems"
  fi
fi

finish
