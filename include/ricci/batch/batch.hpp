#pragma once
/// \file
/// `ricci batch`: parameterize many meshes, each by `ricci param` in a child process of its own
/// (time and memory limits; a crash is that mesh's result), on local worker threads or on other
/// machines (MPI ranks, apps/ricci), with a results log that makes a killed batch resumable.
///
/// The scheduler (this process) hands out meshes, largest first, to whichever worker is free,
/// and alone writes the results log. A worker writes a mesh's outputs (atomically: temporary file
/// and rename), then its record reaches the log; a batch killed in between runs that mesh again
/// on resume and writes the same bytes.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ricci/batch/child_process.hpp"
#include "ricci/batch/jobs.hpp"
#include "ricci/batch/results_log.hpp"
#include "ricci/batch/summary.hpp"

namespace ricci {

/// Where a batch is, after each mesh.
struct BatchProgress {
  int total = 0;    ///< meshes in the batch
  int done = 0;     ///< finished, in this run or an earlier one
  int skipped = 0;  ///< of those, taken from the log of an earlier run
  int ok = 0;       ///< done and Ok
  int failed = 0;   ///< done and not Ok
  int running = 0;  ///< in a worker now
  double elapsed_seconds = 0;
  double meshes_per_minute = 0;      ///< this run's finished meshes over its elapsed time
  double eta_seconds = -1;           ///< remaining meshes at that rate (-1: unknown yet)
  const MeshRecord* last = nullptr;  ///< the mesh just finished (nullptr before the first)
};

/// Options of run_batch.
struct BatchOptions {
  /// The `ricci` executable run as `PROGRAM param MESH -o OBJ --report JSON [options]`.
  std::string program;
  /// Local workers (child processes at once); ignored when run_batch is given workers.
  int jobs = 1;
  /// Per mesh: wall-clock and memory limits (ChildLimits).
  ChildLimits limits;
  /// RICCI_NUM_THREADS of each child; 0: the machine's cores divided by jobs, at least 1.
  int threads_per_job = 0;
  /// Run again the meshes whose record is not Ok (by default a rerun skips every mesh with a
  /// record for the same input bytes and options).
  bool retry_failed = false;
  /// Called after each mesh (and once at the start) on the scheduler's thread.
  std::function<void(const BatchProgress&)> progress;
  /// Stop after this many meshes of this run (0: all); for tests that interrupt a batch.
  int stop_after = 0;
};

/// What run_batch did.
struct BatchResult {
  std::vector<MeshRecord> records;  ///< one per job, in the jobs' order
  int ran = 0;                      ///< meshes run in this call
  int skipped = 0;                  ///< meshes whose earlier record stands
  bool all_ok = false;              ///< every record Ok
  double seconds = 0;
  BatchSummary summary;
  std::string log_path;      ///< OUTDIR/results.jsonl
  std::string summary_path;  ///< OUTDIR/summary.json
};

/// Where the meshes run: local threads each with a child, or MPI ranks. One mesh per slot.
class BatchWorkers {
 public:
  virtual ~BatchWorkers() = default;
  /// Meshes that can run at once.
  virtual int slots() const = 0;
  /// Starts a job on a free slot (the scheduler never starts more than slots()).
  virtual void start(const BatchJob& job) = 0;
  /// Blocks until a started job finishes; returns its record.
  virtual MeshRecord wait() = 0;
};

/// Runs one mesh the way every worker does: `options.program param ...` in a child with the
/// limits, then the record from its exit and its report. Thread-safe; never throws (a failure of
/// the worker itself is the mesh's SpawnFailed record).
/// \param worker the record's worker label
MeshRecord run_batch_mesh(const BatchJob& job, const BatchOptions& options,
                          const std::string& worker);

/// options.jobs threads, each running run_batch_mesh.
std::unique_ptr<BatchWorkers> make_local_workers(const BatchOptions& options);

/// The environment overrides of a mesh's child: RICCI_NUM_THREADS, OMP_NUM_THREADS and
/// OPENBLAS_NUM_THREADS, and
/// the MPI launcher's variables removed (a child is not an MPI process).
std::vector<std::string> batch_child_environment(const BatchOptions& options, int slots);

/// Runs the batch: reads OUTDIR/results.jsonl (a torn last line cut off), keeps the records
/// that stand (same input bytes and options, Ok with its OBJ present, or failed and not
/// retry_failed), rewrites the log without the others, runs the rest largest first on the
/// workers (local ones when null), appends each record as it arrives, then writes
/// OUTDIR/summary.json.
/// \throw InvalidInput when options are bad (no program, jobs < 1); IoError when OUTDIR cannot
///        be created or the log written
BatchResult run_batch(const std::vector<BatchJob>& jobs, const std::string& out_dir,
                      const BatchOptions& options, BatchWorkers* workers = nullptr);

}  // namespace ricci
