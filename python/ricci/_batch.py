"""Many meshes through ``ricci param``: ``batch`` wraps run_batch (ricci/batch/batch.hpp), as the
command line ``ricci batch`` does (docs/batch.md)."""

import json
import os
import shutil
import sys

from . import _ricci


def _is_executable(path):
    return bool(path) and os.path.isfile(path) and os.access(path, os.X_OK)


def find_program(program=None):
    """The ``ricci`` executable that ``batch`` runs: ``program`` when given, else the first
    executable of: $RICCI_EXECUTABLE, the one inside the package (``ricci/bin/ricci``, where
    ``pip install`` puts it), the build tree's ``ricci`` (this module was built beside it), the
    installed ``<prefix>/bin/ricci`` (found from the package's folder, then at the
    configured prefix), ``ricci`` on PATH. Raises ``ricci.Error`` when none is."""
    if program is not None:
        path = os.fspath(program)
        if not _is_executable(path):
            raise _ricci.Error(f"ricci.batch: program={path!r} is not an executable file")
        return os.path.abspath(path)
    candidates = []
    from_env = os.environ.get("RICCI_EXECUTABLE")
    if from_env:
        if not _is_executable(from_env):
            raise _ricci.Error(
                f"ricci.batch: RICCI_EXECUTABLE={from_env!r} is not an executable file")
        return os.path.abspath(from_env)
    # A pip-installed package carries its own program (setup.py): ricci/bin/ricci.
    candidates.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "ricci"))
    candidates.append(_ricci._default_program)
    if _ricci._program_from_package:
        package = os.path.dirname(os.path.abspath(_ricci.__file__))
        candidates.append(os.path.normpath(os.path.join(package, _ricci._program_from_package)))
    candidates.append(_ricci._installed_program)
    candidates.append(shutil.which("ricci"))
    for path in candidates:
        if _is_executable(path):
            return os.path.abspath(path)
    raise _ricci.Error(
        "ricci.batch: cannot find the ricci program (tried "
        + ", ".join(p for p in candidates if p) + " and PATH); pass program=PATH or set "
        "RICCI_EXECUTABLE, or build the target ricci / install it (cmake --install)")


def param_arguments(**param_options):
    """``ricci param`` command-line options from keyword arguments: ``max_log_scale=0.5`` ->
    ``["--max-log-scale", "0.5"]``; True -> the bare flag (``quantize=True`` ->
    ``["--quantize"]``); False and None -> nothing; other values -> ``str(value)``."""
    arguments = []
    for name, value in param_options.items():
        if value is None or value is False:
            continue
        option = "--" + name.replace("_", "-")
        if value is True:
            arguments.append(option)
        elif isinstance(value, (list, tuple, dict, set)):
            raise TypeError(f"ricci.batch: {name}={value!r}: an option of ricci param takes one "
                            "value (a str, a number or True); e.g. cones='17:1,230:1'")
        else:
            arguments += [option, str(os.fspath(value) if hasattr(value, "__fspath__") else value)]
    return arguments


def _print_progress(p):
    """progress=True: a line per mesh on stderr, as ``ricci batch --progress``."""
    last = p["last"]
    if last is None:
        print(f"batch: {p['total']} meshes, {p['skipped']} done before, "
              f"{p['total'] - p['done']} to run", file=sys.stderr, flush=True)
        return
    eta = "?" if p["eta_seconds"] is None else f"{p['eta_seconds']:.0f}s"
    print(f"[{p['done']}/{p['total']}] {last['outcome']} {last['key']} {last['seconds']:.2f} s  "
          f"(ok {p['ok']}, failed {p['failed']}; {p['meshes_per_minute']:.1f} meshes/min, "
          f"ETA {eta})", file=sys.stderr, flush=True)


def batch(paths, out_dir, *, jobs=None, timeout=0, memory_limit=0, threads=0, retry_failed=False,
          progress=None, program=None, **param_options):
    """Parameterize many meshes, each by ``ricci param`` in a child process of its own (a crash,
    a timeout or a memory blow-up is that mesh's outcome, never this process's), as
    ``ricci batch`` does (docs/batch.md).

    paths: a list of mesh files (keys relative to their common folder), or one str / path: a
      folder (every .obj .off .ply .stl under it) or a manifest (a mesh path per line,
      optionally a TAB and options of ricci param for that mesh).
    out_dir: receives KEY.obj (the UV OBJ) and KEY.json (the report) per mesh (KEY: the
      mesh's key less its extension; pig_off and pig_stl for a pig.off beside a pig.stl),
      results.jsonl (a line per mesh) and summary.json. A second call with the same meshes and options skips
      every mesh already recorded there (a failed one too, unless retry_failed=True), so an
      interrupted batch resumes where it stopped.
    jobs: meshes at once (None or 0: os.cpu_count()). timeout: seconds per mesh (0: none).
    memory_limit: MiB of address space per mesh (0: none). threads: threads per mesh (0: the
      cores divided by jobs).
    progress: None; True: a line per mesh on stderr; or a callable taking a dict (total, done,
      skipped, ok, failed, running, elapsed_seconds, meshes_per_minute, eta_seconds or None,
      last_key and last: the record just finished, None at the start), called after each mesh
      and once at the start, holding the GIL (the batch itself runs without it). An exception
      it raises (KeyboardInterrupt included: Ctrl-C is seen after the next mesh) ends the batch
      once the meshes already running finish, and is raised; the log keeps what finished.
    program: the ``ricci`` executable (default: see ``find_program``).
    param_options: options of ``ricci param``, underscores for dashes: ``cones=8`` ->
      ``--cones 8``, ``max_log_scale=0.5``, ``quantize=True`` -> ``--quantize``; False and None
      leave an option out (``polish="none"`` turns the polish off).

    Returns a list of dicts, one per mesh in job order, the lines of results.jsonl: key, input,
    outcome ("ok", "bad_input", "not_converged", "internal_error", "out_of_memory", "crashed",
    "timed_out", "spawn_failed"), seconds, peak_memory_kb, message (the "error: ..." lines of
    ricci param, or the limit), output (the UV OBJ; "" unless ok), report, area_distortion,
    angle_distortion (None when absent), flipped_faces, cones (-1 when absent), exit_code,
    signal, options, worker, finished_at, version, input_hash, input_stamp. A failed mesh is a
    record, never an exception.

    Raises InvalidInput (a ValueError), before anything runs, for an option ricci param does not
    take, a missing mesh file, two meshes with the same output; ricci.Error when the program is
    not found; IoError when out_dir cannot be written.
    """
    options = param_arguments(**param_options)
    executable = find_program(program)
    if isinstance(paths, (str, bytes)) or hasattr(paths, "__fspath__"):
        mesh_paths = os.fsdecode(os.fspath(paths))
    else:
        mesh_paths = [os.fsdecode(os.fspath(p)) for p in paths]
    if not jobs:
        jobs = os.cpu_count() or 1
    if progress is True:
        progress = _print_progress
    elif progress is False:
        progress = None
    lines, _ = _ricci._batch(mesh_paths, os.fsdecode(os.fspath(out_dir)), options, executable,
                             int(jobs), float(timeout), float(memory_limit), int(threads),
                             bool(retry_failed), progress)
    return [json.loads(line) for line in lines]


def batch_summary(out_dir):
    """OUTDIR/summary.json of a batch as a dict: total, counts by outcome, percentiles (count,
    min, p50, p90, p99, max, mean) of seconds, peak_memory_mb, area_distortion and
    angle_distortion, slowest, failed, wall_seconds, meshes_per_minute."""
    with open(os.path.join(os.fspath(out_dir), "summary.json"), encoding="utf-8") as f:
        return json.load(f)
