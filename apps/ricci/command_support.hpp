#pragma once
/// \file
/// What several subcommands share (command_support.cpp).

#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "input_options.hpp"
#include "progress.hpp"
#include "ricci/errors.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci::cli {

/// Refuses to write a result over one of the inputs.
void check_output_is_not_input(const std::string& output, const std::vector<std::string>& inputs);
/// Topological counts are -1 where defects leave them undefined.
std::string or_na(int value);
/// The reader's warnings on stderr.
void print_warnings(const ReadResult& read);
/// The "repair" object of the JSON reports: what changed, and the mode that repaired.
nlohmann::json repair_json(const ReadResult& read, const InputArgs& input);
/// File vertex index -> mesh vertex index (-1 for vertices the reader dropped).
std::vector<int> inverse_map(const std::vector<int>& vertex_map);
/// --cones as a list 'V:K,...' or a file of 'vertex curvature' lines; empty: none.
std::vector<Cone> read_cones(const std::string& spec);
/// Adds input, output and repair to a report and writes it where --report asks; when the flow
/// did not converge says why on stderr. Returns whether it converged.
bool finish_report(const std::string& mesh, const std::string& output,
                   const std::string& report_path, const ReadResult& read, const InputArgs& input,
                   nlohmann::json& report, bool converged, const std::string& why);
/// --cones of param and spline: auto, N, none, one, or 'V:K,...' / a file (file vertex indices).
void apply_cones_option(const std::string& c, const std::string& mesh, const ReadResult& read,
                        ParamOptions& options);

/// Runs a pipeline with the progress display the flags ask for (into `flow.progress`); an
/// InvalidInput gets the mesh's name in front.
template <class Run>
auto run_with_progress(const std::string& mesh, bool progress_flag, bool json, const char* what,
                       FlowOptions& flow, Run run) {
  const ProgressStyle progress = choose_progress_style(progress_flag, json);
  flow.progress = make_progress(progress, what, flow.tolerance);
  try {
    auto result = run();
    finish_progress(progress);
    return result;
  } catch (const TopologyError& e) {
    finish_progress(progress);
    throw TopologyError(mesh + ": " + e.what());
  } catch (const InvalidInput& e) {
    finish_progress(progress);
    throw InvalidInput(mesh + ": " + e.what(), e.fixes());  // the fixes stay
  }
}

}  // namespace ricci::cli
