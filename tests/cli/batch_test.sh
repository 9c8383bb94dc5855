#!/usr/bin/env bash
# `ricci batch` end to end (docs/batch.md): generated meshes, shared meshes when ../shared/meshes
# exists, and hostile files (a crash and a hang injected with param's hidden --fault, a memory hog
# under --memory-limit, a file that is not a mesh). Then kills: a worker (`ricci param` child, or
# an MPI worker rank) and the scheduler, each with kill -9 in mid-run, and a resume. Checked after
# each: every mesh has exactly one line in results.jsonl with the right outcome, the bad file's
# message is the one `ricci param` prints, no temporary file is left, and every Ok mesh's OBJ is
# byte for byte, and its report (less timings and paths) value for value, what a single
# `ricci param` run writes.
#
# Usage: RICCI=/path/to/ricci [MODE=local|mpi] [RICCI_SANITIZED=1] bash tests/cli/batch_test.sh
#        [SCRATCH_DIR]
# MODE=mpi runs the batches under `mpirun -n 3 --oversubscribe` (one scheduler, two workers).
set -u

SHARED="${RICCI_SHARED_MESHES:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/../shared/meshes}"
# shellcheck source=check_framework.sh
source "$(dirname "${BASH_SOURCE[0]}")/check_framework.sh" "batch_${MODE:-local}" "${1:-}"
MODE="${MODE:-local}"
# Sanitizer builds run several times slower, and their shadow memory cannot live under an
# address-space limit: a longer timeout, no memory hog.
LIMIT=(--memory-limit 1000)
TIMEOUT=6
if [[ "${RICCI_SANITIZED:-0}" == 1 ]]; then
  TIMEOUT=20
  LIMIT=()
fi
export RICCI_FAULT_INJECTION=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1

batch() {  # batch ARGS...: ricci batch, locally or under mpirun
  if [[ "$MODE" == mpi ]]; then
    mpirun -n 3 --oversubscribe "$RICCI" batch "$@"
  else
    "$RICCI" batch --jobs 2 "$@"
  fi
}

# The meshes: small generated ones, two slower ones (for the kills), shared ones.
mkdir -p in/gen in/shared
"$RICCI" generate icosphere -o in/gen/icosphere.obj >/dev/null
"$RICCI" generate torus -o in/gen/torus.obj >/dev/null
"$RICCI" generate disk -o in/gen/disk.obj >/dev/null
"$RICCI" generate surface --genus 2 -o in/gen/genus2.obj >/dev/null
"$RICCI" generate cad-cylinder -o in/gen/cad.obj >/dev/null
"$RICCI" generate icosphere --resolution 6 -o in/gen/slow1.obj >/dev/null
cp in/gen/slow1.obj in/gen/slow2.obj && echo "# a copy" >>in/gen/slow2.obj
if [[ -d "$SHARED" ]]; then
  for m in spot.obj bob_tri.obj eight.off; do
    [[ -f "$SHARED/$m" ]] && ln -s "$SHARED/$m" "in/shared/$m"
  done
fi
cp in/gen/disk.obj in/gen/crash.obj
cp in/gen/disk.obj in/gen/hang.obj
cp in/gen/disk.obj in/gen/hog.obj
head -c 3000 /dev/urandom >in/gen/garbage.ply

normal_keys=$(cd in && find . -name '*.obj' -o -name '*.off' | sed 's|^\./||' |
  grep -v -E 'crash|hang|hog' | sort)
# The hostile run leaves out the two slow meshes (they are there for the kills below): its
# timeout then stays short even in a sanitizer build.
small_keys=$(echo "$normal_keys" | grep -v slow)
{
  for k in $small_keys; do echo "$k"; done
  printf 'gen/crash.obj\t--fault segv\n'
  printf 'gen/hang.obj\t--fault hang\n'
  [[ "${RICCI_SANITIZED:-0}" == 1 ]] || printf 'gen/hog.obj\t--fault alloc\n'
  echo "gen/garbage.ply"
} >in/manifest.tsv
hostile_count=$((${RICCI_SANITIZED:-0} == 1 ? 3 : 4))
total=$(($(echo "$small_keys" | wc -l) + hostile_count))

# outcome OUT KEY: the outcome of KEY in OUT/results.jsonl; lines OUT KEY: how many lines name it.
outcome() {
  "$PYTHON" -c 'import json,sys
for line in open(sys.argv[1]):
    r = json.loads(line)
    if r["key"] == sys.argv[2]: print(r["outcome"], r["signal"], r["message"].split("\n")[0])' \
    "$1/results.jsonl" "$2"
}
check_log() {  # check_log NAME OUT COUNT: COUNT lines, each key once, no temporary files
  local n unique temps
  n=$(wc -l <"$2/results.jsonl")
  unique=$("$PYTHON" -c 'import json,sys
print(len({json.loads(l)["key"] for l in open(sys.argv[1])}))' "$2/results.jsonl")
  temps=$(find "$2" -name '.*.tmp.*' | wc -l)
  if [[ "$n" == "$3" && "$unique" == "$3" && "$temps" == 0 ]]; then ok; else
    fail "$1" "results.jsonl has $n lines for $unique keys (want $3 each), $temps temporary files"
  fi
}
# canonical FILE: the report without timings and paths (they differ between runs by design).
canonical() {
  "$PYTHON" - "$1" <<'PY'
import json, sys
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items()
                if "seconds" not in k and k not in ("timings", "input", "output", "files")}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
sys.stdout.write(json.dumps(strip(json.load(open(sys.argv[1]))), sort_keys=True))
PY
}
mkdir -p single
same_as_single() {  # same_as_single NAME OUT KEY...: outputs equal a single ricci param run
  local name=$1 out=$2 key stem bad=0
  shift 2
  for key in "$@"; do
    stem="${key%.*}"
    if [[ ! -f "single/$stem.obj" ]]; then
      mkdir -p "single/$(dirname "$stem")"
      "$RICCI" param "in/$key" -o "single/$stem.obj" --report "single/$stem.json" >/dev/null 2>&1
    fi
    if ! cmp -s "single/$stem.obj" "$out/$stem.obj"; then
      fail "$name" "$key: $out/$stem.obj differs from a single ricci param run"
      bad=1
    elif [[ "$(canonical "single/$stem.json")" != "$(canonical "$out/$stem.json")" ]]; then
      fail "$name" "$key: its report differs from a single ricci param run"
      bad=1
    fi
  done
  ((bad == 0)) && ok
}

# 1. The whole set with hostile files.
batch in/manifest.tsv -o out --timeout "$TIMEOUT" "${LIMIT[@]}" --progress >run1.txt 2>&1
status=$?
if [[ $status == 6 ]]; then ok; else fail run1-status "exit $status, want 6 (some failed)"; fi
check_log run1-log out "$total"
case "$(outcome out gen/crash.obj)" in "crashed 11 killed by SIGSEGV"*) ok ;;
  *) fail crash "$(outcome out gen/crash.obj)" ;; esac
case "$(outcome out gen/hang.obj)" in "timed_out "*"stopped after $TIMEOUT s"*) ok ;;
  *) fail hang "$(outcome out gen/hang.obj)" ;; esac
if [[ "${RICCI_SANITIZED:-0}" != 1 ]]; then
  case "$(outcome out gen/hog.obj)" in "out_of_memory 0 error: out of memory"*) ok ;;
    *) fail hog "$(outcome out gen/hog.obj)" ;; esac
fi
param_message=$("$RICCI" param "$PWD/in/gen/garbage.ply" -o x.obj 2>&1 >/dev/null | grep '^error:')
case "$(outcome out gen/garbage.ply)" in "bad_input 0 $param_message") ok ;;
  *) fail garbage "'$(outcome out gen/garbage.ply)' against param's '$param_message'" ;; esac
for k in $small_keys; do
  [[ "$(outcome out "$k")" == "ok 0 " ]] || fail "ok-$k" "$(outcome out "$k")"
done
ok
for f in out/summary.json out/summary.png out/gen/disk.obj out/gen/disk.json; do
  [[ -s "$f" ]] || fail outputs "$f missing"
done
[[ ! -e out/gen/crash.obj && ! -e out/gen/garbage.obj ]] || fail outputs "a failed mesh has an OBJ"
grep -q 'meshes/min' run1.txt && grep -q 'ETA' run1.txt && ok || fail progress "no rate or ETA"
# shellcheck disable=SC2086
same_as_single run1-identical out $small_keys

# 2. The same command again: nothing runs; --retry-failed runs the failures only.
batch in/manifest.tsv -o out --timeout "$TIMEOUT" "${LIMIT[@]}" >run2.txt 2>&1
grep -q "(0 run now, $total from an earlier run)" run2.txt && ok ||
  fail rerun "$(grep meshes: run2.txt)"
check_log rerun-log out "$total"
batch in/manifest.tsv -o out --timeout "$TIMEOUT" "${LIMIT[@]}" --retry-failed \
  >run3.txt 2>&1
grep -q "($hostile_count run now, " run3.txt && ok || fail retry "$(grep meshes: run3.txt)"
check_log retry-log out "$total"
# Changed options run again; a bad option is refused before anything runs.
batch in/gen -o out_bad --no-such-option >bad.txt 2>&1
status=$?
[[ $status == 2 && ! -e out_bad/results.jsonl ]] && ok || fail bad-option "exit $status"
batch in/gen -o out_bad --report x.json >bad.txt 2>&1
grep -q "is set by ricci batch" bad.txt && ok || fail owned-option "$(cat bad.txt)"

# 3. kill -9 of a worker in mid-run, then resume with --retry-failed.
printf '%s\n' $normal_keys >in/normal.tsv
batch in/normal.tsv -o out_w >run_w.txt 2>&1 &
batch_pid=$!
victim=""
while kill -0 "$batch_pid" 2>/dev/null; do
  if [[ "$MODE" == mpi ]]; then
    # A worker rank: a `ricci batch` process whose MPI rank is not 0.
    for p in $(pgrep -f "batch .*in/normal.tsv -o out_w"); do
      if tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -q '^OMPI_COMM_WORLD_RANK=[12]$'; then
        victim=$p
        break
      fi
    done
  else
    victim=$(pgrep -f "param .*/in/gen/slow" | head -1)
  fi
  [[ -n "$victim" ]] && break
  sleep 0.05
done
if [[ -n "$victim" ]]; then kill -9 "$victim"; ok; else fail kill-worker "no worker found"; fi
if [[ "$MODE" == mpi ]]; then
  # Open MPI's launcher has been seen to stay after a rank's kill -9 with every rank gone (the
  # others exited but unreaped, mpirun waiting on them for good): once no rank is left alive
  # for 20 s, the launcher is what hangs, not ricci, and it is killed.
  gone=0
  while kill -0 "$batch_pid" 2>/dev/null && [[ $gone -lt 400 ]]; do
    alive=0
    for p in $(pgrep -f "batch .*in/normal.tsv -o out_w"); do
      tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -q '^OMPI_COMM_WORLD_RANK=' || continue
      [[ "$(awk '{print $3}' "/proc/$p/stat" 2>/dev/null)" == Z ]] || alive=1
    done
    if [[ $alive == 0 ]]; then gone=$((gone + 1)); else gone=0; fi
    sleep 0.05
  done
  kill -0 "$batch_pid" 2>/dev/null && pkill -9 -f "mpirun .*in/normal.tsv -o out_w"
fi
wait "$batch_pid"
status=$?
[[ $status != 0 ]] && ok || fail kill-worker-status "exit 0 after a kill -9"
batch in/normal.tsv -o out_w --retry-failed >resume_w.txt 2>&1
status=$?
[[ $status == 0 ]] && ok || fail resume-worker "exit $status: $(tail -3 resume_w.txt)"
check_log resume-worker-log out_w "$(echo "$normal_keys" | wc -l)"
# shellcheck disable=SC2086
same_as_single resume-worker-identical out_w $normal_keys

# 4. kill -9 of the scheduler in mid-run (after its first record), then resume.
batch in/normal.tsv -o out_s >run_s.txt 2>&1 &
launcher=$!
scheduler=""
# The batch starts the largest meshes first: under the sanitizers, on a loaded machine, the first
# record comes after the two slow meshes (31 s each seen in CI's conditions), so the wait ends
# when the batch does, not after a fixed count.
while kill -0 "$launcher" 2>/dev/null; do
  if [[ -s out_s/results.jsonl ]]; then
    for p in $(pgrep -f "batch .*in/normal.tsv -o out_s"); do
      if [[ "$MODE" != mpi ]] ||
        tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -q '^OMPI_COMM_WORLD_RANK=0$'; then
        scheduler=$p
        break
      fi
    done
  fi
  [[ -n "$scheduler" ]] && break
  sleep 0.05
done
if [[ -n "$scheduler" ]]; then kill -9 "$scheduler"; ok; else fail kill-scheduler "not found"; fi
wait "$launcher"
# Its children end with it (they get SIGTERM when their parent dies).
for _ in $(seq 1 100); do
  pgrep -f "param .*/in/gen/.* -o .*/out_s/" >/dev/null || break
  sleep 0.05
done
pgrep -f "param .*/in/gen/.* -o .*/out_s/" >/dev/null && fail orphans "param children outlived it"
batch in/normal.tsv -o out_s >resume_s.txt 2>&1
status=$?
[[ $status == 0 ]] && ok || fail resume-scheduler "exit $status: $(tail -3 resume_s.txt)"
grep -q "from an earlier run" resume_s.txt && ok || fail resume-scheduler-skips "$(cat resume_s.txt)"
check_log resume-scheduler-log out_s "$(echo "$normal_keys" | wc -l)"
# shellcheck disable=SC2086
same_as_single resume-scheduler-identical out_s $normal_keys

# 5. Meshes whose keys differ only in the extension write KEY_ext outputs, a unique one its own.
mkdir -p twins
"$RICCI" generate disk -o twins/twin.obj >/dev/null
awk '/^v /{v[n++]=$2" "$3" "$4} /^f /{f[m++]="3 "$2-1" "$3-1" "$4-1}
  END{print "OFF"; print n, m, 0; for(i=0;i<n;i++) print v[i]; for(i=0;i<m;i++) print f[i]}' \
  twins/twin.obj >twins/twin.off
cp twins/twin.obj twins/single.obj
batch twins -o out_t >twins.txt 2>&1
status=$?
[[ $status == 0 ]] && ok || fail twins "exit $status: $(tail -3 twins.txt)"
for f in twin_obj.obj twin_obj.json twin_off.obj twin_off.json single.obj single.json; do
  [[ -s "out_t/$f" ]] || fail twins-outputs "$f missing"
done

finish
