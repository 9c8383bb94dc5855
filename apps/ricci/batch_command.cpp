#include "batch_command.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>

#include "batch_mpi.hpp"
#include "param_command.hpp"
#include "ricci/batch/batch.hpp"
#include "ricci/errors.hpp"
#ifdef RICCI_HAVE_RENDER
#include "ricci/render/batch_summary.hpp"
#endif

namespace ricci::cli {

namespace fs = std::filesystem;

namespace {

std::string duration_text(double seconds) {
  if (seconds < 0) return "?";
  char text[32];
  const long s = std::lround(seconds);
  if (s >= 3600) {
    std::snprintf(text, sizeof text, "%ldh%02ldm", s / 3600, (s % 3600) / 60);
  } else if (s >= 60) {
    std::snprintf(text, sizeof text, "%ldm%02lds", s / 60, s % 60);
  } else {
    std::snprintf(text, sizeof text, "%lds", s);
  }
  return text;
}

/// A bar on a terminal, a line per mesh with --progress, nothing otherwise.
std::function<void(const BatchProgress&)> make_batch_progress(bool lines) {
  const bool bar = !lines && ::isatty(STDERR_FILENO);
  if (!lines && !bar) return {};
  return [lines](const BatchProgress& p) {
    const std::string rate = p.meshes_per_minute > 0
                                 ? std::to_string(static_cast<int>(p.meshes_per_minute)) + "/min"
                                 : "-/min";
    if (lines) {
      if (p.last == nullptr) {
        std::fprintf(stderr, "batch: %d meshes, %d done before, %d to run\n", p.total, p.skipped,
                     p.total - p.done);
        return;
      }
      std::fprintf(stderr, "[%d/%d] %s %s %.2f s  (ok %d, failed %d; %.1f meshes/min, ETA %s)\n",
                   p.done, p.total, mesh_outcome_name(p.last->outcome), p.last->key.c_str(),
                   p.last->seconds, p.ok, p.failed, p.meshes_per_minute,
                   duration_text(p.eta_seconds).c_str());
      return;
    }
    constexpr int kWidth = 30;
    const int filled = p.total > 0 ? kWidth * p.done / p.total : kWidth;
    std::string cells(kWidth, '.');
    std::fill(cells.begin(), cells.begin() + filled, '#');
    std::fprintf(stderr, "\rbatch [%s] %d/%d  ok %d  failed %d  running %d  %s  ETA %s   ",
                 cells.c_str(), p.done, p.total, p.ok, p.failed, p.running, rate.c_str(),
                 duration_text(p.eta_seconds).c_str());
    if (p.done == p.total) std::fputc('\n', stderr);
    std::fflush(stderr);
  };
}

void print_summary(const BatchResult& result, const std::string& out_dir,
                   const std::string& picture) {
  const BatchSummary& s = result.summary;
  std::cout << s.total << " meshes:";
  bool first = true;
  for (const auto& [name, count] : s.counts) {
    if (count == 0) continue;
    std::cout << (first ? " " : ", ") << count << " " << name;
    first = false;
  }
  std::cout << " (" << result.ran << " run now, " << result.skipped << " from an earlier run) in "
            << duration_text(result.seconds) << "\n";
  if (s.seconds.count > 0) {
    std::cout << "  seconds per mesh: median " << s.seconds.p50 << ", p90 " << s.seconds.p90
              << ", max " << s.seconds.max << "\n";
  }
  if (s.angle_distortion.count > 0) {
    std::cout << "  angle distortion (mean sigma ratio): median " << s.angle_distortion.p50
              << ", p90 " << s.angle_distortion.p90 << ", max " << s.angle_distortion.max
              << "; area distortion median " << s.area_distortion.p50 << "\n";
  }
  if (!s.slowest.empty()) {
    std::cout << "  slowest: " << s.slowest.front().first << " " << s.slowest.front().second
              << " s\n";
  }
  constexpr std::size_t kShown = 20;
  for (std::size_t i = 0; i < s.failed.size() && i < kShown; ++i) {
    const MeshRecord& r = s.failed[i];
    std::string message = r.message.substr(0, r.message.find('\n'));
    std::cout << "  " << mesh_outcome_name(r.outcome) << ": " << r.key << ": " << message << "\n";
  }
  if (s.failed.size() > kShown) {
    std::cout << "  ... and " << s.failed.size() - kShown << " more (summary.json)\n";
  }
  std::cout << "  wrote " << (fs::path(out_dir) / "results.jsonl").string() << ", "
            << result.summary_path << (picture.empty() ? "" : ", " + picture) << "\n";
}

}  // namespace

CLI::App* add_batch_subcommand(CLI::App& app, BatchArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "batch",
      "Parameterize many meshes: `ricci param` on every mesh of INPUT, each in a child process "
      "of its own (a crash, a timeout or a memory blow-up is that mesh's result), local workers "
      "by default, or one scheduler and many workers under `mpirun -n K ricci batch ...`. "
      "Writes OUTDIR/KEY.obj and KEY.json per mesh (KEY: the mesh's path under INPUT less its "
      "extension; pig_off and pig_stl for a pig.off beside a pig.stl), OUTDIR/results.jsonl "
      "(one line per mesh), summary.json and summary.png. Rerunning the same command skips "
      "what is done. Options not listed here are passed to `ricci param` (see ricci param "
      "--help). docs/batch.md");
  cmd->add_option("INPUT", args.input,
                  "a folder (every .obj .off .ply .stl under it) or a manifest: one mesh path per "
                  "line, optionally a TAB and options of ricci param for that mesh")
      ->required();
  cmd->add_option("-o,--output", args.output, "output folder")->required();
  cmd->add_option("-j,--jobs", args.jobs,
                  "local worker processes at once (0: the machine's cores); under mpirun every "
                  "rank but the first runs one mesh at a time")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--timeout", args.timeout,
                  "seconds per mesh before it is stopped and recorded as timed_out (0: none)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--memory-limit", args.memory_limit,
                  "MiB of address space per mesh; an allocation past it ends that mesh as "
                  "out_of_memory (0: none)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", args.threads,
                  "threads per mesh (RICCI_NUM_THREADS; 0: cores / jobs)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--retry-failed", args.retry_failed,
                "run again the meshes whose earlier result is a failure (by default a rerun "
                "skips every mesh already recorded for the same file and options)");
  cmd->add_flag("--progress", args.progress,
                "a line per mesh on stderr (with rate and ETA); a terminal gets a bar anyway");
  cmd->add_flag("--json", args.json, "print the summary as JSON");
  cmd->allow_extras();
  return cmd;
}

int run_batch_command(BatchArgs& args, const CLI::App& command, const std::string& argv0) {
  MpiSession mpi;  // before anything else: under mpirun every rank starts here
  args.param_options = command.remaining();
  BatchOptions options;
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  options.program = error ? fs::absolute(argv0).string() : self.string();
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  options.jobs = args.jobs > 0 ? args.jobs : cores;
  options.limits.timeout_seconds = args.timeout;
  options.limits.memory_limit_mb = args.memory_limit;
  options.threads_per_job = args.threads;
  options.retry_failed = args.retry_failed;
  if (mpi.role() == MpiRole::Worker) return mpi.work(options);

  check_param_options(args.param_options, "ricci batch", "the -o folder");
  std::vector<BatchJob> jobs = list_batch_jobs(args.input, args.output, args.param_options);
  for (const BatchJob& job : jobs) {
    if (job.options.size() > args.param_options.size()) {
      check_param_options(job.options, job.key + " (manifest options)", "the -o folder");
    }
  }
  options.progress = make_batch_progress(args.progress);
  const BatchResult result = mpi.role() == MpiRole::Scheduler
                                 ? mpi.schedule(jobs, args.output, options)
                                 : run_batch(jobs, args.output, options);
  std::string picture;
#ifdef RICCI_HAVE_RENDER
  picture = (fs::path(args.output) / "summary.png").string();
  write_batch_summary_picture(result.summary, picture);
#endif
  if (args.json) {
    std::cout << summary_to_json(result.summary) << "\n";
  } else {
    print_summary(result, args.output, picture);
  }
  return result.all_ok ? kOk : kSomeFailed;
}

Subcommand add_batch_command(CLI::App& app, const std::string& argv0) {
  auto args = std::make_shared<BatchArgs>();
  CLI::App* cmd = add_batch_subcommand(app, *args);
  return {cmd, [args, cmd, argv0] { return run_batch_command(*args, *cmd, argv0); }};
}

}  // namespace ricci::cli
