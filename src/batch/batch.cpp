#include "ricci/batch/batch.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <ctime>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/numerics/timer.hpp"
#include "ricci/version.hpp"

namespace ricci {
namespace fs = std::filesystem;

namespace {

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm parts{};
  ::gmtime_r(&now, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &parts);
  return text;
}

/// Size and modification time (nanoseconds) of a file: "bytes:mtime".
std::string file_stamp(const std::string& path) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) return "";
  return std::to_string(s.st_size) + ":" + std::to_string(s.st_mtim.tv_sec) + "." +
         std::to_string(s.st_mtim.tv_nsec);
}

/// The lines `ricci param` printed as its error ("error: ...", "internal error: ..."); else the
/// last few lines of its standard error.
std::string error_message(const std::string& stderr_text) {
  std::istringstream in(stderr_text);
  std::string line, errors;
  std::deque<std::string> last;
  while (std::getline(in, line)) {
    if (line.starts_with("error:") || line.starts_with("internal error:")) {
      errors += (errors.empty() ? "" : "\n") + line;
    }
    if (!line.empty()) last.push_back(line);
    if (last.size() > 5) last.pop_front();
  }
  if (!errors.empty()) return errors;
  std::string joined;
  for (const std::string& l : last) joined += (joined.empty() ? "" : "\n") + l;
  return joined;
}

/// Removes the temporary files write_file_atomically leaves when a child is killed: in the
/// folder of each output, ".NAME.tmp.*" (of any process: no other writer uses these names).
/// Each folder is listed once, however many jobs write into it (a batch of 10^5 meshes in one
/// folder would otherwise list it 10^5 times).
void remove_temporaries(const std::vector<const BatchJob*>& jobs) {
  std::map<fs::path, std::set<std::string>> names_by_folder;  // folder -> ".NAME.tmp."
  for (const BatchJob* job : jobs) {
    for (const std::string& target : {job->output, job->report}) {
      const fs::path path(target);
      names_by_folder[path.parent_path()].insert("." + path.filename().string() + ".tmp.");
    }
  }
  for (const auto& [folder, prefixes] : names_by_folder) {
    std::error_code error;
    for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
      const std::string name = it->path().filename().string();
      if (name.empty() || name[0] != '.') continue;
      // NAME may itself hold ".tmp.": try each occurrence as the end of the prefix.
      for (std::size_t tmp = name.find(".tmp."); tmp != std::string::npos;
           tmp = name.find(".tmp.", tmp + 1)) {
        if (prefixes.count(name.substr(0, tmp + 5)) > 0) {
          fs::remove(it->path(), error);
          break;
        }
      }
    }
  }
}

/// Figures of a written report (MeshRecord's distortion fields).
void read_report_figures(const std::string& path, MeshRecord& record) {
  std::ifstream in(path);
  if (!in) return;
  try {
    const nlohmann::json report = nlohmann::json::parse(in);
    const auto distortion = report.find("distortion");
    if (distortion == report.end() || !distortion->is_object()) return;
    record.area_distortion =
        distortion->value("area_distortion_energy", std::numeric_limits<double>::quiet_NaN());
    record.angle_distortion =
        distortion->value("angle_distortion_mean", std::numeric_limits<double>::quiet_NaN());
    record.flipped_faces = distortion->value("flipped_faces", -1);
    record.cones = distortion->value("cones", -1);
  } catch (const nlohmann::json::exception&) {
    // A report that does not parse leaves the figures absent; the outcome says what happened.
  }
}

/// Local workers: options.jobs threads, each taking the next job from a queue and running it in
/// a child of its own; records come back through a second queue.
class LocalWorkers final : public BatchWorkers {
 public:
  explicit LocalWorkers(const BatchOptions& options) : options_(options) {
    for (int slot = 1; slot <= options_.jobs; ++slot) {
      threads_.emplace_back([this, slot] { work("local " + std::to_string(slot)); });
    }
  }
  ~LocalWorkers() override {
    {
      // Jobs not started stay undone (a scheduler that stops early, or an exception); the
      // running ones finish, which is at most one mesh per slot.
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
      todo_.clear();
    }
    queued_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  int slots() const override { return options_.jobs; }
  void start(const BatchJob& job) override {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      todo_.push_back(job);
    }
    queued_.notify_one();
  }
  MeshRecord wait() override {
    std::unique_lock<std::mutex> lock(mutex_);
    finished_.wait(lock, [this] { return !done_.empty(); });
    MeshRecord record = std::move(done_.front());
    done_.pop_front();
    return record;
  }

 private:
  void work(const std::string& label) {
    for (;;) {
      BatchJob job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        queued_.wait(lock, [this] { return stopping_ || !todo_.empty(); });
        if (todo_.empty()) return;
        job = std::move(todo_.front());
        todo_.pop_front();
      }
      MeshRecord record = run_batch_mesh(job, options_, label);
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        done_.push_back(std::move(record));
      }
      finished_.notify_one();
    }
  }

  BatchOptions options_;
  std::mutex mutex_;
  std::condition_variable queued_, finished_;
  std::deque<BatchJob> todo_;
  std::deque<MeshRecord> done_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;  // last: started after the members they use
};

}  // namespace

std::vector<std::string> batch_child_environment(const BatchOptions& options, int slots) {
  int threads = options.threads_per_job;
  if (threads <= 0) {
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::max(1, cores / std::max(1, slots));
  }
  // CHOLMOD's OpenMP threads too: a child gets its share of the cores and no more.
  std::vector<std::string> environment = {"RICCI_NUM_THREADS=" + std::to_string(threads),
                                          "OMP_NUM_THREADS=" + std::to_string(threads),
                                          "OPENBLAS_NUM_THREADS=1"};
  // A child is not an MPI process: the launcher's variables would make it look for its rank.
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    const std::string entry(*e);
    if (entry.starts_with("OMPI_") || entry.starts_with("PMIX_") || entry.starts_with("PMI_")) {
      environment.push_back(entry.substr(0, entry.find('=')));
    }
  }
  return environment;
}

namespace {

/// A record naming the job, its worker and this ricci's version; the outcome still to fill in.
MeshRecord record_for(const BatchJob& job, const std::string& worker) {
  MeshRecord record;
  record.key = job.key;
  record.input = job.input;
  record.options = job.options;
  record.worker = worker;
  record.version = version();
  return record;
}

MeshRecord run_mesh(const BatchJob& job, const BatchOptions& options, const std::string& worker) {
  MeshRecord record = record_for(job, worker);
  record.input_stamp = file_stamp(job.input);
  try {
    record.input_hash = hash_file(job.input);
  } catch (const IoError& e) {
    record.outcome = MeshOutcome::BadInput;
    record.message = std::string("error: ") + e.what();
    record.finished_at = utc_now();
    return record;
  }
  std::error_code error;
  fs::create_directories(fs::path(job.output).parent_path(), error);
  // Whatever is there afterwards is this run's.
  fs::remove(job.output, error);
  fs::remove(job.report, error);

  std::vector<std::string> argv = {options.program, "param",    job.input, "-o",
                                   job.output,      "--report", job.report};
  argv.insert(argv.end(), job.options.begin(), job.options.end());
  const int slots = std::max(1, options.jobs);
  const ChildResult child =
      run_child(argv, batch_child_environment(options, slots), options.limits);
  record.seconds = child.seconds;
  record.peak_memory_kb = child.peak_memory_kb;
  record.exit_code = child.exit_code;
  record.signal = child.signal;
  const std::string message = error_message(child.stderr_text);
  switch (child.end) {
    case ChildEnd::SpawnFailed:
      record.outcome = MeshOutcome::SpawnFailed;
      record.message = child.spawn_error;
      break;
    case ChildEnd::TimedOut: {
      record.outcome = MeshOutcome::TimedOut;
      std::ostringstream text;
      text << "stopped after " << options.limits.timeout_seconds << " s (the timeout)";
      record.message = text.str();
      break;
    }
    case ChildEnd::Signaled:
      record.outcome = MeshOutcome::Crashed;
      record.message = "killed by " + signal_name(child.signal) +
                       (message.empty() ? std::string() : ": " + message);
      break;
    case ChildEnd::Exited:
      switch (child.exit_code) {
        case 0:
          record.outcome = MeshOutcome::Ok;
          break;
        case 2:
          record.outcome = MeshOutcome::BadInput;
          break;
        case 3:
          record.outcome = MeshOutcome::NotConverged;
          break;
        case 5:
          record.outcome = MeshOutcome::OutOfMemory;
          break;
        default:
          record.outcome = MeshOutcome::InternalError;
          break;
      }
      if (record.outcome != MeshOutcome::Ok) {
        record.message = message.empty()
                             ? "ricci param exited with status " + std::to_string(child.exit_code)
                             : message;
      }
      break;
  }
  if (record.outcome == MeshOutcome::OutOfMemory && options.limits.memory_limit_mb > 0) {
    std::ostringstream text;
    text << " (the memory limit, " << options.limits.memory_limit_mb << " MB)";
    record.message += text.str();
  }
  if (child.end == ChildEnd::Signaled || child.end == ChildEnd::TimedOut) {
    remove_temporaries({&job});
  }
  if (record.outcome == MeshOutcome::Ok && fs::exists(job.output, error)) {
    record.output = job.output;
  } else if (record.outcome == MeshOutcome::Ok) {
    record.outcome = MeshOutcome::InternalError;
    record.message = "ricci param exited 0 but wrote no " + job.output;
  } else {
    fs::remove(job.output, error);  // a failed mesh has no UV OBJ
  }
  if (fs::exists(job.report, error)) {
    record.report = job.report;
    read_report_figures(job.report, record);
  }
  record.finished_at = utc_now();
  return record;
}

}  // namespace

MeshRecord run_batch_mesh(const BatchJob& job, const BatchOptions& options,
                          const std::string& worker) {
  try {
    return run_mesh(job, options, worker);
  } catch (const std::exception& e) {
    // The worker's own trouble (a folder it cannot create, memory): this mesh's record.
    MeshRecord record = record_for(job, worker);
    record.outcome = MeshOutcome::SpawnFailed;
    record.message = e.what();
    record.finished_at = utc_now();
    return record;
  }
}

std::unique_ptr<BatchWorkers> make_local_workers(const BatchOptions& options) {
  return std::make_unique<LocalWorkers>(options);
}

BatchResult run_batch(const std::vector<BatchJob>& jobs, const std::string& out_dir,
                      const BatchOptions& options, BatchWorkers* workers) {
  if (options.program.empty()) throw InvalidInput("run_batch: BatchOptions::program is empty");
  if (options.jobs < 1) throw InvalidInput("run_batch: BatchOptions::jobs must be >= 1");
  if (options.stop_after < 0)
    throw InvalidInput("run_batch: BatchOptions::stop_after must be >= 0");
  if (::access(options.program.c_str(), X_OK) != 0) {
    throw InvalidInput("run_batch: BatchOptions::program " + options.program +
                       " is not an executable file");
  }
  const Clock::time_point start = Clock::now();
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error || !fs::is_directory(out_dir)) {
    throw IoError("ricci batch: cannot create the output folder " + out_dir + ": " +
                  error.message());
  }
  BatchResult result;
  result.log_path = (fs::path(out_dir) / "results.jsonl").string();
  result.summary_path = (fs::path(out_dir) / "summary.json").string();

  // The records that stand; the latest per key wins.
  const ResultsLogContents log = read_results_log(result.log_path);
  std::map<std::string, std::size_t> latest;
  for (std::size_t i = 0; i < log.records.size(); ++i) latest[log.records[i].key] = i;
  std::set<std::string> rerun;
  std::vector<std::size_t> pending;
  std::vector<std::optional<MeshRecord>> final_records(jobs.size());
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    const BatchJob& job = jobs[j];
    const auto it = latest.find(job.key);
    bool stands = false;
    if (it != latest.end()) {
      const MeshRecord& r = log.records[it->second];
      const bool same_options = r.options == job.options;
      bool same_input = !r.input_stamp.empty() && r.input_stamp == file_stamp(job.input);
      if (!same_input && same_options) {
        try {
          same_input = r.input_hash == hash_file(job.input);
        } catch (const IoError&) {
          same_input = false;
        }
      }
      const bool complete =
          r.outcome == MeshOutcome::Ok ? fs::exists(job.output, error) : !options.retry_failed;
      stands = same_options && same_input && complete;
      if (stands) final_records[j] = r;
    }
    if (!stands) {
      rerun.insert(job.key);
      pending.push_back(j);
    }
  }
  // The log without the records about to be replaced, each key once, a torn line cut off.
  const bool duplicates = latest.size() != log.records.size();
  const bool replaced = std::any_of(rerun.begin(), rerun.end(),
                                    [&](const std::string& key) { return latest.count(key) > 0; });
  if (duplicates || replaced || log.torn_bytes > 0) {
    std::vector<MeshRecord> kept;
    for (std::size_t i = 0; i < log.records.size(); ++i) {
      const MeshRecord& r = log.records[i];
      if (latest[r.key] == i && rerun.count(r.key) == 0) kept.push_back(r);
    }
    rewrite_results_log(result.log_path, kept);
  }
  // Largest first: the long meshes start early instead of ending the batch alone.
  std::stable_sort(pending.begin(), pending.end(),
                   [&](std::size_t a, std::size_t b) { return jobs[a].bytes > jobs[b].bytes; });
  std::vector<const BatchJob*> to_clean;
  to_clean.reserve(pending.size());
  for (const std::size_t j : pending) to_clean.push_back(&jobs[j]);
  remove_temporaries(to_clean);

  std::unique_ptr<BatchWorkers> local;
  if (workers == nullptr) {
    local = make_local_workers(options);
    workers = local.get();
  }
  std::map<std::string, std::size_t> index_of;
  for (std::size_t j = 0; j < jobs.size(); ++j) index_of[jobs[j].key] = j;

  BatchProgress progress;
  progress.total = static_cast<int>(jobs.size());
  progress.skipped = static_cast<int>(jobs.size() - pending.size());
  progress.done = progress.skipped;
  for (const auto& r : final_records) {
    if (!r) continue;
    (r->outcome == MeshOutcome::Ok ? progress.ok : progress.failed) += 1;
  }
  auto report_progress = [&](const MeshRecord* last) {
    progress.last = last;
    progress.elapsed_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const int ran = progress.done - progress.skipped;
    if (ran > 0 && progress.elapsed_seconds > 0) {
      progress.meshes_per_minute = 60.0 * ran / progress.elapsed_seconds;
      progress.eta_seconds = (progress.total - progress.done) * progress.elapsed_seconds / ran;
    }
    if (options.progress) options.progress(progress);
  };
  report_progress(nullptr);

  ResultsLogWriter writer(result.log_path);
  std::size_t next = 0;
  const std::size_t limit = options.stop_after > 0
                                ? std::min<std::size_t>(pending.size(), options.stop_after)
                                : pending.size();
  int running = 0;
  const int slots = std::max(1, workers->slots());
  while (next < limit || running > 0) {
    while (next < limit && running < slots) {
      workers->start(jobs[pending[next++]]);
      ++running;
    }
    progress.running = running;
    MeshRecord record = workers->wait();
    --running;
    progress.running = running;
    writer.append(record);
    const auto it = index_of.find(record.key);
    if (it == index_of.end())
      throw Error("run_batch: a worker returned an unknown mesh " + record.key);
    final_records[it->second] = record;
    ++result.ran;
    ++progress.done;
    (record.outcome == MeshOutcome::Ok ? progress.ok : progress.failed) += 1;
    report_progress(&*final_records[it->second]);
  }
  result.skipped = progress.skipped;
  std::vector<MeshRecord> records;
  for (const auto& r : final_records) {
    if (r) records.push_back(*r);
  }
  result.all_ok = records.size() == jobs.size() &&
                  std::all_of(records.begin(), records.end(),
                              [](const MeshRecord& r) { return r.outcome == MeshOutcome::Ok; });
  result.records = std::move(records);
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  result.summary = summarize_batch(result.records, result.seconds);
  result.summary.ran = result.ran;
  const std::string summary = summary_to_json(result.summary);
  write_file_atomically(result.summary_path, [&](std::ostream& out) { out << summary << "\n"; });
  return result;
}

}  // namespace ricci
