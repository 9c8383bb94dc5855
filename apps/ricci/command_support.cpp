// What several subcommands share: reading cones, refusing to overwrite an input, warnings,
// the reports' repair object, and --cones of param and spline.
#include "command_support.hpp"

#include <filesystem>
#include <iostream>
#include <optional>

#include "json_output.hpp"
#include "ricci/errors.hpp"

namespace ricci::cli {

void check_output_is_not_input(const std::string& output, const std::vector<std::string>& inputs) {
  std::error_code ec;
  if (!std::filesystem::exists(output, ec)) return;
  for (const std::string& input : inputs) {
    if (!input.empty() && std::filesystem::exists(input, ec) &&
        std::filesystem::equivalent(output, input, ec)) {
      throw InvalidInput(output + ": the output would overwrite the input " + input +
                         "; choose another -o");
    }
  }
}

std::string or_na(int value) {
  return value >= 0 ? std::to_string(value) : "n/a (not a manifold surface)";
}

void print_warnings(const ReadResult& read) {
  for (const std::string& w : read.warnings) std::cerr << "warning: " << w << "\n";
}

nlohmann::json repair_json(const ReadResult& read, const InputArgs& input) {
  nlohmann::json j = to_json(read.repair);
  j["mode"] = repair_mode_name(repair_mode(input));
  return j;
}

std::vector<int> inverse_map(const std::vector<int>& vertex_map) {
  int top = -1;
  for (int v : vertex_map) top = std::max(top, v);
  std::vector<int> inverse(top + 1, -1);
  for (std::size_t i = 0; i < vertex_map.size(); ++i) inverse[vertex_map[i]] = static_cast<int>(i);
  return inverse;
}

std::vector<Cone> read_cones(const std::string& spec) {
  if (spec.empty()) return {};
  if (std::filesystem::is_regular_file(spec)) return read_cone_file(spec);
  if (spec.find(':') == std::string::npos) {
    throw InvalidInput(
        "--cones: '" + spec +
        "' is neither a file nor a list VERTEX:CURVATURE,... (e.g. 12:pi/2,40:pi/2)");
  }
  return parse_cone_list(spec);
}

bool finish_report(const std::string& mesh, const std::string& output,
                   const std::string& report_path, const ReadResult& read, const InputArgs& input,
                   nlohmann::json& report, bool converged, const std::string& why) {
  report["input"] = mesh;
  report["output"] = output;
  if (read.repaired) report["repair"] = repair_json(read, input);
  if (!report_path.empty()) {
    write_file_atomically(report_path, [&](std::ostream& out) { out << report.dump(1) << "\n"; });
  }
  if (!converged) std::cerr << "error: " << mesh << ": " << why << "\n";
  return converged;
}

void apply_cones_option(const std::string& c, const std::string& mesh, const ReadResult& read,
                        ParamOptions& options) {
  // The modes by name, from their one table (param/parameterize.hpp); "user" is not a name
  // here: the user's cones are given as a list or a file.
  const std::optional<ConeMode> named = find_enum<ConeMode>(c);
  if (named && *named != ConeMode::User) {
    options.cone_mode = *named;
  } else if (!c.empty() && c.find_first_not_of("0123456789") == std::string::npos) {
    options.cone_mode = ConeMode::Auto;
    options.auto_cones.count = std::stoi(c);
    if (options.auto_cones.count < 1) throw InvalidInput("--cones: a cone count must be >= 1");
  } else {
    options.cone_mode = ConeMode::User;
    const std::vector<int> to_mesh = inverse_map(read.vertex_map);
    for (Cone cone : read_cones(c)) {
      if (cone.vertex >= static_cast<int>(to_mesh.size()) || to_mesh[cone.vertex] < 0) {
        throw InvalidInput("--cones: vertex " + std::to_string(cone.vertex) +
                           " is not a vertex of " + mesh + " used by any face");
      }
      cone.vertex = to_mesh[cone.vertex];
      options.cones.push_back(cone);
    }
  }
}

}  // namespace ricci::cli
