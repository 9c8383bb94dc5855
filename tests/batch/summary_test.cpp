// The batch summary: percentiles against hand-computed values, counts, the slowest and failed
// meshes, and its JSON.

#include "ricci/batch/summary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace ricci {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Interpolation takes one product and one sum of numbers of order 1..100: a few ulps.
constexpr double kTol = 1e-12;

MeshRecord record(const std::string& key, MeshOutcome outcome, double seconds,
                  long peak_memory_kb = 2048, double angle = kNaN, double area = kNaN) {
  MeshRecord r;
  r.key = key;
  r.outcome = outcome;
  r.seconds = seconds;
  r.peak_memory_kb = peak_memory_kb;
  r.angle_distortion = angle;
  r.area_distortion = area;
  r.exit_code = outcome == MeshOutcome::Ok ? 0 : 4;
  return r;
}

/// The figures of the values 1, 2, 3, 4 (in any order). Rank h = 3 p (0-based): p50 at 1.5 ->
/// 2.5, p90 at 2.7 -> 3 + 0.7, p99 at 2.97 -> 3 + 0.97.
void expect_figures_of_one_to_four(const Percentiles& p) {
  EXPECT_EQ(p.count, 4);
  EXPECT_EQ(p.min, 1);
  EXPECT_EQ(p.max, 4);
  EXPECT_NEAR(p.p50, 2.5, kTol);
  EXPECT_NEAR(p.p90, 3.7, kTol);
  EXPECT_NEAR(p.p99, 3.97, kTol);
  EXPECT_NEAR(p.mean, 2.5, kTol);
}

TEST(BatchPercentiles, FourValues) {
  expect_figures_of_one_to_four(percentiles({4, 1, 3, 2}));
}

TEST(BatchPercentiles, MatchesNumpyLinear) {
  // numpy.percentile([10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 1000], [50, 90, 99]):
  // h = 10 p -> 60, 100 (rank 9 exactly), 100 + 0.9 * 900 = 910.
  const Percentiles p = percentiles({1000, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100});
  EXPECT_EQ(p.count, 11);
  EXPECT_NEAR(p.p50, 60, kTol);
  EXPECT_NEAR(p.p90, 100, 1e-10);
  EXPECT_NEAR(p.p99, 910, 1e-10);
  EXPECT_NEAR(p.mean, 1550.0 / 11, 1e-10);
}

TEST(BatchPercentiles, SingleValue) {
  const Percentiles p = percentiles({7.5});
  EXPECT_EQ(p.count, 1);
  for (double x : {p.min, p.p50, p.p90, p.p99, p.max, p.mean}) EXPECT_EQ(x, 7.5);
}

TEST(BatchPercentiles, NaNIgnored) {
  expect_figures_of_one_to_four(percentiles({kNaN, 1, 2, kNaN, 3, 4, kNaN}));
}

TEST(BatchPercentiles, EmptyHasCountZeroAndNaNFigures) {
  for (const std::vector<double>& values : {std::vector<double>{}, std::vector<double>{kNaN}}) {
    const Percentiles p = percentiles(values);
    EXPECT_EQ(p.count, 0);
    for (double x : {p.min, p.p50, p.p90, p.p99, p.max, p.mean}) EXPECT_TRUE(std::isnan(x));
  }
}

/// Six meshes: three Ok (one without distortion figures), one crash, one timeout, one bad input.
std::vector<MeshRecord> six_records() {
  std::vector<MeshRecord> r;
  r.push_back(record("a", MeshOutcome::Ok, 2.0, 1024, 1.5, 1.2));
  r.push_back(record("b", MeshOutcome::Crashed, 5.0, 4096));
  r.back().exit_code = -1;
  r.back().signal = 11;
  r.back().message = "killed by SIGSEGV";
  r.push_back(record("c", MeshOutcome::Ok, 5.0, 3072, 1.1, 1.4));
  r.push_back(record("d", MeshOutcome::TimedOut, 60.0, 10240));
  r.back().message = "timed out after 60 s";
  r.push_back(record("e", MeshOutcome::BadInput, 0.5, 512));
  r.back().exit_code = 2;
  r.back().message = "read_obj: e.obj:3: bad face";
  r.push_back(record("f", MeshOutcome::Ok, 1.0, 2048, kNaN, kNaN));
  return r;
}

TEST(BatchSummary, CountsInOutcomeOrder) {
  const BatchSummary s = summarize_batch(six_records(), 30.0);
  EXPECT_EQ(s.total, 6);
  const std::vector<std::pair<std::string, int>> expected = {{"ok", 3},
                                                             {"bad_input", 1},
                                                             {"not_converged", 0},
                                                             {"internal_error", 0},
                                                             {"out_of_memory", 0},
                                                             {"crashed", 1},
                                                             {"timed_out", 1},
                                                             {"spawn_failed", 0}};
  EXPECT_EQ(s.counts, expected);
  EXPECT_EQ(s.wall_seconds, 30.0);
}

TEST(BatchSummary, FiguresOverTheRightMeshes) {
  const BatchSummary s = summarize_batch(six_records(), 30.0);
  // Seconds of all six: sorted 0.5 1 2 5 5 60; p50 at h = 2.5 -> 3.5; mean 73.5 / 6.
  EXPECT_EQ(s.seconds.count, 6);
  EXPECT_NEAR(s.seconds.p50, 3.5, kTol);
  EXPECT_NEAR(s.seconds.mean, 73.5 / 6, kTol);
  EXPECT_EQ(s.seconds.max, 60.0);
  EXPECT_EQ(s.all_seconds, (std::vector<double>{2.0, 5.0, 5.0, 60.0, 0.5, 1.0}));
  // Memory in MiB: 0.5 1 2 3 4 10.
  EXPECT_EQ(s.peak_memory_mb.count, 6);
  EXPECT_EQ(s.peak_memory_mb.min, 0.5);
  EXPECT_EQ(s.peak_memory_mb.max, 10.0);
  EXPECT_NEAR(s.peak_memory_mb.p50, 2.5, kTol);
  // Distortion: the two Ok meshes that have it (f has NaN; failed meshes never count).
  EXPECT_EQ(s.angle_distortion.count, 2);
  EXPECT_NEAR(s.angle_distortion.mean, 1.3, kTol);
  EXPECT_EQ(s.all_angle_distortion, (std::vector<double>{1.5, 1.1}));
  EXPECT_EQ(s.area_distortion.count, 2);
  EXPECT_NEAR(s.area_distortion.p50, 1.3, kTol);
  EXPECT_EQ(s.all_area_distortion, (std::vector<double>{1.2, 1.4}));
}

TEST(BatchSummary, SlowestFirstTiesByKey) {
  const BatchSummary s = summarize_batch(six_records(), 30.0);
  const std::vector<std::pair<std::string, double>> expected = {
      {"d", 60.0}, {"b", 5.0}, {"c", 5.0}, {"a", 2.0}, {"f", 1.0}, {"e", 0.5}};
  EXPECT_EQ(s.slowest, expected);
}

TEST(BatchSummary, SlowestKeepsTen) {
  std::vector<MeshRecord> records;
  records.reserve(25);
  for (int i = 0; i < 25; ++i) {
    records.push_back(record("m" + std::to_string(100 + i), MeshOutcome::Ok, i % 5, 1024, 1.0));
  }
  const BatchSummary s = summarize_batch(records, 10.0);
  ASSERT_EQ(s.slowest.size(), 10u);
  // Five meshes take 4 s (m104, m109, ...), five 3 s: by key within each.
  EXPECT_EQ(s.slowest[0], (std::pair<std::string, double>{"m104", 4.0}));
  EXPECT_EQ(s.slowest[4], (std::pair<std::string, double>{"m124", 4.0}));
  EXPECT_EQ(s.slowest[5], (std::pair<std::string, double>{"m103", 3.0}));
  EXPECT_EQ(s.slowest[9], (std::pair<std::string, double>{"m123", 3.0}));
}

TEST(BatchSummary, FailedInRecordOrder) {
  const BatchSummary s = summarize_batch(six_records(), 30.0);
  ASSERT_EQ(s.failed.size(), 3u);
  EXPECT_EQ(s.failed[0].key, "b");
  EXPECT_EQ(s.failed[0].signal, 11);
  EXPECT_EQ(s.failed[1].key, "d");
  EXPECT_EQ(s.failed[2].key, "e");
  EXPECT_EQ(s.failed[2].message, "read_obj: e.obj:3: bad face");
}

TEST(BatchSummary, EmptyBatch) {
  const BatchSummary s = summarize_batch({}, 0.0);
  EXPECT_EQ(s.total, 0);
  ASSERT_EQ(s.counts.size(), 8u);
  for (const auto& [name, count] : s.counts) EXPECT_EQ(count, 0) << name;
  EXPECT_EQ(s.seconds.count, 0);
  EXPECT_TRUE(s.slowest.empty());
  EXPECT_TRUE(s.failed.empty());
  const nlohmann::json j = nlohmann::json::parse(summary_to_json(s));
  EXPECT_EQ(j["meshes_per_minute"], 0.0);  // no division by a zero wall time
  EXPECT_TRUE(j["seconds"]["p50"].is_null());
}

TEST(BatchSummary, JsonRoundTrip) {
  const std::string text = summary_to_json(summarize_batch(six_records(), 30.0));
  EXPECT_NE(text.find("\n \""), std::string::npos);  // pretty-printed, indent 1
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_EQ(j["total"], 6);
  EXPECT_EQ(j["counts"].size(), 8u);
  EXPECT_EQ(j["counts"]["ok"], 3);
  EXPECT_EQ(j["counts"]["crashed"], 1);
  EXPECT_EQ(j["counts"]["spawn_failed"], 0);
  for (const char* figure : {"seconds", "peak_memory_mb", "area_distortion", "angle_distortion"}) {
    for (const char* field : {"count", "min", "p50", "p90", "p99", "max", "mean"}) {
      EXPECT_TRUE(j[figure].contains(field)) << figure << "." << field;
    }
  }
  EXPECT_EQ(j["seconds"]["count"], 6);
  EXPECT_NEAR(j["seconds"]["p50"].get<double>(), 3.5, kTol);
  EXPECT_NEAR(j["angle_distortion"]["mean"].get<double>(), 1.3, kTol);
  ASSERT_EQ(j["slowest"].size(), 6u);
  EXPECT_EQ(j["slowest"][0]["key"], "d");
  EXPECT_EQ(j["slowest"][0]["seconds"], 60.0);
  ASSERT_EQ(j["failed"].size(), 3u);
  EXPECT_EQ(j["failed"][0]["key"], "b");
  EXPECT_EQ(j["failed"][0]["outcome"], "crashed");
  EXPECT_EQ(j["failed"][0]["exit_code"], -1);
  EXPECT_EQ(j["failed"][0]["signal"], 11);
  EXPECT_EQ(j["failed"][0]["message"], "killed by SIGSEGV");
  EXPECT_EQ(j["failed"][0]["seconds"], 5.0);
  EXPECT_EQ(j["failed"][2]["outcome"], "bad_input");
  EXPECT_EQ(j["failed"][2]["exit_code"], 2);
  EXPECT_EQ(j["wall_seconds"], 30.0);
  EXPECT_NEAR(j["meshes_per_minute"].get<double>(), 12.0, kTol);  // 6 meshes in half a minute
}

TEST(BatchSummary, JsonNullForNaN) {
  // Only failures: no distortion figure at all; one record without a time.
  std::vector<MeshRecord> records = {record("x", MeshOutcome::OutOfMemory, 3.0),
                                     record("y", MeshOutcome::SpawnFailed, kNaN, 0)};
  const nlohmann::json j = nlohmann::json::parse(summary_to_json(summarize_batch(records, 1.0)));
  EXPECT_EQ(j["angle_distortion"]["count"], 0);
  for (const char* field : {"min", "p50", "p90", "p99", "max", "mean"}) {
    EXPECT_TRUE(j["angle_distortion"][field].is_null()) << field;
    EXPECT_TRUE(j["area_distortion"][field].is_null()) << field;
  }
  EXPECT_EQ(j["seconds"]["count"], 1);
  EXPECT_EQ(j["seconds"]["max"], 3.0);
  ASSERT_EQ(j["slowest"].size(), 1u);  // the mesh without a time is not among the slowest
  EXPECT_TRUE(j["failed"][1]["seconds"].is_null());
  EXPECT_EQ(j["failed"][1]["outcome"], "spawn_failed");
}

}  // namespace
}  // namespace ricci
