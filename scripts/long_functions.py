#!/usr/bin/python3
"""Lists the functions of the given folders longer than a limit (default 150 lines).

Reads universal-ctags' line and end fields; lambdas count inside the function that holds
them, not on their own. Exit status 1 when any function is over the limit, so that the
suite can pin the rule (tests/cli/long_functions_test.sh).

    scripts/long_functions.py [--limit N] [--all] DIR...
"""
import argparse
import json
import pathlib
import subprocess
import sys


def functions(paths):
    files = [str(p) for d in paths for p in sorted(pathlib.Path(d).rglob("*")) if p.suffix in (".cpp", ".hpp")]
    if not files:
        return []
    out = subprocess.run(
        ["ctags", "--output-format=json", "--fields=+ne", "--c++-kinds=f", "-o", "-", *files],
        check=True, capture_output=True, text=True).stdout
    rows = []
    for line in out.splitlines():
        tag = json.loads(line)
        if tag.get("name", "").startswith("__anon") or "end" not in tag:
            continue
        rows.append((tag["end"] - tag["line"] + 1, tag["path"], tag["line"], tag["name"]))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=int, default=150)
    parser.add_argument("--all", action="store_true", help="print every function, longest first")
    parser.add_argument("dirs", nargs="+")
    args = parser.parse_args()
    rows = sorted(functions(args.dirs), reverse=True)
    long = [r for r in rows if r[0] > args.limit]
    for n, path, line, name in (rows if args.all else long):
        print(f"{n:5d}  {path}:{line}  {name}")
    print(f"{len(long)} functions over {args.limit} lines (of {len(rows)})", file=sys.stderr)
    return 1 if long else 0


if __name__ == "__main__":
    sys.exit(main())
