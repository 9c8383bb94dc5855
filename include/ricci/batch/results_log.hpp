#pragma once
/// \file
/// The results log of a batch: OUTDIR/results.jsonl, one JSON object per line, one line per mesh.
/// Only the scheduler writes it, a whole line per write(2), synced before the next mesh is
/// counted done, so a batch killed at any moment leaves at most one torn last line (ignored and
/// cut off on the next run) and never a mesh recorded twice.

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "ricci/enum_names.hpp"

namespace ricci {

/// How a mesh of a batch ended.
enum class MeshOutcome {
  Ok,             ///< `ricci param` exited 0: the UV OBJ and the report are written
  BadInput,       ///< exit 2: unreadable or defective mesh, bad option (message as param prints)
  NotConverged,   ///< exit 3: the flow stopped short (the report is written, the OBJ is not)
  InternalError,  ///< exit 4, or any other status
  OutOfMemory,    ///< exit 5: an allocation failed under the memory limit (a child the kernel's
                  ///< out-of-memory killer ends dies of SIGKILL: Crashed, with that signal)
  Crashed,        ///< killed by a signal (SIGSEGV, SIGABRT, SIGKILL from outside, ...)
  TimedOut,       ///< stopped by the batch's --timeout
  SpawnFailed,    ///< the worker could not start `ricci param`
};

template <>
struct EnumNames<MeshOutcome> {
  static constexpr const char* noun = "mesh outcome";
  static constexpr std::array<EnumName<MeshOutcome>, 8> names{{
      {MeshOutcome::Ok, "ok"},
      {MeshOutcome::BadInput, "bad_input"},
      {MeshOutcome::NotConverged, "not_converged"},
      {MeshOutcome::InternalError, "internal_error"},
      {MeshOutcome::OutOfMemory, "out_of_memory"},
      {MeshOutcome::Crashed, "crashed"},
      {MeshOutcome::TimedOut, "timed_out"},
      {MeshOutcome::SpawnFailed, "spawn_failed"},
  }};
};

/// "ok", "bad_input", "not_converged", "internal_error", "out_of_memory", "crashed",
/// "timed_out", "spawn_failed".
const char* mesh_outcome_name(MeshOutcome outcome);
/// The inverse of mesh_outcome_name. \throw InvalidInput on an unknown name
MeshOutcome parse_mesh_outcome(const std::string& name);

/// One line of the results log.
struct MeshRecord {
  std::string key;         ///< BatchJob::key
  std::string input;       ///< BatchJob::input
  std::string input_hash;  ///< hash_file of the input when it ran
  /// Size and modification time of the input when it ran: when both still hold, a rerun trusts
  /// input_hash without reading the file again.
  std::string input_stamp;
  std::vector<std::string> options;  ///< BatchJob::options
  MeshOutcome outcome = MeshOutcome::InternalError;
  int exit_code = -1;       ///< the child's exit status (-1: it did not exit)
  int signal = 0;           ///< the signal that ended it (0: none)
  double seconds = 0;       ///< wall clock of the child
  long peak_memory_kb = 0;  ///< its maximum resident set size
  std::string message;      ///< why it failed: the error lines `ricci param` printed, or the limit
  std::string output;       ///< the UV OBJ ("" unless Ok)
  std::string report;       ///< the JSON report ("" when not written)
  /// Figures from the report (NaN when absent): eq. 9 area distortion, mean sigma ratio.
  double area_distortion = std::numeric_limits<double>::quiet_NaN();
  double angle_distortion = std::numeric_limits<double>::quiet_NaN();
  int flipped_faces = -1, cones = -1;  ///< from the report; -1 when absent
  std::string worker;                  ///< "local 2", "rank 3 on HOST"
  std::string finished_at;             ///< UTC, ISO 8601
  std::string version;                 ///< of the worker's ricci
};

/// The record as one line of JSON (no newline).
std::string to_json_line(const MeshRecord& record);
/// Parses a line written by to_json_line. \throw InvalidInput when it is not one
MeshRecord parse_mesh_record(const std::string& line);

/// What read_results_log found.
struct ResultsLogContents {
  std::vector<MeshRecord> records;  ///< in file order (a key may appear more than once)
  /// Bytes of a last line that has no newline or does not parse (a write cut off by a kill).
  std::uintmax_t torn_bytes = 0;
  std::uintmax_t valid_bytes = 0;  ///< bytes before it
};

/// Reads a results log; a missing file is an empty log.
/// \throw IoError when it cannot be read; InvalidInput when a line other than the last is not a
///        record (naming the line)
ResultsLogContents read_results_log(const std::string& path);

/// Replaces the log with these records, atomically (temporary file and rename).
void rewrite_results_log(const std::string& path, const std::vector<MeshRecord>& records);

/// Appends records to a log, each with one write(2) and an fdatasync before it returns.
class ResultsLogWriter {
 public:
  /// \throw IoError when the file cannot be opened for appending
  explicit ResultsLogWriter(const std::string& path);
  ~ResultsLogWriter();
  ResultsLogWriter(const ResultsLogWriter&) = delete;
  ResultsLogWriter& operator=(const ResultsLogWriter&) = delete;
  /// \throw IoError when the write fails
  void append(const MeshRecord& record);

 private:
  std::string path_;
  int fd_ = -1;
};

/// A 64-bit FNV-1a hash of a file's bytes, as "fnv1a64:" and 16 hex digits: tells whether an
/// input changed since its record was written. \throw IoError when it cannot be read
std::string hash_file(const std::string& path);

}  // namespace ricci
