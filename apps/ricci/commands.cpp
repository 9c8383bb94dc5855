#include "commands.hpp"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>

#include "fixes.hpp"
#include "json_output.hpp"
#include "progress.hpp"
#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/hard_cases.hpp"
#include "ricci/mesh/info.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/param/refinement/common_refinement.hpp"
#include "ricci/param/output_mesh.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/sphere/sphere.hpp"
#include "ricci/spline/manifold_spline.hpp"
#ifdef RICCI_HAVE_RENDER
#include "render_command.hpp"
#include "ricci/render/textured_files.hpp"
#endif

namespace ricci::cli {
namespace {

/// Refuses to write a result over one of the inputs.
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

/// Topological counts are -1 where defects leave them undefined.
std::string or_na(int value) {
  return value >= 0 ? std::to_string(value) : "n/a (not a manifold surface)";
}

void print_warnings(const ReadResult& read) {
  for (const std::string& w : read.warnings) std::cerr << "warning: " << w << "\n";
}

/// The "repair" object of the JSON reports: what changed, and the mode that repaired.
nlohmann::json repair_json(const ReadResult& read, const InputArgs& input) {
  nlohmann::json j = to_json(read.repair);
  j["mode"] = repair_mode_name(repair_mode(input));
  return j;
}

/// File vertex index -> mesh vertex index (-1 for vertices the reader dropped).
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

/// Adds input, output and repair to a report and writes it where --report asks; when the flow
/// did not converge says why on stderr. Returns whether it converged.
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

/// --cones of param and spline: auto, N, none, one, or 'V:K,...' / a file (file vertex indices).
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

}  // namespace

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

int run_flow(const FlowArgs& args) {
  MeshFlowOptions options;
  options.structure.scheme = parse_scheme(args.scheme);
  options.structure.geometry = parse_geometry(args.geometry);
  const bool hyperbolic = options.structure.geometry == Geometry::Hyperbolic;
  options.structure.packing_init = parse_enum<PackingInit>(args.init, "--init");
  options.flow.solver = parse_flow_solver(args.solver);
  options.flow.flips = parse_edge_flips(args.flips);
  options.flow.tolerance = args.tolerance;
  options.flow.max_iterations = args.max_iterations;
  options.flow.gradient_step = args.step;
  if (!args.output.empty()) {
    check_output_is_not_input(args.output, {args.mesh, args.cones, args.target});
  }

  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  const Mesh& mesh = read.mesh;

  TargetSpec& spec = options.target;
  spec.boundary = !args.boundary.empty() ? parse_boundary_mode(args.boundary)
                  : hyperbolic           ? BoundaryMode::Geodesic
                                         : BoundaryMode::Free;
  if (args.target == "natural") {
    spec.kind = TargetKind::Natural;
  } else if (args.target == "flat") {
    spec.kind = TargetKind::Flat;
  } else if (args.target == "free" || args.target == "disk" || args.target == "disk-length" ||
             args.target == "geodesic") {
    spec.kind = TargetKind::Flat;
    spec.boundary = parse_boundary_mode(args.target);
  } else if (args.target == "uniform") {
    spec.kind = TargetKind::Uniform;
  } else if (std::filesystem::is_regular_file(args.target)) {
    // Values are listed per vertex of the file; drop the rows of unreferenced vertices.
    const Eigen::VectorXd file_values = read_values_file(args.target);
    const auto file_vertices = static_cast<Eigen::Index>(read.file_vertices);
    const bool per_file_vertex = file_values.size() == file_vertices;
    if (!per_file_vertex && file_values.size() != mesh.num_vertices()) {
      throw InvalidInput(args.target + ": " + std::to_string(file_values.size()) +
                         " curvature values for the " + std::to_string(file_vertices) +
                         " vertices of " + args.mesh);
    }
    spec.kind = TargetKind::Values;
    spec.values.resize(mesh.num_vertices());
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      spec.values[v] = file_values[per_file_vertex ? read.vertex_map[v] : v];
    }
  } else {
    throw InvalidInput("--target: '" + args.target +
                       "' is neither natural, flat, free, disk, disk-length, geodesic, uniform "
                       "nor a file of per-vertex curvatures");
  }
  // Cone vertices are numbered as in the file (0-based).
  const std::vector<int> to_mesh = inverse_map(read.vertex_map);
  for (Cone cone : read_cones(args.cones)) {
    if (cone.vertex >= static_cast<int>(to_mesh.size()) || to_mesh[cone.vertex] < 0) {
      throw InvalidInput("--cones: vertex " + std::to_string(cone.vertex) + " is not a vertex of " +
                         args.mesh + " used by any face");
    }
    cone.vertex = to_mesh[cone.vertex];
    spec.cones.push_back(cone);
  }
  if (!spec.cones.empty() && spec.kind != TargetKind::Flat && spec.kind != TargetKind::Natural) {
    throw InvalidInput(
        "--cones needs a flat target (--target flat, free, disk, disk-length or geodesic)");
  }

  options.vertex_labels = read.vertex_map;  // messages number vertices as the file does
  const MeshFlowResult result = [&] {
    try {
      return run_with_progress(args.mesh, args.progress, args.json, "flow", options.flow,
                               [&] { return flow_mesh(mesh, options); });
    } catch (const InvalidInput& e) {
      // Gauss-Bonnet's refusal names the natural and uniform targets, but with --cones the
      // natural target is flat with those cones and the uniform one takes none: dropping the
      // cones is the fix where the target is the natural one, and no single option otherwise.
      const bool names_target =
          std::any_of(e.fixes().begin(), e.fixes().end(),
                      [](const OptionFix& f) { return f.option == "target"; });
      if (spec.cones.empty() || !names_target) throw;
      throw InvalidInput(e.what(), args.target == "natural" ? fixes_of({{"cones", ""}})
                                                            : std::vector<OptionFix>{});
    }
  }();

  nlohmann::json summary = flow_summary(result, options);
  summary["input"] = args.mesh;
  summary["warnings"] = read.warnings;
  if (read.repaired) summary["repair"] = repair_json(read, args.input);
  if (!args.output.empty()) {
    nlohmann::json full = summary;
    full["vertex_data"] = flow_arrays(result, read.vertex_map);
    write_file_atomically(args.output, [&](std::ostream& out) { out << full.dump(1) << "\n"; });
  }
  if (args.json) {
    std::cout << summary.dump(2) << "\n";
  } else {
    std::cout << args.mesh << ": " << (result.converged ? "converged" : "NOT converged")
              << ", max |K-bar - K| = " << std::scientific << std::setprecision(3)
              << result.max_error << std::defaultfloat << " ("
              << scheme_name(options.structure.scheme) << ", " << (hyperbolic ? "hyperbolic, " : "")
              << flow_solver_name(options.flow.solver) << ", " << result.target.description
              << ")\n";
    if (scheme_traits(options.structure.scheme).circle_packing) {
      std::cout << "  initial packing fits the input lengths with RMS relative error "
                << std::setprecision(3) << result.structure.fit_rms_relative_error << " (max "
                << result.structure.fit_max_relative_error << ")" << std::defaultfloat << "\n";
    }
    if (hyperbolic) {
      std::cout << "  input lengths scaled by " << std::setprecision(6)
                << result.structure.structure.length_scale << std::defaultfloat
                << " and read as hyperbolic lengths\n";
    }
    for (std::size_t c = 0; c < result.components.size(); ++c) {
      const ComponentFlow& comp = result.components[c];
      if (hyperbolic) {
        // Gauss-Bonnet in curvature -1: area = sum K - 2 pi chi.
        std::cout << "  component " << c << ": hyperbolic area " << std::setprecision(12)
                  << comp.flow.total_area << " = sum K - 2 pi chi up to " << std::setprecision(2)
                  << comp.flow.gauss_bonnet_relative_error << " (relative)" << std::defaultfloat
                  << "\n";
      }
      std::cout << "  component " << c << " (" << comp.vertices.size() << " vertices, genus "
                << comp.genus << ", " << comp.boundary_loops
                << " boundary loops): " << comp.flow.iterations << " iterations, "
                << (comp.flow.intrinsic.flips() > 0
                        ? std::to_string(comp.flow.intrinsic.flips()) + " edges flipped, "
                        : "")
                << std::fixed << std::setprecision(3) << comp.flow.timings.total
                << " s: " << cli::message_with_fixes(comp.flow.message, comp.flow.fixes)
                << std::defaultfloat << "\n";
    }
    if (!args.output.empty()) std::cout << "  wrote " << args.output << "\n";
  }
  return result.converged ? kOk : kNotConverged;
}

namespace {

/// `param --geometry hyperbolic`: the uniformization metric laid out in the Poincare disk.
/// The files `param --faces refinement` writes beside -o (docs/parameterization.md).
struct RefinementFiles {
  std::string linear, vertex_map, matrix;
};

RefinementFiles refinement_files(const std::string& output) {
  const std::filesystem::path p(output);
  const std::string stem = (p.parent_path() / p.stem()).string();
  return {stem + ".linear.obj", stem + ".vertex_map.txt", stem + ".spmat"};
}

/// Per vertex of the parameterized mesh, the input file's vertices (0-based) it is made of: its
/// own, or for a vertex added by an edge split the halves of its parents'.
std::vector<std::vector<std::pair<int, double>>> file_columns(const ParamResult& r,
                                                              const ReadResult& read) {
  const int n = r.mesh.num_vertices();
  const int first_added = n - static_cast<int>(r.added_vertex_parents.size());
  std::vector<std::vector<std::pair<int, double>>> columns(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) {
    if (r.vertex_origin[v] >= 0) {
      columns[v] = {{read.vertex_map[r.vertex_origin[v]], 1.0}};
      continue;
    }
    // Split edges join earlier vertices.
    for (int parent : r.added_vertex_parents[v - first_added]) {
      for (const auto& [c, w] : columns[parent]) {
        auto it = std::find_if(columns[v].begin(), columns[v].end(),
                               [c = c](const auto& e) { return e.first == c; });
        if (it == columns[v].end()) {
          columns[v].push_back({c, 0.5 * w});
        } else {
          it->second += 0.5 * w;
        }
      }
    }
  }
  return columns;
}

/// "obj" or "glb": --format, else the output's extension (.glb: glb).
std::string output_format(const ParamArgs& args) {
  if (!args.format.empty()) return args.format;
  std::string extension = std::filesystem::path(args.output).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".glb" ? "glb" : "obj";
}

/// The checks of --texture and --format before any work: the image exists, glb is available.
void check_texture_options(const ParamArgs& args) {
  const std::string format = output_format(args);
  if (args.texture != "checker" && args.texture != "none") {
    check_output_is_not_input(args.output, {args.texture});
    if (!std::filesystem::is_regular_file(args.texture)) {
      throw InvalidInput(
          "--texture: " + args.texture + " is no image file (give a PNG or JPEG, checker, or none)",
          fixes_of({{"texture", "checker"}}));
    }
  }
  if (format == "obj" && args.texture != "none") {
    std::filesystem::path stem(args.output);
    stem.replace_extension();
    check_output_is_not_input(stem.string() + ".mtl", {args.mesh, args.cones});
    if (args.texture == "checker") {
      check_output_is_not_input(stem.string() + ".png", {args.mesh, args.cones});
    }
  }
  if (format == "glb") {
#ifdef RICCI_HAVE_RENDER
    if (!glb_supported()) {
      throw InvalidInput(
          "--format glb: this ricci was built without tinygltf (install libtinygltf-dev and "
          "rebuild)",
          fixes_of({{"format", "obj"}}));
    }
#else
    throw InvalidInput("--format glb: this ricci was built without its picture library",
                       fixes_of({{"format", "obj"}}));
#endif
    if (args.faces == "refinement") {
      throw InvalidInput(
          "--format glb: glTF interpolates texture coordinates linearly, and the refinement's "
          "are projective (vt u v w); write OBJ (STEM.linear.obj beside it has linear ones)",
          fixes_of({{"format", "obj"}}));
    }
  }
}

/// The parameterization's file: OBJ with its material (STEM.mtl and the checkerboard STEM.png,
/// or --texture's image) unless --texture none, or glTF binary with the texture inside.
void write_textured_output(const ParamArgs& args, const TexturedMesh& textured) {
  WriteOptions write;
  // --format, or the output's extension as output_format reads it: any other extension is OBJ.
  write.format = MeshFormat::Obj;
#ifdef RICCI_HAVE_RENDER
  const std::string texture = args.texture == "checker" ? "" : args.texture;
  if (output_format(args) == "glb") {
    GlbOptions glb;
    glb.texture_path = texture;
    write.format = MeshFormat::Glb;
    write.glb_writer = glb_writer(glb);
  } else if (args.texture != "none") {
    // The material first: an OBJ never names a library that is not there.
    write.material.library = write_obj_material(args.output, texture).library;
  }
#endif
  write_mesh(args.output, textured, write);
}

/// Writes the refinement (homogeneous vt) to `output` and its companions beside it.
void write_refinement(const std::string& output, const std::string& input, const ParamResult& r,
                      const CommonRefinement& c, const ReadResult& read,
                      const ObjMaterial& linear_material) {
  const RefinementFiles files = refinement_files(output);
  Mesh mesh;
  mesh.positions = c.positions;
  mesh.triangles = c.triangles;
  Triangles corners(c.triangles.rows(), 3);
  for (Eigen::Index t = 0; t < corners.rows(); ++t) corners.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
  write_obj(output, mesh, corners, c.projective_uv);
  write_obj(files.linear, mesh, c.uv_triangles, c.uv, linear_material);
  const std::string name = std::filesystem::path(output).filename().string();
  write_file_atomically(files.vertex_map, [&](std::ostream& out) {
    out << "# ricci param --faces refinement: where the input's vertices are in " << name
        << "\n# input_vertex refinement_vertex, 1-based: the order of the v lines in "
        << std::filesystem::path(input).filename().string() << " and in " << name << "\n";
    for (int v = 0; v < r.mesh.num_vertices(); ++v) {
      if (r.vertex_origin[v] < 0) continue;
      out << read.vertex_map[r.vertex_origin[v]] + 1 << " " << c.input_vertex[v] + 1 << "\n";
    }
  });
  const auto columns = file_columns(r, read);
  write_file_atomically(files.matrix, [&](std::ostream& out) {
    char buffer[96];
    std::vector<std::pair<int, double>> row;
    for (int i = 0; i < c.interpolation.rows(); ++i) {
      row.clear();
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(c.interpolation, i); it;
           ++it) {
        for (const auto& [col, w] : columns[it.col()]) {
          auto found = std::find_if(row.begin(), row.end(),
                                    [col = col](const auto& e) { return e.first == col; });
          if (found == row.end()) {
            row.emplace_back(col, w * it.value());
          } else {
            found->second += w * it.value();
          }
        }
      }
      std::sort(row.begin(), row.end());
      for (const auto& [col, w] : row) {
        out.write(buffer, std::snprintf(buffer, sizeof buffer, "%d %d %.17g\n", i + 1, col + 1, w));
      }
    }
    // A last zero entry at (rows, columns) fixes the size for Matlab's spconvert.
    out << c.interpolation.rows() << " " << read.file_vertices << " 0\n";
  });
}

/// What a hyperbolic layout leaves to say on stderr, JSON or not: input faces reversed in it, and
/// vertices so close to the rim of the disk that double precision no longer keeps points apart
/// (a surface of large hyperbolic area spans that far; docs/hyperbolic.md, "Not done").
void warn_about_hyperbolic_layout(const std::string& mesh, const HyperbolicParamResult& result) {
  const HyperbolicLayout& l = result.layout;
  if (l.num_flipped_faces > 0) {
    std::cerr << "warning: " << mesh << ": " << l.num_flipped_faces
              << " faces come out reversed in the layout (docs/hyperbolic.md)\n";
  }
  // Beyond 1 - 1e-12 a unit of hyperbolic distance is below 1e-12 * 1e-4 of the disk near the
  // rim, where the corners of small faces round together.
  if (l.max_radius > 1 - 1e-12) {
    std::cerr
        << "warning: " << mesh << ": the layout reaches |z| = 1 - " << 1 - l.max_radius
        << " in the Poincare disk, where double precision cannot keep points apart (hyperbolic "
           "area "
        << result.flow.components.front().flow.total_area
        << "); the texture coordinates near the rim are unreliable (layout length error "
        << l.max_length_relative_error << "; docs/hyperbolic.md)\n";
  }
}

int run_param_hyperbolic(const ParamArgs& args) {
  HyperbolicParamOptions options;
  if (args.faces != "input") {
    throw InvalidInput("--faces " + args.faces +
                       ": the common refinement is that of vertex scaling in the plane; leave "
                       "--faces out with --geometry hyperbolic");
  }
  options.structure.scheme = parse_scheme(args.scheme);
  options.flow.tolerance = args.tolerance;
  options.flow.flips = parse_edge_flips(args.flips);
  if (args.cones != "needed" && args.cones != "auto" && args.cones != "none") {
    throw InvalidInput(
        "--cones: the hyperbolic parameterization has no cones (its metric has "
        "zero curvature at every vertex); leave --cones out");
  }
  if (args.boundary != "free" && args.boundary != "geodesic") {
    throw InvalidInput("--boundary " + args.boundary +
                       ": the hyperbolic parameterization gives every boundary zero geodesic "
                       "curvature; leave --boundary out");
  }
  check_output_is_not_input(args.output, {args.mesh});
  if (!args.report.empty()) check_output_is_not_input(args.report, {args.mesh});
  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  options.polygons = read.polygons;
  const HyperbolicParamResult result =
      run_with_progress(args.mesh, args.progress, args.json, "param", options.flow,
                        [&] { return parameterize_hyperbolic(read.mesh, options); });
  nlohmann::json report = hyperbolic_param_report(result, options);
  if (!finish_report(args.mesh, args.output, args.report, read, args.input, report,
                     result.converged, "the flow did not converge: " + result.message)) {
    return kNotConverged;
  }
  TexturedMesh textured;
  textured.mesh = read.mesh;
  textured.uv_triangles = result.cut_mesh.triangles;
  textured.uv = result.uv;
  textured.polygons = result.polygons;
  write_textured_output(args, textured);
  warn_about_hyperbolic_layout(args.mesh, result);
#ifdef RICCI_HAVE_RENDER
  write_hyperbolic_pictures(args.pictures, result);
#endif
  if (args.json) {
    std::cout << report.dump(2) << "\n";
    return kOk;
  }
  const HyperbolicLayout& l = result.layout;
  std::cout << args.mesh << " -> " << args.output << " (texture coordinates in the Poincare disk)\n"
            << "  hyperbolic area " << result.flow.components.front().flow.total_area
            << ", cut: " << result.cut.num_generators << " generators, "
            << result.cut.segments.size() << " segments, seam length " << result.seam_length
            << "\n  layout: max radius " << l.max_radius << ", length error "
            << l.max_length_relative_error << ", flipped " << l.num_flipped_faces
            << ", angle distortion mean " << result.distortion.angle_distortion_mean << " max "
            << result.distortion.angle_distortion_max << ", " << result.seconds << " s\n";
  if (result.flow.intrinsic.flips() > 0) {
    std::cout << "  " << result.flow.intrinsic.flips()
              << " edges flipped (intrinsic Delaunay); the input's faces developed in the final "
                 "metric agree on their edges to "
              << result.development_length_mismatch << " (relative)\n";
  }
  if (result.has_group) {
    std::cout << "  Fuchsian group: " << 2 * result.group.genus
              << " generators, |a1 b1 a1^-1 b1^-1 ... - I| = " << result.group.relation_residual
              << " (around the nodes: " << result.group.node_residual << ")\n";
  } else if (!result.group_failure.empty()) {
    std::cout << "  Fuchsian group not computed: " << result.group_failure << "\n";
  }
  if (!args.report.empty()) std::cout << "  wrote " << args.report << "\n";
  return kOk;
}

/// `param` on a mesh of several components, or one whose exact map gave way to another route:
/// the atlas, then a line per component (every one when there are few, else those that did not
/// go by the flow).
void print_components(const ParamArgs& args, const MeshParamResult& result) {
  const Distortion& d = result.distortion;
  const ChartPacking& p = result.packing;
  int failed = 0, overlapping = 0;
  std::array<int, EnumNames<ComponentMethod>::names.size()> by_method{};
  for (const ComponentParam& c : result.components) {
    failed += !c.parameterized;
    ++by_method[static_cast<std::size_t>(c.method)];
    overlapping += c.overlapping_face_pairs > 0;
  }
  const std::size_t n = result.components.size();
  std::cout << args.mesh << " -> " << args.output << "\n"
            << "  " << n << (n == 1 ? " component: " : " components: ");
  const char* separator = "";
  for (const EnumName<ComponentMethod>& entry : EnumNames<ComponentMethod>::names) {
    const int count = by_method[static_cast<std::size_t>(entry.value)];
    if (count == 0) continue;
    std::cout << separator << count << " " << entry.name;
    separator = ", ";
  }
  if (failed > 0) std::cout << " (" << failed << " failed)";
  std::cout << "\n"
            << "  atlas: " << p.charts.size() << " charts packed by "
            << (p.by_shape ? "shape" : "rectangles") << ", coverage " << std::setprecision(4)
            << p.coverage << " (bounding rectangles " << p.rectangle_coverage << "), gutter "
            << p.gutter << ", overlapping face pairs " << p.overlapping_face_pairs << "\n"
            << "  cones " << result.cones.size() << ", seam length " << result.seam_length
            << ", area distortion " << d.area_distortion_energy << ", angle distortion mean "
            << d.angle_distortion_mean << " max " << d.angle_distortion_max << ", flipped "
            << d.flipped_faces << ", " << result.seconds << " s\n";
  if (overlapping > 0) {
    std::cout << "  components whose layout overlapped itself, cut into charts that do not: "
              << overlapping << "\n";
  }
  const bool all = n <= 20;
  int skipped = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const ComponentParam& comp = result.components[c];
    const bool exact =
        comp.method == ComponentMethod::Flow || comp.method == ComponentMethod::Untangled;
    if (!all && comp.parameterized && exact && comp.overlapping_face_pairs == 0) {
      ++skipped;
      continue;
    }
    std::cout << "  component " << c << " (" << comp.faces.size() << " faces, genus " << comp.genus
              << ", " << comp.boundary_loops
              << " boundary loops): " << component_method_name(comp.method);
    if (comp.charts.size() > 1) std::cout << " (" << comp.charts.size() << " charts)";
    std::cout << ", cones " << comp.cones.size() << ", seam length " << comp.seam_length
              << ", angle distortion mean " << comp.distortion.angle_distortion_mean
              << ", area scale " << comp.area_scale << ", " << comp.seconds << " s";
    if (comp.overlapping_face_pairs > 0) {
      std::cout << ", its layout overlapped itself (" << comp.overlapping_face_pairs
                << " face pairs)";
    }
    if (!comp.message.empty()) {
      std::cout << (!comp.parameterized ? ": failed: "
                    : exact             ? ": "
                                        : ": the exact map gave way: ")
                << comp.message;
    }
    std::cout << "\n";
  }
  if (skipped > 0) {
    std::cout << "  (" << skipped
              << " more components by the flow, none overlapping itself: --report lists every "
                 "one)\n";
  }
  if (!result.converged) {
    std::cout << "  wrote " << args.output
              << " with the failed components laid out as charts or patches of their own shape\n";
  }
  if (!args.report.empty()) std::cout << "  wrote " << args.report << "\n";
}

}  // namespace

/// --fault: the failures a batch must survive, on demand (tests of `ricci batch`).
void inject_fault(const std::string& fault) {
  if (fault.empty()) return;
  const char* enabled = std::getenv("RICCI_FAULT_INJECTION");
  if (enabled == nullptr || std::string(enabled) != "1") {
    throw InvalidInput("--fault injects failures for tests; it needs RICCI_FAULT_INJECTION=1");
  }
  if (fault == "segv") {
    std::signal(SIGSEGV, SIG_DFL);  // past any sanitizer's handler: the plain crash
    std::raise(SIGSEGV);
  } else if (fault == "abort") {
    std::abort();
  } else if (fault == "hang") {
    for (;;) ::pause();
  } else if (fault == "solver") {
    // What main makes of the library's SolverError (a numerical breakdown): exit 3.
    throw SolverError("--fault solver: an injected breakdown of the linear algebra");
  } else if (fault == "alloc") {
    // Grows until an allocation fails (under a memory limit) or the kernel steps in.
    std::vector<std::unique_ptr<char[]>> blocks;
    for (;;) {
      constexpr std::size_t kBlock = std::size_t{64} << 20;
      blocks.emplace_back(new char[kBlock]);
      std::memset(blocks.back().get(), 1, kBlock);
    }
  }
  throw InvalidInput("--fault: unknown fault '" + fault + "' (segv, abort, hang, alloc, solver)");
}

int run_param(const ParamArgs& args) {
  inject_fault(args.fault);
  check_texture_options(args);
  if (parse_geometry(args.geometry) == Geometry::Hyperbolic) return run_param_hyperbolic(args);
  ParamOptions options;
  options.structure.scheme = parse_scheme(args.scheme);
  options.boundary = parse_boundary_mode(args.boundary);
  options.quantize = args.quantize;
  options.auto_cones.max_log_scale = args.max_log_scale;
  options.auto_cones.max_cones = args.max_cones;
  options.auto_cones.smoothness = args.cone_smoothness;
  options.flow.tolerance = args.tolerance;
  options.flow.flips = parse_edge_flips(args.flips);
  options.packing.gutter = args.gutter;
  check_output_is_not_input(args.output, {args.mesh, args.cones});
  if (!args.report.empty()) check_output_is_not_input(args.report, {args.mesh, args.cones});
  const bool refinement = args.faces == "refinement";
  // The common refinement places the input's vertices where the flat metric puts them.
  options.polish.enabled = args.polish == "angles" && !refinement;
  // The refinement is the exact map itself, fold-free without moving a vertex.
  options.fold_free.untangle = args.fold_free != "none" && !refinement;
  options.fold_free.charts = args.fold_free == "charts" && !refinement;
  const RefinementFiles files = refinement_files(args.output);
  if (refinement) {
    if (!scheme_traits(options.structure.scheme).ptolemy_flips) {
      throw InvalidInput(
          "--faces refinement: the exact map is that of vertex scaling (Ptolemy flips keep its "
          "conformal class); add --scheme vertex-scaling");
    }
    for (const std::string& path : {files.linear, files.vertex_map, files.matrix}) {
      check_output_is_not_input(path, {args.mesh, args.cones, args.output});
    }
  }

  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  apply_cones_option(args.cones, args.mesh, read, options);
  options.polygons = read.polygons;
  if (refinement) {
    const Topology t = build_topology(read.mesh.triangles, read.mesh.num_vertices());
    if (t.components.size() > 1) {
      throw InvalidInput(args.mesh + ": --faces refinement: the mesh has " +
                         std::to_string(t.components.size()) +
                         " connected components, and the common refinement is made for one; "
                         "leave --faces out for one atlas of them all");
    }
  }
  const MeshParamResult result =
      run_with_progress(args.mesh, args.progress, args.json, "param", options.flow,
                        [&] { return parameterize(read.mesh, options); });
  nlohmann::json report = param_report(result, options);
  // Several components: the atlas covers every face even when some components failed (laid out
  // as patches of their own shape), so it is written, and the exit status says that not all
  // went well.
  const bool several = !result.components.empty() && result.uv.rows() > 0;
  std::optional<CommonRefinement> exact;
  if (refinement && result.converged) {
    exact = common_refinement(result);
    report["refinement"] = refinement_report(*exact, result);
    report["refinement"]["files"] = {{"projective", args.output},
                                     {"linear", files.linear},
                                     {"vertex_map", files.vertex_map},
                                     {"interpolation_matrix", files.matrix}};
  }
  if (!finish_report(args.mesh, args.output, args.report, read, args.input, report,
                     result.converged,
                     several ? result.message
                             : "the flow did not converge: " +
                                   cli::message_with_fixes(result.message, result.flow.fixes)) &&
      !several) {
    return kNotConverged;
  }
  if (exact) {
    // The material goes with the linear companion: tools that read `vt u v` would take the
    // projective file's (u w, v w) for coordinates.
    ObjMaterial linear_material;
#ifdef RICCI_HAVE_RENDER
    if (args.texture != "none") {
      linear_material.library = write_obj_material(refinement_files(args.output).linear,
                                                   args.texture == "checker" ? "" : args.texture)
                                    .library;
    }
#endif
    write_refinement(args.output, args.mesh, result, *exact, read, linear_material);
  } else {
    write_textured_output(args, textured_mesh(result));
    if (!read.polygons.empty() && result.polygons.empty()) {
      std::cerr << "warning: " << args.mesh << ": edge splits changed the faces, so " << args.output
                << " holds triangles, not the file's polygons\n";
    }
    auto proper = [](const Polygons& polygons) {
      int count = 0;
      for (int p = 0; p < polygons.num_polygons(); ++p) count += polygons.size(p) > 3;
      return count;
    };
    if (!result.polygons.empty() && proper(result.polygons) < proper(read.polygons)) {
      std::cerr << "warning: " << args.mesh << ": "
                << proper(read.polygons) - proper(result.polygons)
                << " polygons have no corner from which the layout sees all of them (a fan from "
                   "any corner would fold), so "
                << args.output << " holds each of them as its triangles\n";
    }
  }
#ifdef RICCI_HAVE_RENDER
  write_param_pictures(args.pictures, result, args.mesh, exact ? &*exact : nullptr);
#endif
  if (args.json) {
    std::cout << report.dump(2) << "\n";
  } else if (several) {
    print_components(args, result);
  } else {
    const Distortion& d = result.distortion;
    std::cout << args.mesh << " -> " << args.output << "\n"
              << "  cones " << result.cones.size() << " (" << cone_mode_name(options.cone_mode)
              << "), edge splits " << result.edge_splits << ", cut: " << result.cut.num_generators
              << " generators, " << result.cut.segments.size() << " segments, seam length "
              << result.seam_length << "\n"
              << "  area distortion " << d.area_distortion_energy << ", angle distortion mean "
              << d.angle_distortion_mean << " max " << d.angle_distortion_max << ", flipped "
              << d.flipped_faces << ", layout length error "
              << result.layout.max_length_relative_error << ", " << result.seconds << " s\n";
    if (!result.polygons.empty()) {
      int polygons = 0;
      for (int p = 0; p < result.polygons.num_polygons(); ++p)
        polygons += result.polygons.size(p) > 3;
      std::cout << "  faces: the input's " << result.polygons.num_polygons() << " (" << polygons
                << " of more than 3 corners), no seam inside one; the figures above are of "
                   "their fans as written\n";
    }
    if (exact) {
      const CommonRefinement& c = *exact;
      std::cout << "  refinement " << c.positions.rows() << " vertices, " << c.triangles.rows()
                << " triangles (" << c.isometric_flips << " isometric and " << c.ptolemy_flips
                << " Ptolemy flips undone): final lengths along the intrinsic edges to "
                << c.max_intrinsic_length_error << ", " << c.seconds << " s\n"
                << "  wrote " << files.linear << ", " << files.vertex_map << ", " << files.matrix
                << "\n";
    } else if (result.flow.intrinsic.flips() > 0) {
      std::cout << "  " << result.flow.intrinsic.flips()
                << " intrinsic edge flips; the output keeps the input's faces (development "
                   "mismatch "
                << result.development_length_mismatch
                << "; --faces refinement writes the exact map)\n";
    }
    if (result.untangle.moved_vertices > 0) {
      std::cout << "  untangled: " << result.untangle.flipped_before
                << " faces drawn flipped made positive by moving " << result.untangle.moved_vertices
                << " vertices (seams, cones and boundary exact), " << result.untangle.seconds
                << " s\n";
    }
    if (d.flipped_faces > 0 && !exact) {
      // Each vertex sits at its exact image; a face drawn straight between them folds where the
      // map bends it strongly: needles, or faces next to a strong cone.
      std::cerr << "warning: " << args.mesh << ": " << d.flipped_faces
                << " uv triangles are flipped (needle faces, or faces around a cone too strong "
                   "for its valence, drawn straight between their vertices' exact images)\n"
                << "  try: --fold-free charts (the default), or --faces refinement (the exact "
                   "map without folds)\n";
    }
    if (!args.report.empty()) std::cout << "  wrote " << args.report << "\n";
  }
  // A layout that folds is not a success, whatever the flow did (--fold-free untangle or none
  // leave it as it is; the refinement written beside it is fold-free).
  const bool open_layout =
      !(result.layout.max_length_relative_error <= options.fold_free.max_length_error);
  if (!several && !exact && open_layout) {
    std::cerr << "warning: " << args.mesh << ": the layout does not close up (relative length "
              << "error " << result.layout.max_length_relative_error
              << "): the flat metric's scale spans more than double precision lays out\n"
              << "  try: --fold-free charts (the default)\n";
  }
  const bool folds = !several && !exact && (result.distortion.flipped_faces > 0 || open_layout);
  return result.converged && !folds ? kOk : kNotConverged;
}

int run_spline(const SplineArgs& args) {
  SplineOptions options;
  options.refine = args.refine;
  options.smoothness = args.smoothness;
  options.param.flow.tolerance = args.tolerance;
  options.param.structure.scheme = parse_scheme(args.scheme);
  options.param.flow.flips = parse_edge_flips(args.flips);
  check_output_is_not_input(args.output, {args.mesh, args.cones});
  if (!args.control_net.empty()) {
    check_output_is_not_input(args.control_net, {args.mesh, args.cones, args.output});
  }
  if (!args.report.empty()) check_output_is_not_input(args.report, {args.mesh, args.cones});
  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  if (!args.cones.empty()) {
    options.choose_cone_mode = false;
    apply_cones_option(args.cones, args.mesh, read, options.param);
  }
  const SplineResult result =
      run_with_progress(args.mesh, args.progress, args.json, "spline", options.param.flow,
                        [&] { return fit_manifold_spline(read.mesh, options); });
  nlohmann::json report = spline_report(result, options);
  if (!args.control_net.empty()) report["control_net_file"] = args.control_net;
  if (!finish_report(args.mesh, args.output, args.report, read, args.input, report,
                     result.converged, result.message)) {
    return kNotConverged;
  }
  write_obj(args.output, result.surface);
  if (!args.control_net.empty()) write_obj(args.control_net, result.control_net);
#ifdef RICCI_HAVE_RENDER
  write_manifold_spline_pictures(args.pictures, result);
#endif
  if (args.json) {
    std::cout << report.dump(2) << "\n";
  } else {
    const SplineError& e = result.error;
    if (!result.parameterization_note.empty()) {
      std::cout << "  note: " << result.parameterization_note << "\n";
    }
    std::cout << args.mesh << " -> " << args.output << "\n"
              << "  cones " << result.param.cones.size() << ", surface "
              << result.surface.num_faces() << " faces (refine " << options.refine
              << "), control net " << result.control_net.num_vertices() << " points\n"
              << "  error / bbox diagonal: distance max " << e.max_distance << " rms "
              << e.rms_distance << ", parametric max " << e.max_parametric << " rms "
              << e.rms_parametric << "\n"
              << "  C1 jumps (relative): value " << result.continuity.relative_value_jump
              << ", gradient " << result.continuity.relative_gradient_jump << ", " << result.seconds
              << " s\n";
    if (!args.control_net.empty()) std::cout << "  wrote " << args.control_net << "\n";
    if (!args.report.empty()) std::cout << "  wrote " << args.report << "\n";
  }
  return kOk;
}

int run_sphere(const SphereArgs& args) {
  SphereOptions options;
  options.structure.scheme = parse_scheme(args.scheme);
  options.flow.tolerance = args.tolerance;
  options.flow.flips = parse_edge_flips(args.flips);
  options.untangle = args.untangle;
  check_output_is_not_input(args.output, {args.mesh});
  if (!args.report.empty()) check_output_is_not_input(args.report, {args.mesh});

  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  if (args.pole >= 0) {
    const std::vector<int> to_mesh = inverse_map(read.vertex_map);
    if (args.pole >= static_cast<int>(to_mesh.size()) || to_mesh[args.pole] < 0) {
      throw InvalidInput("--pole: vertex " + std::to_string(args.pole) + " is not a vertex of " +
                         args.mesh + " used by any face");
    }
    options.pole = to_mesh[args.pole];
  }
  const SphereResult result =
      run_with_progress(args.mesh, args.progress, args.json, "sphere", options.flow,
                        [&] { return sphere_map(read.mesh, options); });
  nlohmann::json report = sphere_report(result, options);
  report["pole_file_index"] = read.vertex_map[result.pole];
  // The library's fixes name mesh vertices; --pole takes the file's.
  std::vector<OptionFix> fixes = result.fixes;
  for (OptionFix& fix : fixes) {
    if (fix.option == "pole") fix.value = std::to_string(read.vertex_map[std::stoi(fix.value)]);
  }
  std::string why = cli::message_with_fixes(result.message, fixes);
  if (result.converged && !result.valid) {
    // No option of sphere helps a map that inverts faces after untangling, or a limb squeezed
    // below double resolution; a cut parameterization with cones shrinks no limb.
    why += "\n  try: ricci param " + args.mesh + " -o OUT.obj (a parameterization with cones)";
  }
  if (!finish_report(args.mesh, args.output, args.report, read, args.input, report, result.valid,
                     why)) {
    return kNotConverged;
  }
  Mesh sphere;
  sphere.positions = result.positions;
  sphere.triangles = read.mesh.triangles;
  write_obj(args.output, sphere);
  if (args.json) {
    std::cout << report.dump(2) << "\n";
  } else {
    std::cout << args.mesh << " -> " << args.output << "\n"
              << "  pole " << read.vertex_map[result.pole] << ", flow "
              << result.flow.components.front().flow.iterations << " iterations, centring "
              << result.centre_iterations << " steps (|centre| " << result.centre_of_mass << ")\n"
              << "  inverted faces " << result.inverted_faces << ", area - 4 pi "
              << result.spherical_area - 4 * std::numbers::pi << ", angle distortion mean "
              << result.angle_distortion_mean << " max " << result.angle_distortion_max
              << ", log area [" << result.log_area_min << ", " << result.log_area_max << "]\n"
              << "  precision " << result.precision_bits << " bits (smallest altitude: plane "
              << result.min_plane_altitude << ", sphere " << result.min_sphere_altitude << "), "
              << result.unresolved_faces << " faces below double resolution, " << result.seconds
              << " s\n";
    if (!args.report.empty()) std::cout << "  wrote " << args.report << "\n";
  }
  return kOk;
}

int run_generate(const GenerateArgs& args) {
  const int r = args.resolution;
  Mesh mesh;
  if (args.kind == "tetrahedron") {
    mesh = make_tetrahedron(1.0);
  } else if (args.kind == "icosphere") {
    mesh = make_icosphere(r > 0 ? r : 3);
  } else if (args.kind == "disk") {
    mesh = make_disk(r > 0 ? r : 16, 0.5);
  } else if (args.kind == "torus") {
    mesh = make_torus(r > 0 ? 2 * r : 64, r > 0 ? r : 32);
  } else if (args.kind == "surface") {
    mesh = args.holes > 0 ? make_surface_with_holes(args.genus, args.holes, r > 0 ? r : 24)
                          : make_closed_surface(args.genus, r > 0 ? r : 24);
  } else if (args.kind == "cad-cylinder") {
    mesh = make_cad_cylinder(r > 0 ? r : 360);
  } else if (args.kind == "cad-ring") {
    mesh = make_cad_ring(r > 0 ? r : 360);
  } else if (args.kind == "fingers") {
    mesh = make_ball_with_fingers(args.fingers, args.finger_length, r > 0 ? r : 16);
  } else {
    throw InvalidInput("generate: unknown kind '" + args.kind +
                       "'; expected tetrahedron, icosphere, disk, torus, surface, cad-cylinder, "
                       "cad-ring or fingers");
  }
  if (args.valence3) mesh = split_faces_near_corner(mesh, 0.05, 0.05, 3);
  if (args.needles > 0) mesh = pull_vertices_to_neighbours(mesh, args.needles, 1, 2);
  write_obj(args.output, mesh);
  std::cout << "wrote " << args.output << ": " << mesh.num_vertices() << " vertices, "
            << mesh.num_faces() << " faces\n";
  return kOk;
}

}  // namespace ricci::cli
