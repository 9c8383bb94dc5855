// run_batch, the scheduler: which meshes run, in what order, what a rerun skips, how outcomes are
// told apart. The worker program is a shell script standing in for `ricci param` (the real one
// runs end to end in tests/cli/batch_test.sh): it writes the OBJ and the report, appends its
// mesh to calls.txt, and ends as the mesh's first line says ("ok", "exit N", "segv", "sleep").
#include "ricci/batch/batch.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <utility>

#include "ricci/errors.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

struct Fixture {
  fs::path root, in, out, program, calls;
};

Fixture make_fixture(const std::string& name) {
  Fixture f;
  f.root = testing::fresh_tmp_dir(name);
  f.in = f.root / "in";
  f.out = f.root / "out";
  f.program = f.root / "fake-ricci";
  f.calls = f.root / "calls.txt";
  fs::create_directories(f.in);
  std::ofstream(f.program) << "#!/bin/sh\n"
                              "# fake-ricci param MESH -o OBJ --report JSON [options]\n"
                              "mesh=$2; obj=$4; report=$6; shift 6\n"
                              "echo \"$mesh\" >>'"
                           << f.calls.string()
                           << "'\n"
                              "what=$(head -n 1 \"$mesh\")\n"
                              "case \"$what\" in\n"
                              "  segv) kill -SEGV $$ ;;\n"
                              "  sleep) sleep 30 ;;\n"
                              "  exit*) echo 'warning: ignored' >&2; echo \"error: $mesh: "
                              "broken\" >&2; exit ${what#exit } ;;\n"
                              "esac\n"
                              "{ cat \"$mesh\"; echo \"options: $*\"; } >\"$obj\"\n"
                              "echo '{\"distortion\": {\"area_distortion_energy\": 0.5, "
                              "\"angle_distortion_mean\": 1.25, \"flipped_faces\": 0, \"cones\": "
                              "3}}' >\"$report\"\n";
  fs::permissions(f.program, fs::perms::owner_all);
  return f;
}

void write(const fs::path& path, const std::string& text) {
  testing::write_text_file(path, text);
}

/// Writes input meshes into f.in, each a (name, first lines) pair: the first line tells the fake
/// ricci what to do (ok, exit N, segv, sleep).
void write_inputs(const Fixture& f,
                  std::initializer_list<std::pair<const char*, const char*>> inputs) {
  for (const auto& [name, text] : inputs) write(f.in / name, text);
}

std::vector<std::string> lines(const fs::path& path) {
  std::vector<std::string> result;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) result.push_back(line);
  return result;
}

BatchOptions options_for(const Fixture& f, int jobs = 1) {
  BatchOptions options;
  options.program = f.program.string();
  options.jobs = jobs;
  return options;
}

const MeshRecord& record_of(const BatchResult& r, const std::string& key) {
  for (const MeshRecord& record : r.records) {
    if (record.key == key) return record;
  }
  throw std::runtime_error("no record for " + key);
}

TEST(RunBatch, RunsLargestFirstAndRecordsEachMeshOnce) {
  const Fixture f = make_fixture("run_batch_order");
  write(f.in / "small.obj", "ok\n");
  write(f.in / "large.obj", "ok\n" + std::string(5000, '#') + "\n");
  write(f.in / "sub/middle.obj", "ok\n" + std::string(500, '#') + "\n");
  const std::vector<BatchJob> jobs =
      list_batch_jobs(f.in.string(), f.out.string(), {"--cones", "8"});
  std::vector<int> done;
  BatchOptions options = options_for(f);
  options.progress = [&](const BatchProgress& p) { done.push_back(p.done); };
  const BatchResult r = run_batch(jobs, f.out.string(), options);
  // One worker: the calls are in the scheduler's order, largest first.
  EXPECT_EQ(lines(f.calls), (std::vector<std::string>{jobs[0].input, jobs[2].input, jobs[1].input}))
      << "keys: " << jobs[0].key << " " << jobs[1].key << " " << jobs[2].key;
  EXPECT_EQ(done, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_TRUE(r.all_ok);
  EXPECT_EQ(r.ran, 3);
  EXPECT_EQ(r.skipped, 0);
  ASSERT_EQ(r.records.size(), 3u);
  EXPECT_EQ(r.records[0].key, "large.obj");  // job order, not run order
  EXPECT_EQ(r.records[2].key, "sub/middle.obj");
  const MeshRecord& middle = record_of(r, "sub/middle.obj");
  EXPECT_EQ(middle.outcome, MeshOutcome::Ok);
  EXPECT_EQ(middle.output, (f.out / "sub/middle.obj").string());
  EXPECT_EQ(middle.area_distortion, 0.5);
  EXPECT_EQ(middle.angle_distortion, 1.25);
  EXPECT_EQ(middle.cones, 3);
  EXPECT_EQ(middle.options, (std::vector<std::string>{"--cones", "8"}));
  EXPECT_EQ(lines(f.out / "sub/middle.obj").back(), "options: --cones 8");
  EXPECT_EQ(lines(f.out / "results.jsonl").size(), 3u);
  EXPECT_TRUE(fs::exists(f.out / "summary.json"));
  EXPECT_EQ(r.summary.total, 3);
}

TEST(RunBatch, OutcomesComeFromTheExitStatusSignalAndLimit) {
  const Fixture f = make_fixture("run_batch_outcomes");
  write_inputs(f, {{"bad.obj", "exit 2\n"},
                   {"stuck.obj", "exit 3\n"},
                   {"bug.obj", "exit 4\n"},
                   {"hog.obj", "exit 5\n"},
                   {"crash.obj", "segv\n"},
                   {"hang.obj", "sleep\n"},
                   {"fine.obj", "ok\n"}});
  BatchOptions options = options_for(f, 2);
  options.limits.timeout_seconds = 0.5;
  options.limits.kill_grace_seconds = 0.5;
  const BatchResult r =
      run_batch(list_batch_jobs(f.in.string(), f.out.string(), {}), f.out.string(), options);
  EXPECT_FALSE(r.all_ok);
  EXPECT_EQ(record_of(r, "bad.obj").outcome, MeshOutcome::BadInput);
  // The error lines, without the warnings.
  EXPECT_EQ(record_of(r, "bad.obj").message, "error: " + (f.in / "bad.obj").string() + ": broken");
  EXPECT_EQ(record_of(r, "bad.obj").output, "");
  EXPECT_EQ(record_of(r, "stuck.obj").outcome, MeshOutcome::NotConverged);
  EXPECT_EQ(record_of(r, "bug.obj").outcome, MeshOutcome::InternalError);
  EXPECT_EQ(record_of(r, "hog.obj").outcome, MeshOutcome::OutOfMemory);
  EXPECT_EQ(record_of(r, "crash.obj").outcome, MeshOutcome::Crashed);
  EXPECT_EQ(record_of(r, "crash.obj").message, "killed by SIGSEGV");
  EXPECT_EQ(record_of(r, "hang.obj").outcome, MeshOutcome::TimedOut);
  EXPECT_EQ(record_of(r, "hang.obj").message, "stopped after 0.5 s (the timeout)");
  EXPECT_EQ(record_of(r, "fine.obj").outcome, MeshOutcome::Ok);
  const auto& counts = r.summary.counts;
  EXPECT_EQ(counts[0], (std::pair<std::string, int>{"ok", 1}));
  EXPECT_EQ(r.summary.failed.size(), 6u);
}

TEST(RunBatch, ARerunSkipsWhatStandsAndRunsWhatChanged) {
  const Fixture f = make_fixture("run_batch_rerun");
  write_inputs(f, {{"a.obj", "ok\n"},
                   {"b.obj", "ok\n"},
                   {"c.obj", "exit 2\n"},
                   {"d.obj", "ok\n"},
                   {"e.obj", "ok\n"}});
  const BatchOptions options = options_for(f);
  auto jobs = [&] { return list_batch_jobs(f.in.string(), f.out.string(), {}); };
  run_batch(jobs(), f.out.string(), options);
  ASSERT_EQ(lines(f.calls).size(), 5u);

  fs::remove(f.calls);
  BatchResult r = run_batch(jobs(), f.out.string(), options);
  EXPECT_EQ(r.ran, 0);
  EXPECT_EQ(r.skipped, 5);
  EXPECT_FALSE(fs::exists(f.calls));
  EXPECT_EQ(record_of(r, "c.obj").outcome, MeshOutcome::BadInput);  // failures stand too

  // b's bytes change, d's OBJ is gone, e gets a per-mesh option, a is touched but not changed:
  // b, d and e run again; a stands on its hash.
  write(f.in / "b.obj", "ok\nchanged\n");
  fs::remove(f.out / "d.obj");
  fs::last_write_time(f.in / "a.obj", fs::last_write_time(f.in / "a.obj") + std::chrono::hours(1));
  std::vector<BatchJob> changed = jobs();
  changed[4].options = {"--tol", "1e-9"};
  r = run_batch(changed, f.out.string(), options);
  EXPECT_EQ(r.ran, 3);
  std::vector<std::string> calls = lines(f.calls);
  std::sort(calls.begin(), calls.end());
  EXPECT_EQ(calls, (std::vector<std::string>{(f.in / "b.obj").string(), (f.in / "d.obj").string(),
                                             (f.in / "e.obj").string()}));
  // The log holds each mesh once, the replaced records gone.
  const ResultsLogContents log = read_results_log((f.out / "results.jsonl").string());
  ASSERT_EQ(log.records.size(), 5u);
  std::set<std::string> keys;
  for (const MeshRecord& rec : log.records) keys.insert(rec.key);
  EXPECT_EQ(keys.size(), 5u);

  // --retry-failed runs c (still failing) and nothing else.
  fs::remove(f.calls);
  BatchOptions retry = options;
  retry.retry_failed = true;
  r = run_batch(changed, f.out.string(), retry);
  EXPECT_EQ(lines(f.calls), (std::vector<std::string>{(f.in / "c.obj").string()}));
  EXPECT_EQ(read_results_log((f.out / "results.jsonl").string()).records.size(), 5u);
}

TEST(RunBatch, AnInterruptedBatchResumesFromItsLogEvenWithATornLine) {
  const Fixture f = make_fixture("run_batch_resume");
  for (int i = 0; i < 6; ++i) write(f.in / ("m" + std::to_string(i) + ".obj"), "ok\n");
  const std::vector<BatchJob> jobs = list_batch_jobs(f.in.string(), f.out.string(), {});
  BatchOptions options = options_for(f);
  options.stop_after = 2;
  BatchResult r = run_batch(jobs, f.out.string(), options);
  EXPECT_EQ(r.ran, 2);
  EXPECT_FALSE(r.all_ok);
  EXPECT_EQ(r.records.size(), 2u);
  // A kill in the middle of an append leaves half a line.
  std::ofstream(f.out / "results.jsonl", std::ios::app) << "{\"key\": \"m5.obj\", \"outc";
  options.stop_after = 0;
  r = run_batch(jobs, f.out.string(), options);
  EXPECT_EQ(r.ran, 4);
  EXPECT_EQ(r.skipped, 2);
  EXPECT_TRUE(r.all_ok);
  EXPECT_EQ(lines(f.calls).size(), 6u);
  const ResultsLogContents log = read_results_log((f.out / "results.jsonl").string());
  EXPECT_EQ(log.records.size(), 6u);
  EXPECT_EQ(log.torn_bytes, 0u);
}

TEST(RunBatch, LeftoverTemporariesOfAKilledChildAreRemoved) {
  const Fixture f = make_fixture("run_batch_temporaries");
  write(f.in / "a.obj", "ok\n");
  write(f.out / ".a.obj.tmp.12345.0", "half an OBJ");
  write(f.out / ".a.json.tmp.12345.1", "half a report");
  write(f.out / ".other.tmp.1.1", "not ours");
  run_batch(list_batch_jobs(f.in.string(), f.out.string(), {}), f.out.string(), options_for(f));
  EXPECT_FALSE(fs::exists(f.out / ".a.obj.tmp.12345.0"));
  EXPECT_FALSE(fs::exists(f.out / ".a.json.tmp.12345.1"));
  EXPECT_TRUE(fs::exists(f.out / ".other.tmp.1.1"));
}

TEST(RunBatch, ChildrenGetTheirShareOfTheCoresAndNoMpiVariables) {
  BatchOptions options;
  options.threads_per_job = 3;
  ::setenv("OMPI_COMM_WORLD_RANK", "1", 1);
  const std::vector<std::string> env = batch_child_environment(options, 2);
  ::unsetenv("OMPI_COMM_WORLD_RANK");
  EXPECT_NE(std::find(env.begin(), env.end(), "RICCI_NUM_THREADS=3"), env.end());
  EXPECT_NE(std::find(env.begin(), env.end(), "OMP_NUM_THREADS=3"), env.end());
  EXPECT_NE(std::find(env.begin(), env.end(), "OPENBLAS_NUM_THREADS=1"), env.end());
  EXPECT_NE(std::find(env.begin(), env.end(), "OMPI_COMM_WORLD_RANK"), env.end());  // removed
}

TEST(RunBatch, RefusesBadOptions) {
  const Fixture f = make_fixture("run_batch_refusals");
  write(f.in / "a.obj", "ok\n");
  const std::vector<BatchJob> jobs = list_batch_jobs(f.in.string(), f.out.string(), {});
  BatchOptions options = options_for(f);
  options.jobs = 0;
  EXPECT_THROW(run_batch(jobs, f.out.string(), options), InvalidInput);
  options = options_for(f);
  options.program = (f.root / "missing").string();
  EXPECT_THROW(run_batch(jobs, f.out.string(), options), InvalidInput);
  options.program = "";
  EXPECT_THROW(run_batch(jobs, f.out.string(), options), InvalidInput);
}

}  // namespace
}  // namespace ricci
