#include "render_command.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/repair.hpp"
#include "ricci/mesh/textured_mesh.hpp"
#include "ricci/render/image.hpp"
#include "ricci/render/param_pictures.hpp"
#include "ricci/render/render_mesh.hpp"
#include "ricci/render/spline_pictures.hpp"
#include "ricci/render/textured_files.hpp"
#include "ricci/render/tiling.hpp"
#include "ricci/render/uv_plot.hpp"
#include "ricci/render/web_viewer.hpp"

namespace ricci::cli {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

/// Cones are read from the texture angles: glTF stores them in single precision, whose angle
/// sums wander by ~1e-6 around 2 pi at seams, so a cone there must differ by more.
double cone_tolerance_of(const std::string& mesh) {
  return lower_extension(mesh) == ".glb" ? 1e-4 : 1e-6;
}

/// "auto" (zero), an axis ("x", "-z", "+y") or three numbers (as separate values or "1,1,1").
Eigen::Vector3d parse_direction(const char* flag, std::vector<std::string> values) {
  if (values.size() == 1 && values[0].find(',') != std::string::npos) {
    std::string text = values[0];
    values.clear();
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = text.find(',', start);
      values.push_back(text.substr(start, comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  auto bad = [&]() -> InvalidInput {
    std::string given;
    for (const std::string& v : values) given += (given.empty() ? "" : " ") + v;
    return InvalidInput(std::string(flag) + ": '" + given +
                        "' is not auto, an axis (x, -x, y, -y, z, -z) or three numbers X Y Z");
  };
  if (values.size() == 1) {
    const std::string& v = values[0];
    if (v == "auto") return Eigen::Vector3d::Zero();
    const bool negative = !v.empty() && v[0] == '-';
    const std::string axis = (!v.empty() && (v[0] == '-' || v[0] == '+')) ? v.substr(1) : v;
    const double sign = negative ? -1.0 : 1.0;
    if (axis == "x") return sign * Eigen::Vector3d::UnitX();
    if (axis == "y") return sign * Eigen::Vector3d::UnitY();
    if (axis == "z") return sign * Eigen::Vector3d::UnitZ();
    throw bad();
  }
  if (values.size() != 3) throw bad();
  Eigen::Vector3d d;
  for (int i = 0; i < 3; ++i) {
    std::size_t used = 0;
    try {
      d[i] = std::stod(values[i], &used);
    } catch (const std::exception&) {
      throw bad();
    }
    if (used != values[i].size() || !std::isfinite(d[i])) throw bad();
  }
  if (d.isZero(0)) throw InvalidInput(std::string(flag) + ": the direction must not be zero");
  return d;
}

void check_not_input(const std::string& output, const std::string& input) {
  std::error_code ec;
  if (std::filesystem::exists(output, ec) && std::filesystem::equivalent(output, input, ec)) {
    throw InvalidInput(output + ": the output would overwrite the input " + input +
                       "; choose another -o");
  }
}

}  // namespace

CLI::App* add_render_subcommand(CLI::App& app, RenderArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "render",
      "Draw an OBJ with texture coordinates (what `param` writes) as a PNG: checkerboard texture, "
      "Lambert shading, seams as dark lines, cones as red dots. No window needed.");
  cmd->add_option("MESH", args.mesh, "OBJ file with vt coordinates (f v/vt)")->required();
  cmd->add_option("-o,--output", args.output, "output .png")->required();
  cmd->add_option("--width", args.width, "picture width, pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--height", args.height, "picture height, pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--view", args.view,
                  "where the camera looks from: auto (least-extent axis or a 3/4 view), an axis "
                  "(x, -x, y, -y, z, -z) or a direction X Y Z")
      ->expected(1, 3)
      ->capture_default_str();
  cmd->add_option("--up", args.up, "screen up direction: an axis or X Y Z (default: automatic)")
      ->expected(1, 3);
  cmd->add_option("--checker", args.checker, "checker squares per unit of texture coordinate")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--supersampling", args.supersampling,
                  "samples per pixel along each axis (anti-aliasing)")
      ->capture_default_str()
      ->check(CLI::Range(1, 8));
  cmd->add_flag("--smooth", args.smooth,
                "shade with interpolated vertex normals instead of face normals");
  cmd->add_flag("--no-seams", args.no_seams, "do not draw the seams");
  cmd->add_flag("--no-cones", args.no_cones, "do not mark the cones");
  cmd->add_option("--uv", args.uv_output,
                  "also write the texture layout coloured by log area distortion (.svg or .png)");
  add_input_options(cmd, args.input);
  return cmd;
}

int run_render(const RenderArgs& args) {
  if (lower_extension(args.output) != ".png") {
    throw InvalidInput(args.output + ": render writes PNG; give -o a .png file");
  }
  const std::string uv_ext = lower_extension(args.uv_output);
  if (!args.uv_output.empty() && uv_ext != ".svg" && uv_ext != ".png") {
    throw InvalidInput(args.uv_output + ": --uv writes .svg or .png");
  }
  if (!args.uv_output.empty() && std::filesystem::path(args.uv_output).lexically_normal() ==
                                     std::filesystem::path(args.output).lexically_normal()) {
    throw InvalidInput(args.uv_output + ": --uv and -o name the same file");
  }
  check_not_input(args.output, args.mesh);
  if (!args.uv_output.empty()) check_not_input(args.uv_output, args.mesh);

  TexturedMesh textured = read_textured_file(args.mesh);
  // A picture needs no valid mesh: the auto mode repairs what it can and draws the rest; the
  // never mode refuses any defect.
  const RepairMode mode = repair_mode(args.input);
  const ValidationReport defects =
      mode == RepairMode::Always ? ValidationReport{} : find_defects(textured.mesh);
  if (mode == RepairMode::Never && !defects.ok()) {
    try {
      throw_first_defect(defects, args.mesh);
    } catch (const InvalidInput& e) {
      throw InvalidInput(e.what(), args.input.strict ? fixes_of({{"strict", "false"}})
                                                     : fixes_of({{"repair", "auto"}}));
    }
  }
  if (mode == RepairMode::Always || !defects.ok()) {
    // Texture coordinates belong to face corners, so they follow the faces: kept faces keep
    // their uv corners, reversed faces exchange corners 1 and 2 like their vertices. Slivers
    // stay (they draw nothing), so that every face keeps the corners of its input face.
    RepairOptions repair_options;
    repair_options.remove_slivers = false;
    repair_options.largest_component_only = args.input.largest_component;
    RepairResult repaired = repair_mesh(textured.mesh, repair_options);
    print_repair(args.mesh, repaired.report, mode == RepairMode::Auto);
    Triangles uv_triangles(repaired.mesh.num_faces(), 3);
    for (int f = 0; f < repaired.mesh.num_faces(); ++f) {
      const auto corners = textured.uv_triangles.row(repaired.face_map[f]);
      uv_triangles.row(f) << corners(0), corners(repaired.face_flipped[f] ? 2 : 1),
          corners(repaired.face_flipped[f] ? 1 : 2);
    }
    textured.mesh = std::move(repaired.mesh);
    textured.uv_triangles = std::move(uv_triangles);
  }
  RenderOptions options;
  options.cone_tolerance = cone_tolerance_of(args.mesh);
  options.width = args.width;
  options.height = args.height;
  options.view = parse_direction("--view", args.view);
  if (!args.up.empty()) options.up = parse_direction("--up", args.up);
  options.checker = args.checker;
  options.supersampling = args.supersampling;
  options.smooth_shading = args.smooth;
  options.draw_seams = !args.no_seams;
  options.mark_cones = !args.no_cones;
  options.uv_weights = textured.uv_weights;  // homogeneous vt: projective interpolation
  const RenderResult rendered =
      render_textured_mesh(textured.mesh, textured.uv_triangles, textured.uv, options);
  write_png(args.output, rendered.image);
  const Eigen::Vector3d v = rendered.camera.view + Eigen::Vector3d::Zero();  // no "-0"
  std::cout << args.mesh << " -> " << args.output << " (" << args.width << " x " << args.height
            << ")\n  view from (" << v.x() << ", " << v.y() << ", " << v.z() << "), "
            << rendered.visible_faces << " of " << textured.mesh.num_faces() << " faces visible, "
            << rendered.seam_edges << " seam edges, " << rendered.cones << " cones ("
            << rendered.visible_cones << " visible)\n";
  if (!args.uv_output.empty()) {
    UvPlotOptions uv_options;
    uv_options.cone_tolerance = cone_tolerance_of(args.mesh);
    UvPlotInfo info;
    if (uv_ext == ".svg") {
      write_svg(args.uv_output, plot_uv_layout_svg(textured.mesh, textured.uv_triangles,
                                                   textured.uv, uv_options, &info));
    } else {
      write_png(args.uv_output, plot_uv_layout(textured.mesh, textured.uv_triangles, textured.uv,
                                               uv_options, &info));
    }
    std::cout << "  layout -> " << args.uv_output << ": ln area ratio in [" << info.log_area_min
              << ", " << info.log_area_max << "], " << info.flipped_faces << " flipped faces\n";
  }
  return kOk;
}

CLI::App* add_view_subcommand(CLI::App& app, ViewArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "view",
      "Write an interactive viewer of an OBJ with texture coordinates (what `param` writes, "
      "`vt u v w` of --faces refinement included) as one self-contained HTML file: the surface "
      "with a checkerboard, seams and cones beside the texture layout; colouring by area or "
      "angle distortion; hover a face for its figures. Open it in a browser (WebGL), no network "
      "needed.");
  cmd->add_option("MESH", args.mesh, "OBJ file with vt coordinates (f v/vt)")->required();
  cmd->add_option("-o,--output", args.output, "output .html")->required();
  cmd->add_option("--title", args.title, "the page's title (default: the mesh's file name)");
  cmd->add_option("--checker", args.checker,
                  "checker squares per unit of texture coordinate when the page opens")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1e5));
  cmd->add_option("--colour", args.colouring,
                  "colouring when the page opens: checker, area (ln of the area ratio) or angle "
                  "(sigma_max / sigma_min)")
      ->capture_default_str()
      ->check(CLI::IsMember(enum_primary_names<ViewerColouring>()));
  return cmd;
}

int run_view(const ViewArgs& args) {
  const std::string ext = lower_extension(args.output);
  if (ext != ".html" && ext != ".htm") {
    throw InvalidInput(args.output + ": view writes an HTML page; give -o a .html file");
  }
  check_not_input(args.output, args.mesh);
  const TexturedMesh textured = read_textured_file(args.mesh);
  WebViewerOptions options;
  options.cone_tolerance = cone_tolerance_of(args.mesh);
  options.title =
      args.title.empty() ? std::filesystem::path(args.mesh).filename().string() : args.title;
  options.uv_weights = textured.uv_weights;
  options.checker = args.checker;
  options.colouring = parse_enum<ViewerColouring>(args.colouring, "--colour");
  const WebViewerInfo info =
      write_web_viewer(args.output, textured.mesh, textured.uv_triangles, textured.uv, options);
  std::cout << args.mesh << " -> " << args.output << " (" << (info.bytes + 512 * 1024) / (1 << 20)
            << " MB)\n  " << info.vertices << " vertices, " << info.faces << " faces, "
            << info.seam_edges << " seam edges, " << info.cones << " cones, " << info.flipped_faces
            << " flipped faces"
            << (info.projective ? ", projective texture coordinates (vt u v w)" : "") << "\n";
  return kOk;
}

void write_hyperbolic_pictures(const std::string& folder, const HyperbolicParamResult& result) {
  if (folder.empty()) return;
  std::filesystem::create_directories(folder);
  std::vector<Mobius> generators;
  for (const SegmentIsometry& s : result.layout.segment_maps) generators.push_back(s.map);
  TilingInfo info;
  const std::string svg = (std::filesystem::path(folder) / "tiling.svg").string();
  const std::string png = (std::filesystem::path(folder) / "tiling.png").string();
  std::string drawing;
  try {
    drawing = draw_tiling_svg(result.uv, result.cut_mesh.triangles, generators, {}, &info);
  } catch (const InvalidInput& e) {
    // The parameterization is written; only its picture is out of reach (segment maps whose
    // determinant double precision cannot resolve, far out in the disk).
    std::cerr << "warning: pictures: the tiling is not drawn: " << e.what() << "\n";
    return;
  }
  write_svg(svg, drawing);
  write_png(png, draw_tiling(result.uv, result.cut_mesh.triangles, generators));
  std::cerr << "pictures: " << svg << " " << png << " (fundamental domain and " << info.images_drawn
            << " of its images)\n";
}

void write_param_pictures(const std::string& folder, const MeshParamResult& result,
                          const std::string& input, const CommonRefinement* refinement) {
  if (folder.empty()) return;
  ParamPicturesOptions options;
  options.viewer.title = std::filesystem::path(input).filename().string() + ": " +
                         std::to_string(result.cones.size()) + " cones";
  // The refinement's page shows what -o holds: the exact map, projective per face.
  options.web_viewer = refinement == nullptr;
  ParamPicturesResult written = write_parameterization_pictures(folder, result, options);
  if (refinement && web_viewer_available()) {
    Mesh mesh;
    mesh.positions = refinement->positions;
    mesh.triangles = refinement->triangles;
    const Eigen::Index corners = refinement->projective_uv.rows();
    Triangles uv_triangles(mesh.triangles.rows(), 3);
    for (Eigen::Index t = 0; t < uv_triangles.rows(); ++t) {
      uv_triangles.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
    }
    Eigen::Matrix<double, Eigen::Dynamic, 2> uv(corners, 2);
    WebViewerOptions viewer = options.viewer;
    viewer.title += " (common refinement)";
    viewer.uv_weights = refinement->projective_uv.col(2);
    uv.col(0) = refinement->projective_uv.col(0).cwiseQuotient(viewer.uv_weights);
    uv.col(1) = refinement->projective_uv.col(1).cwiseQuotient(viewer.uv_weights);
    written.files.push_back((std::filesystem::path(folder) / "view.html").string());
    write_web_viewer(written.files.back(), mesh, uv_triangles, uv, viewer);
  }
  std::cerr << "pictures:";
  for (const std::string& file : written.files) std::cerr << " " << file;
  std::cerr << "\n";
  if (written.gradient_ran) {
    std::cerr << "  convergence plot: gradient flow " << written.gradient_iterations
              << " iterations (" << written.gradient_status << "), max |K-bar - K| "
              << written.gradient_max_error << "\n";
  }
}

void write_manifold_spline_pictures(const std::string& folder, const SplineResult& result) {
  if (folder.empty()) return;
  const SplinePicturesResult written = ricci::write_spline_pictures(folder, result);
  std::cerr << "pictures:";
  for (const std::string& file : written.files) std::cerr << " " << file;
  std::cerr << "\n";
}

Subcommand add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = add_render_subcommand(app, *args);
  return {cmd, [args] { return run_render(*args); }};
}

Subcommand add_view_command(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* cmd = add_view_subcommand(app, *args);
  return {cmd, [args] { return run_view(*args); }};
}

}  // namespace ricci::cli
