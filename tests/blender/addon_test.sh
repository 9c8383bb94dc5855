#!/usr/bin/env bash
# The Blender add-on end to end: `ricci blender-addon` writes the zip, a headless Blender
# installs and enables it the usual way and unwraps generated meshes (tests/blender/
# addon_check.py, which checks the UVs with ../shared/tools/checkuv.py). Blender's user folders
# point into the scratch folder, so that nothing is installed for the user running the test.
# Exits 77 (skipped) without Blender or without ../shared/tools/checkuv.py, once the zip's own
# checks passed.
#   RICCI=build/ricci [BLENDER=blender] bash tests/blender/addon_test.sh [SCRATCH_DIR]
set -u
here="$(cd "$(dirname "$0")" && pwd)"
[[ -n "${RICCI:-}" && "$RICCI" != /* && -x "$RICCI" ]] && RICCI="$PWD/$RICCI"
BLENDER="${BLENDER:-blender}"
checkuv="${RICCI_CHECKUV:-$here/../../../shared/tools/checkuv.py}"
source "$here/../cli/check_framework.sh" addon_test "${1:-}"

# The zip: the add-on and the compiled module; refusals leave nothing behind.
"$RICCI" blender-addon -o ricci_uv.zip >addon.log 2>&1 && ok ||
  fail "ricci blender-addon" "$(cat addon.log)"
listing="$("$PYTHON" -c "import sys, zipfile; print('\n'.join(zipfile.ZipFile(sys.argv[1]).namelist()))" ricci_uv.zip)"
for f in ricci_uv/__init__.py ricci_uv/operator.py ricci_uv/unwrap.py ricci_uv/ricci/__init__.py; do
  grep -qx "$f" <<<"$listing" && ok || fail "zip holds $f" "$listing"
done
grep -q '^ricci_uv/ricci/_ricci\..*\.so$' <<<"$listing" && ok || fail "zip holds the module" "$listing"
"$RICCI" blender-addon -o addon.tar >/dev/null 2>err.txt
[[ $? == 2 && ! -e addon.tar ]] && grep -q '\.zip' err.txt && ok || fail "-o addon.tar" "$(cat err.txt)"
"$RICCI" blender-addon --python-package "$WORK" -o other.zip >/dev/null 2>err.txt
[[ $? == 2 && ! -e other.zip ]] && grep -q 'not the ricci Python package' err.txt && ok ||
  fail "--python-package of another folder" "$(cat err.txt)"

skip() {  # after the checks above: exit 77 when they passed
  echo "addon_test: skipped: $1"
  ((failed > 0)) && finish
  cd / && rm -rf "$WORK"
  exit 77
}
command -v "$BLENDER" >/dev/null ||
  skip "$BLENDER not found (scripts/install-deps.sh installs Debian's blender)"
[[ -f "$checkuv" ]] || skip "$checkuv not found"

"$RICCI" generate torus -o torus.obj >/dev/null && ok || fail "generate torus" ""
"$RICCI" generate surface --genus 2 -o genus2.obj >/dev/null && ok || fail "generate genus 2" ""
mkdir -p scripts config
if BLENDER_USER_SCRIPTS="$WORK/scripts" BLENDER_USER_CONFIG="$WORK/config" \
  timeout 600 "$BLENDER" -b --factory-startup --python-exit-code 1 \
  -P "$here/addon_check.py" -- "$WORK/ricci_uv.zip" "$WORK" "$checkuv" torus.obj genus2.obj \
  >blender.log 2>&1; then
  ok
else
  fail "blender" "$(grep -E '^FAIL|Error|Traceback' blender.log | head -n 20)"
fi
grep -E '^(ok|FAIL|     )' blender.log

# The menu's way (modal: the work in a thread, the interface drawing on) and Blender's undo need
# a window: Blender under a virtual X server (xvfb-run), on a mesh large enough to take several
# of the operator's timer ticks.
if command -v xvfb-run >/dev/null; then
  "$RICCI" generate surface --genus 2 --resolution 90 -o genus2.obj >/dev/null && ok ||
    fail "generate a larger genus 2" ""
  if BLENDER_USER_SCRIPTS="$WORK/scripts" BLENDER_USER_CONFIG="$WORK/config" \
    timeout 300 xvfb-run -a -s "-screen 0 1280x800x24" "$BLENDER" --factory-startup \
    -P "$here/modal_check.py" -- "$WORK/ricci_uv.zip" "$WORK/genus2.obj" >modal.log 2>&1; then
    ok
  else
    fail "blender (modal, undo)" "$(grep -E '^FAIL|Error|Traceback' modal.log | head -n 20)"
  fi
  grep -E '^(ok|FAIL)' modal.log
else
  echo "note: xvfb-run not found: the modal run and undo are not checked (apt install xvfb)"
fi
finish
