#pragma once
/// \file
/// The end of a batch in figures: counts by outcome, percentiles of seconds and distortion, the
/// slowest and the failed meshes (OUTDIR/summary.json; the picture is render/batch_summary).

#include <string>
#include <utility>
#include <vector>

#include "ricci/batch/results_log.hpp"

namespace ricci {

/// Percentiles of one figure over the meshes that have it.
struct Percentiles {
  int count = 0;  ///< meshes with the figure
  double min = 0, p50 = 0, p90 = 0, p99 = 0, max = 0, mean = 0;
};

/// Summary of a batch's records.
struct BatchSummary {
  int total = 0;
  /// (outcome name, count) for every outcome, in MeshOutcome order.
  std::vector<std::pair<std::string, int>> counts;
  Percentiles seconds;           ///< per mesh, every outcome
  Percentiles peak_memory_mb;    ///< per mesh, every outcome
  Percentiles area_distortion;   ///< Ok meshes
  Percentiles angle_distortion;  ///< Ok meshes
  /// The slowest meshes (up to 10), slowest first: (key, seconds).
  std::vector<std::pair<std::string, double>> slowest;
  /// Every mesh not Ok, in record order.
  std::vector<MeshRecord> failed;
  /// Per-mesh figures for histograms: seconds of every mesh, angle and area distortion of the Ok
  /// ones.
  std::vector<double> all_seconds, all_angle_distortion, all_area_distortion;
  double wall_seconds = 0;  ///< the run that wrote it
  /// Meshes that run ran (the others' records came from an earlier run); -1: unknown, all.
  int ran = -1;
};

/// Percentiles by linear interpolation between order statistics (p50 of {1, 2, 3, 4} is 2.5).
Percentiles percentiles(std::vector<double> values);

/// The summary of a batch's records. \param wall_seconds the run's duration
BatchSummary summarize_batch(const std::vector<MeshRecord>& records, double wall_seconds);

/// The summary as JSON (pretty-printed).
std::string summary_to_json(const BatchSummary& summary);

}  // namespace ricci
