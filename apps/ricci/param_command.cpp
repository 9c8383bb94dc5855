// `ricci param`: the run of the parameterization command (its options: param_options.cpp).
#include "param_command.hpp"

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

#include "command_support.hpp"
#include "fixes.hpp"
#include "json_output.hpp"
#include "progress.hpp"
#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/param/output_mesh.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/param/refinement/common_refinement.hpp"
#ifdef RICCI_HAVE_RENDER
#include "render_command.hpp"
#include "ricci/render/textured_files.hpp"
#endif

namespace ricci::cli {
namespace {

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
std::vector<std::vector<std::pair<int, double>>> file_columns(const Parameterization& r,
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
void write_refinement(const std::string& output, const std::string& input,
                      const Parameterization& r, const CommonRefinement& c, const ReadResult& read,
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

/// `param --geometry hyperbolic`: the uniformization metric laid out in the Poincare disk.
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

/// The library's options from param's arguments (the cones wait for the mesh: apply_cones_option).
ParamOptions param_options(const ParamArgs& args) {
  ParamOptions options;
  options.structure.scheme = parse_scheme(args.scheme);
  options.boundary = parse_boundary_mode(args.boundary);
  options.seams = parse_seam_mode(args.seams);
  options.quantize = args.quantize;
  options.auto_cones.max_log_scale = args.max_log_scale;
  options.auto_cones.max_cones = args.max_cones;
  options.auto_cones.smoothness = args.cone_smoothness;
  options.flow.tolerance = args.tolerance;
  options.flow.flips = parse_edge_flips(args.flips);
  options.packing.gutter = args.gutter;
  const bool refinement = args.faces == "refinement";
  // The common refinement places the input's vertices where the flat metric puts them.
  options.polish.enabled = args.polish == "angles" && !refinement;
  // The refinement is the exact map itself, fold-free without moving a vertex.
  options.fold_free.untangle = args.fold_free != "none" && !refinement;
  options.fold_free.charts = args.fold_free == "charts" && !refinement;
  return options;
}

/// The checks before any work: no output over an input, and what --faces refinement needs.
void check_param_outputs(const ParamArgs& args, const ParamOptions& options) {
  check_output_is_not_input(args.output, {args.mesh, args.cones});
  if (!args.report.empty()) check_output_is_not_input(args.report, {args.mesh, args.cones});
  if (args.faces != "refinement") return;
  if (!scheme_traits(options.structure.scheme).ptolemy_flips) {
    throw InvalidInput(
        "--faces refinement: the exact map is that of vertex scaling (Ptolemy flips keep its "
        "conformal class); add --scheme vertex-scaling");
  }
  const RefinementFiles files = refinement_files(args.output);
  for (const std::string& path : {files.linear, files.vertex_map, files.matrix}) {
    check_output_is_not_input(path, {args.mesh, args.cones, args.output});
  }
}

/// --faces refinement is made for one connected component.
void check_one_component(const ParamArgs& args, const Mesh& mesh) {
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  if (t.components.size() > 1) {
    throw InvalidInput(args.mesh + ": --faces refinement: the mesh has " +
                       std::to_string(t.components.size()) +
                       " connected components, and the common refinement is made for one; "
                       "leave --faces out for one atlas of them all");
  }
}

/// Polygons of more than three corners.
int proper_polygons(const Polygons& polygons) {
  int count = 0;
  for (int p = 0; p < polygons.num_polygons(); ++p) count += polygons.size(p) > 3;
  return count;
}

/// Writes the parameterization (or the refinement and its companions) and says on stderr where
/// the file's polygons could not be kept.
void write_param_outputs(const ParamArgs& args, const ReadResult& read,
                         const Parameterization& result,
                         const std::optional<CommonRefinement>& exact) {
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
    return;
  }
  write_textured_output(args, textured_mesh(result));
  if (!read.polygons.empty() && result.polygons.empty()) {
    std::cerr << "warning: " << args.mesh << ": edge splits changed the faces, so " << args.output
              << " holds triangles, not the file's polygons\n";
  }
  if (!result.polygons.empty() &&
      proper_polygons(result.polygons) < proper_polygons(read.polygons)) {
    std::cerr << "warning: " << args.mesh << ": "
              << proper_polygons(read.polygons) - proper_polygons(result.polygons)
              << " polygons have no corner from which the layout sees all of them (a fan from "
                 "any corner would fold), so "
              << args.output << " holds each of them as its triangles\n";
  }
}

/// The summary of one chart on stdout (and its warnings on stderr).
void print_chart_summary(const ParamArgs& args, const ParamOptions& options,
                         const MeshParamResult& result,
                         const std::optional<CommonRefinement>& exact) {
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
    std::cout << "  faces: the input's " << result.polygons.num_polygons() << " ("
              << proper_polygons(result.polygons)
              << " of more than 3 corners), no seam inside one; the figures above are of "
                 "their fans as written\n";
  }
  if (exact) {
    const CommonRefinement& c = *exact;
    const RefinementFiles files = refinement_files(args.output);
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
              << result.routes.front().pipeline.development_length_mismatch
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

}  // namespace

int run_param(const ParamArgs& args) {
  inject_fault(args.fault);
  check_texture_options(args);
  if (parse_geometry(args.geometry) == Geometry::Hyperbolic) return run_param_hyperbolic(args);
  ParamOptions options = param_options(args);
  check_param_outputs(args, options);
  const bool refinement = args.faces == "refinement";

  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  apply_cones_option(args.cones, args.mesh, read, options);
  options.polygons = read.polygons;
  if (refinement) check_one_component(args, read.mesh);
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
    const RefinementFiles files = refinement_files(args.output);
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
  write_param_outputs(args, read, result, exact);
#ifdef RICCI_HAVE_RENDER
  write_param_pictures(args.pictures, result, args.mesh, exact ? &*exact : nullptr);
#endif
  if (args.json) {
    std::cout << report.dump(2) << "\n";
  } else if (several) {
    print_components(args, result);
  } else {
    print_chart_summary(args, options, result, exact);
  }
  for (const ComponentRoute& route : result.routes) {
    if (route.pipeline.too_few_cones.empty()) continue;
    std::cerr << "warning: " << args.mesh << ": " << route.pipeline.too_few_cones << "\n"
              << "  try: --seams free, or --cones auto\n";
  }
  for (const ComponentRoute& route : result.routes) {
    if (route.pipeline.free_seams_note.empty()) continue;
    std::cerr << "note: " << args.mesh << ": " << route.pipeline.free_seams_note << "\n"
              << "  try: more cones (--cones N) for free seams that distort less\n";
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

Subcommand add_param_command(CLI::App& app) {
  auto args = std::make_shared<ParamArgs>();
  CLI::App* cmd = add_param_subcommand(app, *args);
  return {cmd, [args] { return run_param(*args); }};
}

}  // namespace ricci::cli
