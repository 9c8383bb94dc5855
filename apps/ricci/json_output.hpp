#pragma once
/// \file
/// JSON views of ricci's result structs, for `--json` summaries and result files.

#include <nlohmann/json.hpp>

#include "ricci/flow/mesh_flow.hpp"
#include "ricci/hyperbolic/hyperbolic_param.hpp"
#include "ricci/mesh/info.hpp"
#include "ricci/mesh/repair.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/param/refinement/common_refinement.hpp"
#include "ricci/sphere/sphere.hpp"
#include "ricci/spline/manifold_spline.hpp"

namespace ricci::cli {

/// Summary of a mesh (ricci info).
nlohmann::json to_json(const MeshInfo& info);

/// What --repair changed: counts with examples of every kind of change, and the messages (the
/// same keys as the dictionary the Python module returns).
nlohmann::json to_json(const RepairReport& report);

/// Summary of a flow: status, errors, timings, per-component history; no per-vertex arrays.
nlohmann::json flow_summary(const MeshFlowResult& result, const MeshFlowOptions& options);

/// Per-vertex and per-edge arrays of a flow; vertex rows in mesh order, with file_index giving
/// each row's 0-based vertex index in the input file.
nlohmann::json flow_arrays(const MeshFlowResult& result, const std::vector<int>& file_index);

/// Report of a parameterization: cones, modifications, cut, layout, atlas, distortion and the
/// flow summary.
nlohmann::json param_report(const MeshParamResult& result, const ParamOptions& options);

/// The figures of a common refinement (`param --faces refinement`): sizes beside the input's,
/// flips undone, crossing points, exactness checks, timing.
nlohmann::json refinement_report(const CommonRefinement& refinement, const Parameterization& param);

/// The report of `param --geometry hyperbolic`: flow, cut, disk layout, the deck transformation
/// of every segment, the words around the nodes, the Fuchsian group and the distortion.
nlohmann::json hyperbolic_param_report(const HyperbolicParamResult& result,
                                       const HyperbolicParamOptions& options);

/// Report of a spherical conformal map: invariants, Moebius normalisation, distortion, timings
/// and the disk's flow summary; pole in mesh indices (the caller adds file indices).
/// The diagnostics of fit_manifold_spline: errors, C1 jumps, fit, timings, the parameterization.
nlohmann::json spline_report(const SplineResult& result, const SplineOptions& options);

nlohmann::json sphere_report(const SphereResult& result, const SphereOptions& options);

}  // namespace ricci::cli
