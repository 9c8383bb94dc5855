#!/usr/bin/python3
"""Every refusal of the `ricci` program that names a fix ("try: --cones auto, or --cones one")
names one that works: each case provokes one, the test reads the fixes off the "try:" line,
applies each to the same command and expects exit 0.

A fix is applied the way its phrasing says (apps/ricci/fixes.hpp): "--option value" sets the
option (replacing the value given, if any), "--flag" adds a flag, "--repair=mode" replaces any
--repair, "drop --flag" removes the flag (or the option with its value: "drop --cones").

The sources are searched for the places that attach fixes (fixes_of, OptionFix{...}, ...); a
place no case covers fails the test, so that a new refusal with a fix comes with its case.

Usage: RICCI=/path/to/ricci /usr/bin/python3 tests/cli/fixes_test.py SOURCE_DIR [SCRATCH_DIR]
Prints one line per check and "N passed, M failed, K expected failures"; exits 1 when a check
failed (the scratch folder is then kept).
"""

import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile

RICCI = os.environ.get("RICCI", "")


# --- cases ----------------------------------------------------------------------------------------

# A case: a name, the places in the sources whose fixes it provokes ("file:marker", see SITES
# below), the command (after `ricci`), the exit code the refusal has, the printed fixes that are
# known not to work, each with the reason (expected failures: reported, not failed), and, for a
# refusal reported elsewhere that this build may not make, why it may succeed instead.
Case = collections.namedtuple("Case", "name sites args exit_code broken may_succeed",
                              defaults=(2, {}, ""))

# Issue 25: on high-genus closed surfaces a fixed count too small ("--cones 8") was refused with
# "N automatic cones cannot carry the curvature" and fixes ("--cones 2N+2", "--cones auto") that
# failed the same way, automatic cones being capped (ConeSelectionOptions::max_cones). The cone
# rework for high genus (src/param/cones/cones.cpp, parameterize.cpp) is another change's; where this
# build refuses, a fix that fails is listed here as expected, not failed.
HIGH_GENUS = ("issue 25: automatic cones on high genus are capped (param/cones/cones.hpp); the cone "
              "rework for high genus is to fix it")
HIGH_GENUS_PARAMETERIZED = ("this build parameterizes it (the refusal of issue 25 is not made "
                            "here); nothing to check")

STRONG_CONES = "0:-2pi,5:1.5pi,11:1.5pi,20:1.5pi,30:1.5pi"
THURSTON_BOUND = "0:-4pi,1:pi,2:pi,3:pi,4:pi,5:pi,6:pi,7:pi,8:pi"


def cases(boundary_vertex):
    return [
        # Mesh input: refusals of --strict and --repair=never, and --largest-component with them.
        Case("flow --strict on a non-manifold edge", ["apps/ricci/input_options.cpp:strict"],
             ["flow", "fin.obj", "--strict", "-o", "out.json"]),
        Case("param --repair=never on duplicate faces", ["apps/ricci/input_options.cpp:repair"],
             ["param", "duplicate.obj", "--repair=never", "-o", "out.obj"]),
        Case("param --strict on a sliver", ["apps/ricci/input_options.cpp:strict"],
             ["param", "sliver.obj", "--strict", "-o", "out.obj"]),
        Case("sphere --strict on inconsistent orientation", ["apps/ricci/input_options.cpp:strict"],
             ["sphere", "flipped_ico.obj", "--strict", "-o", "out.obj"]),
        Case("spline --strict on a bow-tie", ["apps/ricci/input_options.cpp:strict"],
             ["spline", "flipped_ico.obj", "--strict", "-o", "out.obj"]),
        Case("info --strict --largest-component", ["apps/ricci/input_options.cpp:largest"],
             ["info", "bowtie.obj", "--strict", "--largest-component"]),
        Case("--largest-component with --strict", ["apps/ricci/input_options.cpp:largest"],
             ["param", "two_parts.obj", "--strict", "--largest-component", "-o", "out.obj"]),
        Case("--largest-component with --repair=never", ["apps/ricci/input_options.cpp:largest"],
             ["flow", "two_parts.obj", "--repair=never", "--largest-component"]),
        Case("render --strict on a defective textured OBJ",
             ["apps/ricci/render_command.cpp:strict"],
             ["render", "flipped_uv.obj", "--strict", "-o", "out.png", "--width", "32",
              "--height", "32"]),
        # Targets and schemes (src/flow/target.cpp).
        Case("flow: flat target on a sphere", ["src/flow/target.cpp:gauss-bonnet"],
             ["flow", "ico.obj", "--target", "flat"]),
        Case("flow: a cone on the free boundary", ["src/flow/target.cpp:boundary"],
             ["flow", "disk.obj", "--cones", f"{boundary_vertex}:pi/2"]),
        Case("flow: Thurston's vertex bound", ["src/flow/target.cpp:vertex-bound"],
             ["flow", "ico.obj", "--scheme", "thurston", "--cones", THURSTON_BOUND]),
        Case("flow: Thurston's vertex bound, the tangential one kept",
             ["src/flow/target.cpp:vertex-bound"],
             ["flow", "ico.obj", "--scheme", "thurston", "--cones", STRONG_CONES]),
        Case("flow: tangential scheme's vertex bound", ["src/flow/target.cpp:vertex-bound"],
             ["flow", "ico.obj", "--scheme", "tangential", "--cones", THURSTON_BOUND]),
        Case("flow: vertex scaling without flips, vertex bound",
             ["src/flow/target.cpp:vertex-bound"],
             ["flow", "ico.obj", "--flips", "off", "--cones", THURSTON_BOUND]),
        Case("flow: cones breaking Gauss-Bonnet",
             ["src/flow/target.cpp:gauss-bonnet", "apps/ricci/flow_command.cpp:cones"],
             ["flow", "ico.obj", "--cones", "0:pi"]),
        Case("flow: hyperbolic torus", ["src/flow/target.cpp:hyperbolic"],
             ["flow", "torus.obj", "--geometry", "hyperbolic"]),
        # A flow that stops short (exit 3) names its fix too (src/flow/ricci_flow.cpp).
        Case("flow: strong cones without flips", ["src/flow/ricci_flow.cpp:flips"],
             ["flow", "ico.obj", "--flips", "off", "--cones", STRONG_CONES], 3),
        # Parameterization (src/param/one_component.cpp, hyperbolic_param.cpp).
        Case("param: sphere without cones", ["src/param/one_component.cpp:none"],
             ["param", "ico.obj", "--cones", "none", "-o", "out.obj"]),
        Case("param: genus 2 without cones", ["src/param/one_component.cpp:none"],
             ["param", "genus2.obj", "--cones", "none", "-o", "out.obj"]),
        Case("param: one cone on a torus", ["src/param/one_component.cpp:one"],
             ["param", "torus.obj", "--cones", "one", "-o", "out.obj"]),
        Case("param: user cones breaking Gauss-Bonnet", ["src/param/one_component.cpp:user"],
             ["param", "ico.obj", "--cones", "0:pi", "-o", "out.obj"]),
        Case("param: one automatic cone on a sphere", ["src/param/one_component.cpp:count"],
             ["param", "ico.obj", "--cones", "1", "-o", "out.obj"]),
        Case("param: 2 automatic cones on a sphere", ["src/param/one_component.cpp:count"],
             ["param", "ico.obj", "--cones", "2", "-o", "out.obj"]),
        Case("param: 8 automatic cones on genus 20", ["src/param/one_component.cpp:count"],
             ["param", "genus20.obj", "--cones", "8", "-o", "out.obj"],
             broken={"--cones 18": HIGH_GENUS, "--cones auto": HIGH_GENUS},
             may_succeed=HIGH_GENUS_PARAMETERIZED),
        Case("param: hyperbolic torus", ["src/hyperbolic/hyperbolic_param.cpp:euclidean"],
             ["param", "torus.obj", "--geometry", "hyperbolic", "-o", "out.obj"]),
        Case("spline: sphere without cones", ["src/param/one_component.cpp:none"],
             ["spline", "ico.obj", "--cones", "none", "-o", "out.obj"]),
        # Output options (apps/ricci/param_command.cpp).
        Case("param: --texture of a missing image", ["apps/ricci/param_command.cpp:texture"],
             ["param", "torus.obj", "-o", "out.obj", "--texture", "nosuch.png"]),
        Case("param: glb of the refinement", ["apps/ricci/param_command.cpp:format"],
             ["param", "torus.obj", "-o", "out.glb", "--faces", "refinement"]),
    ]


# The places that attach fixes, by file: the markers the cases name, and how many expressions
# there build fixes (fixes_of(...), OptionFix{...}, the helpers' calls). A count that changes
# fails the test: a new refusal with a fix needs its case (and its marker here).
SITES = {
    "src/flow/target.cpp": (6, ["boundary", "vertex-bound", "hyperbolic", "gauss-bonnet"]),
    "src/flow/ricci_flow.cpp": (2, ["flips"]),
    "src/param/one_component.cpp": (7, ["count", "none", "one", "user"]),
    "src/hyperbolic/hyperbolic_param.cpp": (1, ["euclidean"]),
    "src/mesh/io/write_mesh.cpp": (1, ["drop-uv"]),
    "src/mesh/io/reader_support.cpp": (1, ["repair"]),
    "apps/ricci/input_options.cpp": (5, ["largest", "strict", "repair"]),
    "apps/ricci/render_command.cpp": (2, ["strict"]),
    "apps/ricci/flow_command.cpp": (1, ["cones"]),
    "apps/ricci/param_command.cpp":
        (4, ["texture", "format", "format-without-tinygltf", "format-without-render"]),
}
SITE_PATTERN = re.compile(r"fixes_of\(|OptionFix\{|more_cones_fixes\(|reading_fixes\(")
# Covered without a case here, and why.
COVERED_ELSEWHERE = {
    # WriteOptions::drop_uv: only Python's write_mesh reaches it (python/tests/test_mesh.py).
    "src/mesh/io/write_mesh.cpp:drop-uv",
    # The reader's fix (ReadOptions::repair) is what the --strict and --repair=never cases see,
    # rephrased by input_options.cpp.
    "src/mesh/io/reader_support.cpp:repair",
    # --format glb in a build without tinygltf or without the picture library: not this build.
    "apps/ricci/param_command.cpp:format-without-tinygltf",
    "apps/ricci/param_command.cpp:format-without-render",
}


def count_sites(source_dir):
    """Per file under src/ and apps/: the expressions that build fixes (the helpers'
    definitions, errors.cpp's fixes_of and the phrasing in fixes.hpp aside)."""
    counts = {}
    for folder in ("src", "apps"):
        for root, _, files in os.walk(os.path.join(source_dir, folder)):
            for name in files:
                if not name.endswith((".cpp", ".hpp")):
                    continue
                path = os.path.join(root, name)
                rel = os.path.relpath(path, source_dir)
                if rel in ("src/errors.cpp", "apps/ricci/fixes.hpp"):
                    continue
                text = open(path, encoding="utf-8").read()
                text = re.sub(r"std::vector<OptionFix> (more_cones_fixes|reading_fixes)\(", "",
                              text)
                n = len(SITE_PATTERN.findall(text))
                if n:
                    counts[rel] = n
    return counts


# --- meshes ---------------------------------------------------------------------------------------

FIN = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0.5 0.5 1\nf 1 2 3\nf 2 4 3\nf 2 5 3\n"
DUPLICATE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\nf 3 1 2\n"
SLIVER = ("v 0 0 0\nv 2 0 0\nv 1 0 0\nv 1 -1 0\nv 1 1 0\n"
          "f 1 4 2\nf 1 3 5\nf 3 2 5\nf 1 2 3\n")
BOWTIE = "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0 2 0\nv 1 2 0\nf 1 2 3\nf 3 5 4\n"
TWO_PARTS = ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nv 6 5 5\nv 5 6 5\nv 6 6 5\n"
             "f 1 2 3\nf 4 5 6\nf 5 7 6\nf 4 5 6\n")


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def read_obj(path):
    vertices, faces = [], []
    for line in open(path):
        w = line.split()
        if w and w[0] == "v":
            vertices.append(line)
        elif w and w[0] == "f":
            faces.append([int(x.split("/")[0]) for x in w[1:]])
    return vertices, faces


def flip_one_face(source, target):
    vertices, faces = read_obj(source)
    faces[0] = faces[0][::-1]
    write(target, "".join(vertices) + "".join(f"f {a} {b} {c}\n" for a, b, c in faces))


def a_boundary_vertex(path):
    """0-based index of a vertex on a boundary edge (an edge of one face)."""
    _, faces = read_obj(path)
    edges = collections.Counter()
    for f in faces:
        for k in range(3):
            edges[frozenset((f[k], f[(k + 1) % 3]))] += 1
    edge = next(e for e, n in edges.items() if n == 1)
    return min(edge) - 1


def flip_one_textured_face(source, target):
    """A UV OBJ (param's output) with its first face reversed, corners and texture alike."""
    lines = open(source).read().splitlines(keepends=True)
    for i, line in enumerate(lines):
        if line.startswith("f "):
            corners = line.split()[1:]
            lines[i] = "f " + " ".join(reversed(corners)) + "\n"
            break
    write(target, "".join(lines))


# --- running --------------------------------------------------------------------------------------

def run(args, cwd):
    done = subprocess.run([RICCI] + args, cwd=cwd, capture_output=True, text=True, timeout=900)
    return done.returncode, done.stdout + done.stderr


def printed_fixes(output):
    """The fixes of the first "try:" line: ["--cones auto", "drop --strict", ...]."""
    for line in output.splitlines():
        line = line.strip()
        if line.startswith("try: "):
            return line[len("try: "):].split(", or ")
    return None


# The options that take no value (dropping one leaves the next word).
FLAGS = {"--strict", "--largest-component", "--repair", "--json", "--progress", "--quantize"}


def apply_fix(args, fix):
    """args with the fix applied (see the module's doc)."""
    args = list(args)
    if fix.startswith("drop "):
        flag = fix[len("drop "):]
        if flag not in FLAGS and flag in args:  # an option and its value
            i = args.index(flag)
            del args[i:i + 2]
        return [a for a in args if a != flag and not a.startswith(flag + "=")]
    words = fix.split(" ")
    flag = words[0].split("=")[0]
    if "=" in words[0] or len(words) == 1:
        args = [a for a in args if a != flag and not a.startswith(flag + "=")]
        return args + [words[0]]
    if flag in args:
        i = args.index(flag)
        args[i + 1] = words[1]
        return args
    return args + words


def main():
    if len(sys.argv) < 2 or not os.access(RICCI, os.X_OK):
        print("usage: RICCI=/path/to/ricci fixes_test.py SOURCE_DIR [SCRATCH_DIR]",
              file=sys.stderr)
        return 2
    source_dir = sys.argv[1]
    scratch = sys.argv[2] if len(sys.argv) > 2 else tempfile.gettempdir()
    os.makedirs(scratch, exist_ok=True)
    work = tempfile.mkdtemp(prefix="fixes.", dir=scratch)
    passed, failed, expected = 0, 0, 0

    def check(name, good, why=""):
        nonlocal passed, failed
        if good:
            passed += 1
        else:
            failed += 1
            print(f"FAIL: {name}: {why}")

    # Meshes.
    for kind, extra in (("icosphere", ["--resolution", "2"]), ("torus", []), ("disk", []),
                        ("surface", ["--genus", "2"])):
        code, out = run(["generate", kind, "-o", f"{kind}.obj"] + extra, work)
        check(f"generate {kind}", code == 0, out)
    os.replace(os.path.join(work, "icosphere.obj"), os.path.join(work, "ico.obj"))
    os.replace(os.path.join(work, "surface.obj"), os.path.join(work, "genus2.obj"))
    code, out = run(["generate", "surface", "--genus", "20", "-o", "genus20.obj"], work)
    check("generate genus 20", code == 0, out)
    for name, text in (("fin.obj", FIN), ("duplicate.obj", DUPLICATE), ("sliver.obj", SLIVER),
                       ("bowtie.obj", BOWTIE), ("two_parts.obj", TWO_PARTS)):
        write(os.path.join(work, name), text)
    flip_one_face(os.path.join(work, "ico.obj"), os.path.join(work, "flipped_ico.obj"))
    has_render = run(["render", "--help"], work)[0] == 0
    if has_render:
        code, out = run(["param", "torus.obj", "-o", "torus_uv.obj"], work)
        check("param torus for render", code == 0, out)
        flip_one_textured_face(os.path.join(work, "torus_uv.obj"),
                               os.path.join(work, "flipped_uv.obj"))

    # Every place that attaches fixes has a case.
    all_cases = cases(a_boundary_vertex(os.path.join(work, "disk.obj")))
    counts = count_sites(source_dir)
    covered = set(COVERED_ELSEWHERE)
    for case in all_cases:
        covered.update(case.sites)
    for rel in sorted(set(counts) | set(SITES)):
        count, markers = SITES.get(rel, (0, []))
        check(f"fix places in {rel}", counts.get(rel, 0) == count,
              f"{counts.get(rel, 0)} expressions build fixes, the test knows {count}: give the "
              "new refusal a case here, a marker in SITES, and update the count")
        for marker in markers:
            check(f"a case for {rel}:{marker}", f"{rel}:{marker}" in covered, "no case provokes it")

    # The cases.
    for case in all_cases:
        if case.args[0] == "render" and not has_render:
            continue
        code, out = run(case.args, work)
        fixes = printed_fixes(out)
        if code == 0 and case.may_succeed:
            print(f"NOTE: {case.name}: {case.may_succeed}")
            continue
        check(f"{case.name}: refused with exit {case.exit_code}", code == case.exit_code,
              f"exit {code}: {out[-600:]}")
        check(f"{case.name}: names a fix", fixes is not None, out[-600:])
        for fix in fixes or []:
            fixed = apply_fix(case.args, fix)
            code, fixed_out = run(fixed, work)
            name = f"{case.name}: 'try: {fix}' -> ricci {' '.join(fixed)}"
            if fix in case.broken:
                expected += 1
                state = "still fails (expected)" if code != 0 else "WORKS NOW: drop it from broken"
                print(f"XFAIL: {name}: {state}: {case.broken[fix]}")
                if code == 0:
                    check(name, False, "listed as broken but works: update the case")
                continue
            check(name, code == 0, f"exit {code}: {fixed_out[-600:]}")
        print(f"{case.name}: {', '.join(fixes or ['no fix'])}")

    print(f"{passed} passed, {failed} failed, {expected} expected failures")
    if failed:
        print(f"scratch files kept in {work}", file=sys.stderr)
        return 1
    shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
