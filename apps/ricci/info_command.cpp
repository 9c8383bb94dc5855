// `ricci info`: counts, topology and defects of a mesh file.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "command_support.hpp"
#include "commands.hpp"
#include "json_output.hpp"
#include "ricci/mesh/info.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci::cli {
namespace {

struct InfoArgs {
  std::string mesh;
  bool json = false;
  InputArgs input;  ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
};

int run_info(const InfoArgs& args) {
  // info reports every defect instead of stopping at the first; in the auto mode it describes
  // the file as it is, and what the other commands' repair would make of it.
  const RepairMode mode = repair_mode(args.input);
  ReadResult read;
  if (mode == RepairMode::Auto) {
    ReadOptions as_it_is;
    as_it_is.validate = false;
    read = read_mesh(args.mesh, as_it_is);
  } else {
    read = read_input(args.mesh, args.input, false);
  }
  const MeshInfo info = mesh_info(read.mesh);
  // The auto mode's preview: what repair changes, and the defects it leaves.
  std::optional<ReadResult> preview;
  std::optional<ValidationReport> after;
  if (mode == RepairMode::Auto && !info.validation.ok()) {
    ReadOptions repairing;
    repairing.validate = false;
    repairing.repair = true;
    preview = read_mesh(args.mesh, repairing);
    after = find_defects(preview->mesh);
  }
  if (args.json) {
    nlohmann::json j = to_json(info);
    j["file"] = args.mesh;
    j["warnings"] = read.warnings;
    j["dropped_vertices"] = read.dropped_vertices.size();
    if (read.repaired) j["repair"] = repair_json(read, args.input);
    if (mode == RepairMode::Auto) {
      nlohmann::json would = {{"would_repair", preview.has_value()}};
      if (preview) {
        would["valid_after"] = after->ok();
        would["repair"] = to_json(preview->repair);
        nlohmann::json left = nlohmann::json::object();
        for (const auto& [kind, count] : after->counts) {
          if (kind != DefectKind::UnreferencedVertex) left[defect_name(kind)] = count;
        }
        would["defects_after"] = left;
      }
      j["auto_repair"] = would;
    }
    std::cout << j.dump(2) << "\n";
  } else {
    print_warnings(read);
    std::cout << args.mesh << "\n"
              << "  vertices             " << info.vertices;
    if (!read.dropped_vertices.empty()) {
      std::cout << " (" << read.dropped_vertices.size() << " unreferenced dropped)";
    }
    std::cout << "\n  edges                " << or_na(info.edges) << "\n"
              << "  faces                " << info.faces << "\n"
              << "  components           " << or_na(info.components) << "\n"
              << "  boundary loops       " << or_na(info.boundary_loops) << "\n"
              << "  Euler characteristic " << or_na(info.euler_characteristic) << "\n"
              << "  genus                " << or_na(info.genus) << "\n"
              << "  smallest angle       " << std::setprecision(4) << info.min_angle_degrees
              << " deg\n"
              << "  largest angle        " << info.max_angle_degrees << " deg\n";
    if (info.component_info.size() > 1) {
      for (std::size_t c = 0; c < info.component_info.size(); ++c) {
        const ComponentInfo& ci = info.component_info[c];
        std::cout << "  component " << c << ": V " << ci.vertices << ", F " << ci.faces
                  << ", boundary loops " << ci.boundary_loops << ", chi " << ci.euler_characteristic
                  << ", genus " << ci.genus << "\n";
      }
    }
    if (info.validation.defects.empty()) {
      std::cout << "  defects              none\n";
    } else {
      std::cout << "  defects:\n";
      for (const auto& [kind, count] : info.validation.counts) {
        std::cout << "    " << defect_name(kind) << ": " << count << "\n";
      }
      for (const Defect& d : info.validation.defects) std::cout << "    - " << d.message << "\n";
    }
    if (preview && after->ok()) {
      std::cout << "  repair:              the other commands repair this mesh (their default "
                   "--repair=auto; --strict refuses it), and it is valid afterwards ("
                << preview->mesh.num_vertices() << " vertices, " << preview->mesh.num_faces()
                << " faces):\n";
    } else if (preview) {
      std::cout << "  repair:              repair leaves defects, so the other commands refuse "
                   "this mesh:\n";
    }
    if (preview) {
      for (const std::string& m : preview->repair.messages) std::cout << "    - " << m << "\n";
      for (const Defect& d : after->defects) {
        if (d.kind == DefectKind::UnreferencedVertex) continue;
        std::cout << "    - after repair: " << d.message << "\n";
        break;
      }
    }
  }
  return info.validation.ok() ? kOk : kBadInput;
}

}  // namespace

Subcommand add_info_command(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "info",
      "Print counts, topology (components, boundary loops, Euler characteristic, genus), "
      "the smallest angle and every defect of a mesh file as it is, and what the repair of the "
      "other commands (their default --repair=auto) would change; exit 2 when the file has "
      "defects, even ones repair fixes. --repair describes the repaired mesh instead.");
  cmd->add_option("MESH", args->mesh, "mesh file (.obj .off .ply .stl)")->required();
  cmd->add_flag("--json", args->json, "print the summary as JSON");
  add_input_options(cmd, args->input, true);
  return {cmd, [args] { return run_info(*args); }};
}

}  // namespace ricci::cli
