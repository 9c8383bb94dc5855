// The results log: records round trip, torn last lines, atomic rewrites, appends, file hashes.
#include "ricci/batch/results_log.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "ricci/errors.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

fs::path fresh(const std::string& name) {
  return testing::fresh_tmp_dir(name);
}

MeshRecord sample(const std::string& key, MeshOutcome outcome) {
  MeshRecord r;
  r.key = key;
  r.input = "/data/" + key;
  r.input_hash = "fnv1a64:0123456789abcdef";
  r.input_stamp = "12:3.4";
  r.options = {"--cones", "8", "caf\xc3\xa9"};
  r.outcome = outcome;
  r.exit_code = outcome == MeshOutcome::Ok ? 0 : 2;
  r.seconds = 1.25;
  r.peak_memory_kb = 4096;
  r.message = outcome == MeshOutcome::Ok ? "" : "error: x.obj line 3: bad index\nsecond line";
  r.output = "/out/x.obj";
  r.report = "/out/x.json";
  r.area_distortion = outcome == MeshOutcome::Ok ? 0.5 : std::nan("");
  r.angle_distortion = 1.02;
  r.flipped_faces = 0;
  r.cones = 8;
  r.worker = "local 1";
  r.finished_at = "2026-11-26T15:00:00Z";
  r.version = "0.1.0";
  return r;
}

TEST(ResultsLog, ARecordSurvivesItsJsonLine) {
  for (const MeshOutcome outcome : {MeshOutcome::Ok, MeshOutcome::BadInput, MeshOutcome::Crashed,
                                    MeshOutcome::TimedOut, MeshOutcome::OutOfMemory}) {
    const MeshRecord r = sample("a/b.obj", outcome);
    const std::string line = to_json_line(r);
    EXPECT_EQ(line.find('\n'), std::string::npos);
    const MeshRecord back = parse_mesh_record(line);
    EXPECT_EQ(back.key, r.key);
    EXPECT_EQ(back.options, r.options);
    EXPECT_EQ(back.outcome, outcome);
    EXPECT_EQ(back.message, r.message);
    EXPECT_EQ(back.input_stamp, r.input_stamp);
    EXPECT_EQ(back.seconds, 1.25);
    EXPECT_EQ(std::isnan(back.area_distortion), std::isnan(r.area_distortion));
    EXPECT_EQ(to_json_line(back), line);
  }
  EXPECT_EQ(parse_mesh_outcome(mesh_outcome_name(MeshOutcome::NotConverged)),
            MeshOutcome::NotConverged);
  EXPECT_THROW(parse_mesh_outcome("fine"), InvalidInput);
  EXPECT_THROW(parse_mesh_record("{\"key\": \"a\"}"), InvalidInput);
  // The key is required (the outcome too); the other fields default.
  EXPECT_THROW(parse_mesh_record("{\"outcome\": \"ok\"}"), InvalidInput);
  EXPECT_THROW(parse_mesh_record("[1, 2"), InvalidInput);
}

TEST(ResultsLog, ATornLastLineIsIgnoredAndABadMiddleLineRefused) {
  const fs::path dir = fresh("results_log_torn");
  const std::string path = (dir / "results.jsonl").string();
  EXPECT_TRUE(read_results_log(path).records.empty());  // missing: empty
  {
    ResultsLogWriter writer(path);
    writer.append(sample("a.obj", MeshOutcome::Ok));
    writer.append(sample("b.obj", MeshOutcome::BadInput));
  }
  const std::uintmax_t whole = fs::file_size(path);
  const std::string third = to_json_line(sample("c.obj", MeshOutcome::Ok));
  std::ofstream(path, std::ios::app) << third.substr(0, third.size() / 2);  // cut off by a kill
  ResultsLogContents log = read_results_log(path);
  ASSERT_EQ(log.records.size(), 2u);
  EXPECT_EQ(log.records[1].key, "b.obj");
  EXPECT_EQ(log.valid_bytes, whole);
  EXPECT_EQ(log.torn_bytes, third.size() / 2);

  rewrite_results_log(path, log.records);
  EXPECT_EQ(fs::file_size(path), whole);
  log = read_results_log(path);
  EXPECT_EQ(log.torn_bytes, 0u);

  std::ofstream(path, std::ios::app) << "garbage\n" << third << "\n";
  try {
    read_results_log(path);
    FAIL() << "a bad line in the middle";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
}

TEST(ResultsLog, FileHashesTellContentsApart) {
  const fs::path dir = fresh("results_log_hash");
  std::ofstream(dir / "a") << "v 0 0 0\n";
  std::ofstream(dir / "b") << "v 0 0 1\n";
  testing::write_text_file(dir / "empty", "");
  const std::string a = hash_file((dir / "a").string());
  EXPECT_EQ(a.size(), 8u + 16u);
  EXPECT_EQ(a, hash_file((dir / "a").string()));
  EXPECT_NE(a, hash_file((dir / "b").string()));
  // FNV-1a 64 of no bytes is its offset basis.
  EXPECT_EQ(hash_file((dir / "empty").string()), "fnv1a64:cbf29ce484222325");
  EXPECT_THROW(hash_file((dir / "missing").string()), IoError);
}

}  // namespace
}  // namespace ricci
