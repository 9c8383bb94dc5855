#!/usr/bin/env bash
# `ricci batch` throughput (docs/batch.md): MESHES generated meshes of mixed kinds and sizes
# (icosphere, torus, disk, surface of genus 0..4, cad-cylinder; a target face count drawn from a
# log-normal, median about 1,600, clipped to 100..100,000, then the nearest resolution of the kind,
# so 64 to 81,920 faces: many small meshes and few large ones; cad-cylinder capped at about 2,000
# faces, its fans slow down faster than linearly; a fixed seed, so the same list every time), run
# as one batch, each time into a fresh output folder:
#   --jobs 1 (its child gets RICCI_NUM_THREADS=2: cores / jobs), --jobs 1 --threads 1, --jobs 2,
#   mpirun -n 2 (1 scheduler + 1 worker), mpirun -n 3 (1 + 2 workers); all but the first run each
#   mesh on one thread.
# Per configuration: wall seconds of the whole command, seconds of the batch loop itself
# (summary.json's wall_seconds: no MPI start-up, no summary picture), meshes per minute, scaling
# efficiency = throughput / (workers x the --jobs 1 --threads 1 throughput), the sum of the
# per-mesh child seconds (results.jsonl: fork to reaping of each `ricci param`), and the overhead
# per mesh = (wall x workers - sum of child seconds) / meshes: the time a worker slot is not
# running a child (hashing the input, removing old outputs, reading the report, the scheduler's
# log append with fdatasync, handing out the next mesh: a queue locally, MPI messages polled
# every 2 ms under mpirun; with the command's wall, also start-up, listing the meshes and
# drawing summary.png). Every configuration's OBJs are compared byte for byte (cmp) with the
# --jobs 1 run's (2 threads against 1). Also the bare cost of starting one process:
# `ricci --version` and `ricci param` on the tetrahedron, to put the overhead in context.
#
# Usage: RICCI=build/ricci [MESHES=500] [REPEAT_START=20] bash bench/batch.sh [SCRATCH_DIR]
#        (scratch default: build/bench-batch; its runs/ folder is emptied first)
# MPI rows need mpirun and a ricci built with MPI (else they say n/a); as root the script sets
# OMPI_ALLOW_RUN_AS_ROOT. On two cores, 1 + 2 ranks oversubscribe (--oversubscribe): the
# scheduler rank mostly sleeps. Takes about 3 minutes on two cores; run it on an idle machine
# (each row says how much CPU other processes used during it). Prints markdown tables.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
ricci=${RICCI:-$here/build/ricci}
meshes_wanted=${MESHES:-500}
repeat=${REPEAT_START:-20}
scratch=${1:-$here/build/bench-batch}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -x "$ricci" ] || { echo "batch.sh: $ricci is not executable (set RICCI)" >&2; exit 1; }
ricci=$(cd "$(dirname "$ricci")" && pwd)/$(basename "$ricci")
rm -rf "$scratch/meshes" "$scratch/runs"
mkdir -p "$scratch/meshes" "$scratch/runs"
cd "$scratch"

now() { date +%s.%N; }

# The mesh list: "name kind resolution genus", deterministic.
/usr/bin/python3 - "$meshes_wanted" >list.txt <<'EOF'
import math, random, sys
n = int(sys.argv[1])
rng = random.Random(20240501)
# faces of each kind as a function of --resolution r (checked against `ricci generate`)
surface_c = {0: 12.0, 1: 6.9, 2: 4.1, 3: 2.7, 4: 2.1}
kinds = ["icosphere", "torus", "disk", "surface", "surface", "cad-cylinder"]
for i in range(n):
    faces = 10 ** min(5.0, max(2.0, rng.gauss(3.2, 0.6)))
    kind = rng.choice(kinds)
    genus = 2
    if kind == "icosphere":    # 20 * 4^r
        r = min(6, max(1, round(math.log(faces / 20, 4))))
    elif kind == "torus":      # 4 r^2
        r = max(4, round(math.sqrt(faces / 4)))
    elif kind == "disk":       # 6 r^2
        r = max(4, round(math.sqrt(faces / 6)))
    elif kind == "surface":    # about c_g r^2
        genus = rng.randint(0, 4)
        r = max(4, round(math.sqrt(faces / surface_c[genus])))
    else:                      # cad-cylinder: 4 r - 4, capped at about 2,000 faces
        r = min(500, max(4, round(faces / 4) + 1))
    print(f"m{i:03d}-{kind}-r{r}-g{genus} {kind} {r} {genus}")
EOF
t0=$(now)
while read -r name kind r genus; do
  "$ricci" generate "$kind" --resolution "$r" --genus "$genus" -o "meshes/$name.obj" >/dev/null
done <list.txt
gen_seconds=$(echo "$(now) - $t0" | bc)

# CPU ticks of the whole machine (user, nice, system, irq, softirq), and of this shell and its
# waited-for descendants (the batch, its ranks, their children): the difference during a run is
# other work on the machine, which inflates every figure.
busy_ticks() { awk '/^cpu /{print $2 + $3 + $4 + $7 + $8}' /proc/stat; }
own_ticks() { awk '{print $14 + $15 + $16 + $17}' "/proc/$$/stat"; }
hz=$(getconf CLK_TCK)

# One configuration: label, workers, then the command (run in the scratch folder; the output
# folder is runs/LABEL). Appends "label workers wall rc other_cpu_seconds" to runs.txt.
: >runs.txt
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
run() {
  local label=$1 workers=$2
  shift 2
  local start busy0 own0 rc=0
  busy0=$(busy_ticks)
  own0=$(own_ticks)
  start=$(now)
  "$@" meshes -o "runs/$label" >"runs/$label.out" 2>"runs/$label.err" || rc=$?
  local wall other
  wall=$(echo "$(now) - $start" | bc)
  other=$(echo "(($(busy_ticks) - $busy0) - ($(own_ticks) - $own0)) / $hz" | bc -l)
  echo "$label $workers $wall $rc $other" >>runs.txt
}
run jobs1 1 "$ricci" batch --jobs 1
run jobs1t1 1 "$ricci" batch --jobs 1 --threads 1
run jobs2 2 "$ricci" batch --jobs 2
if command -v mpirun >/dev/null; then
  run mpi1+1 1 mpirun -n 2 --oversubscribe "$ricci" batch
  run mpi1+2 2 mpirun -n 3 --oversubscribe "$ricci" batch
fi

# The bare cost of a process: `ricci --version`, and `ricci param` on the tetrahedron.
"$ricci" generate tetrahedron -o tetra.obj >/dev/null
start=$(now)
for _ in $(seq "$repeat"); do "$ricci" --version >/dev/null; done
version_ms=$(echo "($(now) - $start) * 1000 / $repeat" | bc -l)
start=$(now)
for _ in $(seq "$repeat"); do "$ricci" param tetra.obj -o tetra-uv.obj >/dev/null 2>&1; done
tetra_ms=$(echo "($(now) - $start) * 1000 / $repeat" | bc -l)
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

/usr/bin/python3 - "$gen_seconds" "$version_ms" "$tetra_ms" "$(nproc)" "$load_before" \
  "$load_after" <<'EOF'
import collections, filecmp, json, os, statistics, sys
gen_seconds, version_ms, tetra_ms = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
cores, load_before, load_after = sys.argv[4], sys.argv[5], sys.argv[6]

def pct(values, q):  # numpy's linear interpolation
    v = sorted(values)
    k = (len(v) - 1) * q
    lo = int(k)
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (v[hi] - v[lo]) * (k - lo)

faces, kinds = {}, collections.Counter()
for name in sorted(os.listdir("meshes")):
    with open(os.path.join("meshes", name)) as f:
        faces[name] = sum(1 for line in f if line.startswith("f "))
    kinds[name.split("-")[1] if not name.split("-")[1] == "cad" else "cad-cylinder"] += 1
fv = list(faces.values())
print(f"{len(fv)} meshes generated in {gen_seconds:.1f} s, {cores} cores; kinds: "
      + ", ".join(f"{k} {c}" for k, c in sorted(kinds.items())))
print()
print("| faces | min | p10 | p50 | p90 | p99 | max | mean | < 1k | 1k..10k | 10k..100k |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
print(f"| | {min(fv)} | {pct(fv, .1):.0f} | {pct(fv, .5):.0f} | {pct(fv, .9):.0f} | "
      f"{pct(fv, .99):.0f} | {max(fv)} | {statistics.mean(fv):.0f} | "
      f"{sum(f < 1000 for f in fv)} | {sum(1000 <= f < 10000 for f in fv)} | "
      f"{sum(f >= 10000 for f in fv)} |")
print()

runs = []
with open("runs.txt") as f:
    for line in f:
        label, workers, wall, rc, other = line.split()
        runs.append((label, int(workers), float(wall), int(rc), max(0.0, float(other))))

def records(label):
    path = os.path.join("runs", label, "results.jsonl")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]

names = {"jobs1": "`--jobs 1` (2 threads)", "jobs1t1": "`--jobs 1 --threads 1`",
         "jobs2": "`--jobs 2`", "mpi1+1": "`mpirun -n 2` (1 + 1)",
         "mpi1+2": "`mpirun -n 3` (1 + 2)"}
base = records("jobs1")
base_ok = {r["key"]: r["output"] for r in base if r["outcome"] == "ok"}
# Efficiency against one worker with one thread, as every other row has (--jobs 1 alone gives
# its child both cores' threads).
base_rate = {r[0]: 60 * len(records(r[0])) / r[2] for r in runs}.get("jobs1t1")
print("| configuration | workers | exit | wall s | batch loop s | meshes/min | scaling efficiency "
      "| sum of child s | overhead ms/mesh (wall) | overhead ms/mesh (loop) | outcomes "
      "| OBJs identical to --jobs 1 | other processes' CPU s |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for label, workers, wall, rc, other in runs:
    recs = records(label)
    if rc not in (0, 6) or not recs:
        print(f"| {names[label]} | {workers} | {rc} | n/a | | | | | | | (runs/{label}.err) | | |")
        continue
    n = len(recs)
    with open(os.path.join("runs", label, "summary.json")) as f:
        loop = json.load(f)["wall_seconds"]
    child = sum(r["seconds"] for r in recs)
    rate = 60 * n / wall
    eff = rate / (workers * base_rate) if base_rate else float("nan")
    outcomes = collections.Counter(r["outcome"] for r in recs)
    same = differ = missing = 0
    for r in recs:
        if r["key"] not in base_ok:
            continue
        if r["outcome"] != "ok" or not os.path.exists(r["output"]):
            missing += 1
        elif filecmp.cmp(r["output"], base_ok[r["key"]], shallow=False):
            same += 1
        else:
            differ += 1
    identical = f"{same} of {len(base_ok)}" + (f", {differ} differ" if differ else "") + \
        (f", {missing} missing" if missing else "")
    print(f"| {names[label]} | {workers} | {rc} | {wall:.1f} | {loop:.1f} | {rate:.0f} | "
          f"{eff:.2f} | {child:.1f} | {1000 * (wall * workers - child) / n:.1f} | "
          f"{1000 * (loop * workers - child) / n:.1f} | "
          + ", ".join(f"{c} {o}" for o, c in sorted(outcomes.items()))
          + f" | {identical} | {other:.1f} |")
print()
if base:
    s = [r["seconds"] for r in base]
    by_key = {r["key"]: r["seconds"] for r in base}
    top = sorted(by_key.items(), key=lambda kv: -kv[1])[:3]
    print(f"--jobs 1 child seconds per mesh: mean {statistics.mean(s):.3f}, p50 {pct(s, .5):.3f}, "
          f"p90 {pct(s, .9):.3f}, p99 {pct(s, .99):.3f}, max {max(s):.3f}; the slowest "
          f"3 meshes take {100 * sum(v for _, v in top) / sum(s):.0f}% of the sum ("
          + ", ".join(f"{k} {v:.2f} s" for k, v in top) + ")")
    peak = [r["peak_memory_kb"] / 1024 for r in base]
    print(f"peak resident memory per mesh: p50 {pct(peak, .5):.0f} MiB, max {max(peak):.0f} MiB")
print(f"process start: `ricci --version` {version_ms:.1f} ms, `ricci param` on the tetrahedron "
      f"{tetra_ms:.1f} ms (mean of serial runs)")
print(f"load average (1, 5, 15 min) before the runs: {load_before}; after: {load_after}; other "
      "processes' CPU s: what the machine did beside the batch during each run (0: quiet)")
EOF
