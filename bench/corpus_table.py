#!/usr/bin/env python3
"""The corpus table of bench/corpus.sh: reads a `ricci batch` output folder over
../shared/corpus, checks every UV OBJ with ../shared/tools/checkuv.py (independent of ricci),
sorts the meshes into the classes of MANIFEST.tsv and prints, per class: meshes, ok (exit 0),
clean (ok, 0 flipped and seam mismatch <= 1e-6 by the checker), exact (clean and seams <= 1e-9),
flipped faces, seconds, the routes the components took, and then the slowest meshes and every
mesh that is not clean with why.

Usage: corpus_table.py CORPUS_DIR BATCH_OUT_DIR [--json OUT.json] [--jobs N]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
from collections import Counter, defaultdict
from concurrent.futures import ThreadPoolExecutor

CLASSES = ["closed genus 0", "closed genus 1", "closed genus 2-9", "closed genus >= 10",
           "open (one piece, triangles)", "polygon faces", "several components", "non-manifold"]


def mesh_class(row):
    """The issue's classes, in its order of precedence."""
    if row["manifold"] != "yes":
        return "non-manifold"
    if row["face_sizes"] != "tri":
        return "polygon faces"
    if row["components"] != "1":
        return "several components"
    if row["boundary_loops"] != "0":
        return "open (one piece, triangles)"
    genus = int(row["genus"])
    if genus == 0:
        return "closed genus 0"
    if genus == 1:
        return "closed genus 1"
    return "closed genus 2-9" if genus < 10 else "closed genus >= 10"


def check(checkuv, obj):
    try:
        out = subprocess.run([sys.executable, checkuv, obj], capture_output=True, text=True,
                             timeout=1800)
        return json.loads(out.stdout)
    except Exception as e:  # a checker failure is a finding, not a crash of the table
        return {"error": str(e)}


def routes_of(report_path):
    """The routes each component took, from the JSON report (absent in older reports)."""
    try:
        with open(report_path) as fh:
            report = json.load(fh)
    except (OSError, ValueError):
        return []
    return [route.get("method", "?") for route in report.get("routes", [])]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("corpus")
    ap.add_argument("out")
    ap.add_argument("--json")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    checkuv = os.environ.get("CHECKUV") or os.path.join(here, "..", "..", "shared", "tools",
                                                        "checkuv.py")
    manifest = {}
    with open(os.path.join(args.corpus, "MANIFEST.tsv")) as fh:
        for row in csv.DictReader(fh, delimiter="\t"):
            manifest[os.path.realpath(os.path.join(args.corpus, row["file"]))] = row
    results = {}
    with open(os.path.join(args.out, "results.jsonl")) as fh:
        for line in fh:
            r = json.loads(line)
            results[os.path.realpath(r["input"])] = r  # the last line of a mesh wins
    todo = [(p, r) for p, r in results.items() if r.get("outcome") == "ok" and r.get("output")]
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        checks = dict(zip([p for p, _ in todo],
                          pool.map(lambda pr: check(checkuv, pr[1]["output"]), todo)))
    rows = []
    for path, m in manifest.items():
        r = results.get(path)
        c = checks.get(path, {})
        ok = r is not None and r.get("outcome") == "ok"
        flipped = c.get("flipped") if ok else None
        mismatch = c.get("seam_length_mismatch") if ok else None
        clean = ok and flipped == 0 and mismatch is not None and mismatch <= 1e-6
        exact = clean and mismatch <= 1e-9
        rows.append({
            "file": m["file"], "class": mesh_class(m), "faces": int(m["faces"] or 0),
            "genus": m["genus"], "ok": ok, "clean": clean, "exact": exact,
            "flipped": flipped, "seam_mismatch": mismatch,
            "checker_error": c.get("error"),
            "angle": c.get("angle_distortion_mean"), "area": c.get("area_distortion_energy"),
            "outcome": r.get("outcome") if r else "missing",
            "seconds": r.get("seconds", 0) if r else 0,
            "message": (r.get("message") or "")[:300] if r else "not run",
            "routes": routes_of(r["report"]) if ok and r.get("report") else [],
        })
    by_class = defaultdict(list)
    for row in rows:
        by_class[row["class"]].append(row)
    print("| class | meshes | ok | clean (0 flipped, seams <= 1e-6) | seams <= 1e-9 | flipped faces "
          "| seconds | routes |")
    print("|---|---|---|---|---|---|---|---|")
    total = Counter()
    all_routes = Counter()
    for cls in CLASSES + sorted(set(by_class) - set(CLASSES)):
        rs = by_class.get(cls, [])
        if not rs:
            continue
        routes = Counter(x for r in rs for x in r["routes"])
        all_routes.update(routes)
        line = Counter(meshes=len(rs), ok=sum(r["ok"] for r in rs),
                       clean=sum(r["clean"] for r in rs), exact=sum(r["exact"] for r in rs),
                       flipped=sum(r["flipped"] or 0 for r in rs))
        seconds = sum(r["seconds"] for r in rs)
        total.update(line)
        total["seconds"] += seconds
        print(f"| {cls} | {line['meshes']} | {line['ok']} | {line['clean']} | {line['exact']} | "
              f"{line['flipped']} | {seconds:.1f} | "
              f"{', '.join(f'{k} {v}' for k, v in sorted(routes.items())) or '-'} |")
    print(f"| all | {total['meshes']} | {total['ok']} | {total['clean']} | {total['exact']} | "
          f"{total['flipped']} | {total['seconds']:.1f} | "
          f"{', '.join(f'{k} {v}' for k, v in sorted(all_routes.items())) or '-'} |")
    print("\nSlowest meshes:")
    for r in sorted(rows, key=lambda r: -r["seconds"])[:8]:
        print(f"  {r['seconds']:7.2f} s  {r['file']} ({r['faces']} faces, {r['class']})")
    print("\nNot clean:")
    for r in sorted(rows, key=lambda r: (CLASSES.index(r["class"])
                                         if r["class"] in CLASSES else 99, r["file"])):
        if r["clean"]:
            continue
        why = (f"flipped {r['flipped']}, seams {r['seam_mismatch']:.2g}" if r["ok"] and
               r["flipped"] is not None else f"{r['outcome']}: {r['message'] or r['checker_error']}")
        print(f"  [{r['class']}] {r['file']}: {why}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
