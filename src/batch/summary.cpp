#include "ricci/batch/summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>

#include "batch/detail/json_numbers.hpp"

namespace ricci {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::size_t kSlowestShown = 10;

/// Every outcome, in declaration order (the order of BatchSummary::counts).
constexpr MeshOutcome kOutcomes[] = {
    MeshOutcome::Ok,           MeshOutcome::BadInput,
    MeshOutcome::NotConverged, MeshOutcome::InternalError,
    MeshOutcome::OutOfMemory,  MeshOutcome::Crashed,
    MeshOutcome::TimedOut,     MeshOutcome::SpawnFailed,
};

/// The p-quantile (p in [0, 1]) of sorted values by linear interpolation between the order
/// statistics at ranks floor(h) and ceil(h), h = (n - 1) p: numpy's default method ("linear",
/// Hyndman and Fan's type 7). \pre sorted is sorted and not empty
double quantile(const std::vector<double>& sorted, double p) {
  const double h = (static_cast<double>(sorted.size()) - 1) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  // Equal neighbours (infinite ones included) give that value, not inf - inf.
  if (sorted[hi] == sorted[lo]) return sorted[lo];
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

using batch_detail::number_or_null;

nlohmann::json to_json(const Percentiles& p) {
  return {{"count", p.count},
          {"min", number_or_null(p.min)},
          {"p50", number_or_null(p.p50)},
          {"p90", number_or_null(p.p90)},
          {"p99", number_or_null(p.p99)},
          {"max", number_or_null(p.max)},
          {"mean", number_or_null(p.mean)}};
}

}  // namespace

/// NaN values are left out; with none left, count is 0 and every figure NaN (null in the JSON),
/// so that an empty figure is never read as a zero.
Percentiles percentiles(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double x) { return std::isnan(x); }),
               values.end());
  Percentiles p;
  p.count = static_cast<int>(values.size());
  if (values.empty()) {
    p.min = p.p50 = p.p90 = p.p99 = p.max = p.mean = kNaN;
    return p;
  }
  std::sort(values.begin(), values.end());
  p.min = values.front();
  p.max = values.back();
  p.p50 = quantile(values, 0.50);
  p.p90 = quantile(values, 0.90);
  p.p99 = quantile(values, 0.99);
  p.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  return p;
}

BatchSummary summarize_batch(const std::vector<MeshRecord>& records, double wall_seconds) {
  BatchSummary s;
  s.total = static_cast<int>(records.size());
  s.wall_seconds = wall_seconds;

  for (MeshOutcome outcome : kOutcomes) {
    const auto n = std::count_if(records.begin(), records.end(),
                                 [&](const MeshRecord& r) { return r.outcome == outcome; });
    s.counts.emplace_back(mesh_outcome_name(outcome), static_cast<int>(n));
  }

  std::vector<double> memory_mb;
  s.all_seconds.reserve(records.size());
  memory_mb.reserve(records.size());
  for (const MeshRecord& r : records) {
    s.all_seconds.push_back(r.seconds);
    memory_mb.push_back(static_cast<double>(r.peak_memory_kb) / 1024.0);
    if (r.outcome == MeshOutcome::Ok) {
      if (std::isfinite(r.angle_distortion)) s.all_angle_distortion.push_back(r.angle_distortion);
      if (std::isfinite(r.area_distortion)) s.all_area_distortion.push_back(r.area_distortion);
    } else {
      s.failed.push_back(r);
    }
  }
  s.seconds = percentiles(s.all_seconds);
  s.peak_memory_mb = percentiles(std::move(memory_mb));
  s.angle_distortion = percentiles(s.all_angle_distortion);
  s.area_distortion = percentiles(s.all_area_distortion);

  // Slowest first, ties by key; a record without a time (NaN) is never among the slowest.
  std::vector<const MeshRecord*> timed;
  for (const MeshRecord& r : records) {
    if (!std::isnan(r.seconds)) timed.push_back(&r);
  }
  const std::size_t shown = std::min(kSlowestShown, timed.size());
  std::partial_sort(timed.begin(), timed.begin() + static_cast<std::ptrdiff_t>(shown), timed.end(),
                    [](const MeshRecord* a, const MeshRecord* b) {
                      if (a->seconds != b->seconds) return a->seconds > b->seconds;
                      return a->key < b->key;
                    });
  for (std::size_t i = 0; i < shown; ++i) s.slowest.emplace_back(timed[i]->key, timed[i]->seconds);
  return s;
}

std::string summary_to_json(const BatchSummary& summary) {
  nlohmann::json j;
  j["total"] = summary.total;
  nlohmann::json counts = nlohmann::json::object();
  for (const auto& [name, count] : summary.counts) counts[name] = count;
  j["counts"] = counts;
  j["seconds"] = to_json(summary.seconds);
  j["peak_memory_mb"] = to_json(summary.peak_memory_mb);
  j["area_distortion"] = to_json(summary.area_distortion);
  j["angle_distortion"] = to_json(summary.angle_distortion);
  nlohmann::json slowest = nlohmann::json::array();
  for (const auto& [key, seconds] : summary.slowest) {
    slowest.push_back({{"key", key}, {"seconds", number_or_null(seconds)}});
  }
  j["slowest"] = slowest;
  nlohmann::json failed = nlohmann::json::array();
  for (const MeshRecord& r : summary.failed) {
    failed.push_back({{"key", r.key},
                      {"outcome", mesh_outcome_name(r.outcome)},
                      {"exit_code", r.exit_code},
                      {"signal", r.signal},
                      {"message", r.message},
                      {"seconds", number_or_null(r.seconds)}});
  }
  j["failed"] = failed;
  j["wall_seconds"] = number_or_null(summary.wall_seconds);
  // Meshes this run ran over its minutes (a resumed run's skipped meshes do not count); 0 when
  // the run took no measurable time.
  const int ran = summary.ran >= 0 ? summary.ran : summary.total;
  j["ran"] = ran;
  const double per_minute = summary.wall_seconds > 0 && std::isfinite(summary.wall_seconds)
                                ? ran / (summary.wall_seconds / 60.0)
                                : 0.0;
  j["meshes_per_minute"] = per_minute;
  // Messages are child output: replace invalid UTF-8 instead of throwing.
  return j.dump(1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace ricci
