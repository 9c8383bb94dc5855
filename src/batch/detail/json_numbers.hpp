#pragma once
// Private to the batch module: how the results log and the summary write a figure to JSON, in
// one place so that the two files always agree.

#include <cmath>

#include <nlohmann/json.hpp>

namespace ricci::batch_detail {

/// JSON number, or null when not finite (JSON has no NaN).
inline nlohmann::json number_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

}  // namespace ricci::batch_detail
