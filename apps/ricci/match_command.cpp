// `ricci match` and `ricci morph`: correspondences between two surfaces through their
// canonical domains (docs/matching.md), and morphs along them.
#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "command_support.hpp"
#include "commands.hpp"
#include "input_options.hpp"
#include "ricci/errors.hpp"
#include "ricci/hyperbolic/hyperbolic_param.hpp"
#include "ricci/match/match.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/mesh/topology.hpp"
#ifdef RICCI_HAVE_RENDER
#include "ricci/render/image.hpp"
#include "ricci/render/render_mesh.hpp"
#endif

namespace ricci::cli {
namespace {

struct MatchArgs {
  std::string a, b;
  InputArgs input;
  std::string output;     ///< MAP.txt (A -> B)
  std::string reverse;    ///< B -> A, when given
  std::string landmarks;  ///< file of "i j" lines
  std::string report;
  bool json = false;
  bool signature = false;
  bool progress = false;
};

struct MorphArgs {
  std::string a, b;
  InputArgs input;
  std::string output;  ///< folder
  std::string landmarks;
  int frames = 8;
  bool rigid = true;
  bool strip = true;
  bool progress = false;
};

nlohmann::json complex_json(std::complex<double> z) {
  return {z.real(), z.imag()};
}

// Landmark pairs "i j" (file vertex indices of A and B, 0-based), one a line; '#' comments.
std::vector<std::pair<int, int>> read_landmarks(const std::string& path, const ReadResult& a,
                                                const ReadResult& b) {
  std::ifstream in(path);
  if (!in) throw InvalidInput("--landmarks: cannot read " + path);
  const std::vector<int> to_a = inverse_map(a.vertex_map), to_b = inverse_map(b.vertex_map);
  std::vector<std::pair<int, int>> pairs;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = path + ":" + std::to_string(number) + ": ";
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    long long i = 0, j = 0;
    if (!(fields >> i)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      throw InvalidInput(where + "expected two vertex indices 'i j', got '" + line + "'");
    }
    std::string rest;
    if (!(fields >> j) || (fields >> rest)) {
      throw InvalidInput(where + "expected two vertex indices 'i j', got '" + line + "'");
    }
    const auto lookup = [&](long long v, const std::vector<int>& to_mesh, const char* mesh) {
      if (v < 0 || v >= static_cast<long long>(to_mesh.size()) ||
          to_mesh[static_cast<std::size_t>(v)] < 0) {
        throw InvalidInput(where + "vertex " + std::to_string(v) + " is not a vertex of " + mesh +
                           " used by a face");
      }
      return to_mesh[static_cast<std::size_t>(v)];
    };
    pairs.emplace_back(lookup(i, to_a, "A"), lookup(j, to_b, "B"));
  }
  if (pairs.empty()) throw InvalidInput("--landmarks: " + path + " holds no pairs");
  return pairs;
}

// One line per file vertex of the source: "face w0 w1 w2" (face of the target's triangles as
// read; -1 0 0 0 for a file vertex no face uses).
void write_map(const std::string& path, const std::string& source, const std::string& target,
               const ReadResult& from, const SurfaceMap& map) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "# ricci match: " << source << " -> " << target
        << "\n# one line per vertex of the first mesh: face of the second (0-based, its triangles "
           "as ricci reads them) and the barycentric weights of that face's corners\n";
    out << std::setprecision(17);
    const std::vector<int> to_mesh = inverse_map(from.vertex_map);
    for (int v = 0; v < from.file_vertices; ++v) {
      const int m =
          v < static_cast<int>(to_mesh.size()) ? to_mesh[static_cast<std::size_t>(v)] : -1;
      if (m < 0 || map.face(m) < 0) {
        out << "-1 0 0 0\n";
        continue;
      }
      out << map.face(m) << " " << map.weights(m, 0) << " " << map.weights(m, 1) << " "
          << map.weights(m, 2) << "\n";
    }
  });
}

// The conformal invariants of one surface: the torus modulus, the Fuchsian generators' traces.
nlohmann::json signature_of(const Mesh& mesh) {
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  nlohmann::json s;
  if (topology.components.size() != 1) {
    s["components"] = topology.components.size();
    return s;
  }
  const Component& c = topology.components.front();
  s["genus"] = c.genus;
  s["boundary_loops"] = c.num_boundary_loops;
  if (c.num_boundary_loops == 0 && c.genus == 0) {
    s["invariant"] = "none (every genus-0 closed surface is conformal to the sphere)";
  } else if (c.num_boundary_loops == 1 && c.genus == 0) {
    s["invariant"] = "none (every disk is conformal to the unit disk)";
  } else if (c.num_boundary_loops == 0 && c.genus == 1) {
    const CanonicalDomain d = canonical_domain(mesh);
    s["modulus"] = complex_json(d.modulus);
    s["converged"] = d.converged;
  } else if (c.num_boundary_loops == 0) {
    const HyperbolicParamResult h = parameterize_hyperbolic(mesh);
    s["converged"] = h.converged && h.has_group;
    if (h.has_group) {
      // |trace| of a_i and b_i (2 cosh(length / 2) of the closed geodesic in their class); they
      // depend on the homology basis the cut chose, so they compare surfaces cut alike.
      nlohmann::json traces = nlohmann::json::array();
      for (int i = 0; i < h.group.genus; ++i) {
        traces.push_back(std::abs(2 * h.group.a[static_cast<std::size_t>(i)].a.real()));
        traces.push_back(std::abs(2 * h.group.b[static_cast<std::size_t>(i)].a.real()));
      }
      s["fuchsian_traces"] = traces;
    } else {
      s["message"] = h.group_failure.empty() ? h.message : h.group_failure;
    }
  }
  return s;
}

nlohmann::json match_report(const MatchResult& m, const MatchArgs& args) {
  nlohmann::json r;
  r["a"] = args.a;
  r["b"] = args.b;
  r["domain"] = enum_name(m.domain);
  r["converged"] = m.converged;
  r["exact"] = m.exact;
  if (!m.message.empty()) r["message"] = m.message;
  r["alignment"] = {{"method", m.alignment.method},
                    {"factor_mismatch", m.alignment.factor_mismatch}};
  // The shape signature: what of each surface's conformal structure the domain keeps.
  for (const auto& [key, modulus] :
       {std::pair{"signature_a", m.modulus_a}, std::pair{"signature_b", m.modulus_b}}) {
    if (m.domain == DomainKind::Torus) {
      r[key] = {{"genus", 1}, {"boundary_loops", 0}, {"modulus", complex_json(modulus)}};
    } else {
      r[key] = {
          {"genus", 0},
          {"boundary_loops", m.domain == DomainKind::Disk ? 1 : 0},
          {"invariant", m.domain == DomainKind::Disk
                            ? "none (every disk is conformal to the unit disk)"
                            : "none (every genus-0 closed surface is conformal to the sphere)"}};
    }
  }
  if (m.domain == DomainKind::Torus) {
    r["alignment"]["affine_map"] = {
        {m.alignment.torus_linear(0, 0), m.alignment.torus_linear(0, 1)},
        {m.alignment.torus_linear(1, 0), m.alignment.torus_linear(1, 1)}};
    r["alignment"]["affine_distortion"] = m.alignment.torus_distortion;
    r["alignment"]["modulus_distance"] = m.alignment.modulus_distance;
    r["modulus_a"] = complex_json(m.modulus_a);
    r["modulus_b"] = complex_json(m.modulus_b);
  }
  nlohmann::json landmarks = nlohmann::json::array();
  for (const LandmarkResidual& l : m.landmarks) landmarks.push_back({{"distance", l.distance}});
  r["landmarks"] = {
      {"count", m.landmarks.size()},
      {"rms", m.landmark_rms},
      {"max", m.landmark_max},
      {"max_relative_to_b_diagonal", m.b_diagonal > 0 ? m.landmark_max / m.b_diagonal : 0.0},
      {"residuals", landmarks}};
  r["distortion"] = {{"angle_distortion_mean", m.distortion.angle_distortion_mean},
                     {"angle_distortion_max", m.distortion.angle_distortion_max},
                     {"area_distortion_energy", m.distortion.area_distortion_energy},
                     {"log_area_stddev", m.distortion.log_area_stddev},
                     {"log_area_min", m.distortion.log_area_min},
                     {"log_area_max", m.distortion.log_area_max},
                     {"flipped_faces", m.distortion.flipped_faces},
                     {"degenerate_faces", m.distortion.degenerate_faces}};
  r["outside"] = {{"forward", m.forward.outside}, {"max_weight_miss", m.forward.max_outside}};
  r["flow_iterations"] = {m.flow_iterations_a, m.flow_iterations_b};
  r["seconds"] = {{"domains", m.domain_seconds},
                  {"align", m.align_seconds},
                  {"locate", m.locate_seconds},
                  {"total", m.seconds}};
  return r;
}

void write_json(const std::string& path, const nlohmann::json& report) {
  write_file_atomically(path, [&](std::ostream& out) { out << report.dump(2) << "\n"; });
}

int run_match(const MatchArgs& args) {
  for (const std::string* out : {&args.output, &args.reverse, &args.report}) {
    if (!out->empty()) check_output_is_not_input(*out, {args.a, args.b});
  }
  const ReadResult a = read_input(args.a, args.input);
  const ReadResult b = read_input(args.b, args.input);
  print_warnings(a);
  print_warnings(b);
  if (args.signature) {
    nlohmann::json report = {{"a", args.a},
                             {"b", args.b},
                             {"signature_a", signature_of(a.mesh)},
                             {"signature_b", signature_of(b.mesh)}};
    if (!args.report.empty()) write_json(args.report, report);
    std::cout << report.dump(2) << "\n";
    return kOk;
  }
  if (args.output.empty())
    throw InvalidInput("ricci match: -o MAP.txt is required (or --signature)");
  MatchOptions options;
  if (!args.landmarks.empty()) options.landmarks = read_landmarks(args.landmarks, a, b);
  options.reverse = !args.reverse.empty();
  MatchResult m;
  try {
    m = run_with_progress(args.a + " -> " + args.b, args.progress, args.json, "match",
                          options.domain.flow,
                          [&] { return match_surfaces(a.mesh, b.mesh, options); });
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string(e.what()) +
                       "\n  try: ricci match A B --signature (the conformal invariants of any two "
                       "surfaces)");
  }
  nlohmann::json report = match_report(m, args);
  if (!m.converged) {
    if (!args.report.empty()) write_json(args.report, report);
    std::cerr << "error: the canonical maps did not converge: " << m.message << "\n";
    return kNotConverged;
  }
  write_map(args.output, args.a, args.b, a, m.forward);
  if (!args.reverse.empty()) write_map(args.reverse, args.b, args.a, b, m.backward);
  if (!args.report.empty()) write_json(args.report, report);
  if (args.json) {
    std::cout << report.dump(2) << "\n";
  } else {
    std::cout << args.a << " -> " << args.b << ": " << enum_name(m.domain) << ", aligned by "
              << m.alignment.method << "\n";
    if (!m.landmarks.empty()) {
      std::cout << "  landmarks: " << m.landmarks.size() << ", residual rms " << m.landmark_rms
                << " max " << m.landmark_max << " (" << m.landmark_max / m.b_diagonal
                << " of B's diagonal)\n";
    }
    if (m.domain == DomainKind::Torus) {
      std::cout << "  moduli " << m.modulus_a.real() << std::showpos << m.modulus_a.imag()
                << "i and " << std::noshowpos << m.modulus_b.real() << std::showpos
                << m.modulus_b.imag() << std::noshowpos << "i: distance "
                << m.alignment.modulus_distance << ", affine distortion "
                << m.alignment.torus_distortion << "\n";
    }
    std::cout << "  map: angle distortion mean " << m.distortion.angle_distortion_mean << " max "
              << m.distortion.angle_distortion_max << ", log area stddev "
              << m.distortion.log_area_stddev << ", flipped " << m.distortion.flipped_faces << ", "
              << m.seconds << " s\n  wrote " << args.output << "\n";
    if (!args.reverse.empty()) std::cout << "  wrote " << args.reverse << "\n";
  }
  return kOk;
}

#ifdef RICCI_HAVE_RENDER
// A checkerboard from A's two widest bounding-box axes, the same texture on every frame.
Eigen::Matrix<double, Eigen::Dynamic, 2> checker_coordinates(const Positions& p) {
  const Eigen::RowVector3d lo = p.colwise().minCoeff(), hi = p.colwise().maxCoeff();
  const Eigen::RowVector3d extent = hi - lo;
  int first = 0;
  extent.maxCoeff(&first);
  int second = (first + 1) % 3;
  if (extent((first + 2) % 3) > extent(second)) second = (first + 2) % 3;
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv(p.rows(), 2);
  const double scale = extent(first) > 0 ? 1 / extent(first) : 1;
  uv.col(0) = (p.col(first).array() - lo(first)) * scale;
  uv.col(1) = (p.col(second).array() - lo(second)) * scale;
  return uv;
}

void write_strip(const std::string& path, const Mesh& a, const std::vector<Positions>& frames) {
  const int side = 256;
  Positions all(static_cast<Eigen::Index>(frames.size()) * a.positions.rows(), 3);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    all.middleRows(static_cast<Eigen::Index>(k) * a.positions.rows(), a.positions.rows()) =
        frames[k];
  }
  RenderOptions options;
  options.width = options.height = side;
  options.checker = 8;
  options.draw_seams = false;
  options.mark_cones = false;
  options.smooth_shading = true;
  Mesh first = a;
  first.positions = frames.front();
  options.camera = fit_camera(first, options, all);
  const auto uv = checker_coordinates(a.positions);
  Image strip = make_image(side * static_cast<int>(frames.size()), side, Rgb{1, 1, 1});
  for (std::size_t k = 0; k < frames.size(); ++k) {
    Mesh frame = a;
    frame.positions = frames[k];
    const RenderResult picture = render_textured_mesh(frame, a.triangles, uv, options);
    for (int y = 0; y < side; ++y) {
      for (int x = 0; x < side; ++x) {
        strip.pixels[static_cast<std::size_t>(y) * strip.width +
                     static_cast<std::size_t>(k) * side + x] = picture.image.at(x, y);
      }
    }
  }
  write_png(path, strip);
}
#endif

int run_morph(const MorphArgs& args) {
  if (args.frames < 2)
    throw InvalidInput("--frames must be at least 2, not " + std::to_string(args.frames));
  namespace fs = std::filesystem;
  const ReadResult a = read_input(args.a, args.input);
  const ReadResult b = read_input(args.b, args.input);
  print_warnings(a);
  print_warnings(b);
  MatchOptions options;
  if (!args.landmarks.empty()) options.landmarks = read_landmarks(args.landmarks, a, b);
  const MatchResult m = run_with_progress(args.a + " -> " + args.b, args.progress, false, "match",
                                          options.domain.flow,
                                          [&] { return match_surfaces(a.mesh, b.mesh, options); });
  if (!m.converged) {
    std::cerr << "error: the canonical maps did not converge: " << m.message << "\n";
    return kNotConverged;
  }
  const std::vector<Positions> frames =
      morph_frames(a.mesh, mapped_positions(b.mesh, m.forward), args.frames, args.rigid);
  // Everything is written into a scratch folder beside the output first and moved in only when
  // all of it was written: a failure leaves no partial set of frames.
  const fs::path out(args.output);
  std::error_code error;
  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  fs::create_directories(parent, error);
  std::string scratch_name = (parent / ("." + out.filename().string() + ".partXXXXXX")).string();
  if (mkdtemp(scratch_name.data()) == nullptr) {
    throw IoError(args.output + ": cannot create a folder beside it (" +
                  std::error_code(errno, std::generic_category()).message() + ")");
  }
  const fs::path scratch(scratch_name);
  std::vector<std::string> names;
  try {
    for (std::size_t k = 0; k < frames.size(); ++k) {
      std::ostringstream name;
      name << "frame_" << std::setw(3) << std::setfill('0') << k << ".obj";
      check_output_is_not_input((out / name.str()).string(), {args.a, args.b});
      Mesh frame = a.mesh;
      frame.positions = frames[k];
      write_obj((scratch / name.str()).string(), frame);
      names.push_back(name.str());
    }
#ifdef RICCI_HAVE_RENDER
    if (args.strip) {
      write_strip((scratch / "strip.png").string(), a.mesh, frames);
      names.emplace_back("strip.png");
    }
#endif
    fs::create_directories(out, error);
    if (error || !fs::is_directory(out)) {
      throw IoError(args.output + ": cannot create the output folder (" + error.message() + ")");
    }
    for (const std::string& name : names) fs::rename(scratch / name, out / name);
  } catch (...) {
    fs::remove_all(scratch, error);
    throw;
  }
  fs::remove_all(scratch, error);
  std::vector<std::string> written;
  written.reserve(names.size());
  for (const std::string& name : names) written.push_back((out / name).string());
  std::cout << args.a << " -> " << args.b << ": " << frames.size() << " frames ("
            << enum_name(m.domain) << ", " << m.alignment.method << "), map angle distortion mean "
            << m.distortion.angle_distortion_mean << "\n";
  for (const std::string& w : written) std::cout << "  wrote " << w << "\n";
  return kOk;
}

}  // namespace

Subcommand add_match_command(CLI::App& app) {
  auto args = std::make_shared<MatchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "match",
      "Correspondence between two surfaces of the same topology through their conformal maps "
      "(docs/matching.md): closed genus 0 on the sphere (aligned by a Moebius transformation "
      "fitted to landmarks, or the centre of mass of the area and the rotation that best aligns "
      "the conformal factors), disks on the unit disk, closed genus 1 on their flat tori "
      "(aligned by the lattices; the affine map between them when the moduli differ). Writes "
      "one line 'face w0 w1 w2' per vertex of A: the face of B and barycentric weights.");
  cmd->add_option("A", args->a, "first mesh (.obj .off .ply .stl)")->required();
  cmd->add_option("B", args->b, "second mesh, same topology")->required();
  cmd->add_option("-o,--output", args->output, "the map A -> B (text, one line per vertex of A)");
  cmd->add_option("--reverse", args->reverse, "also write the map B -> A here");
  cmd->add_option("--landmarks", args->landmarks,
                  "file of 'i j' lines: vertex i of A (0-based, file order) goes to vertex j of B");
  cmd->add_option("--report", args->report,
                  "JSON report: alignment, landmark residuals, the map's distortion, moduli");
  cmd->add_flag("--json", args->json, "print the report as JSON");
  cmd->add_flag("--signature", args->signature,
                "only the conformal invariants of A and B (torus modulus, Fuchsian traces of "
                "genus >= 2), for any topology");
  cmd->add_flag("--progress", args->progress, "print the flows' iterations on stderr");
  add_input_options(cmd, args->input);
  return {cmd, [args] { return run_match(*args); }};
}

Subcommand add_morph_command(CLI::App& app) {
  auto args = std::make_shared<MorphArgs>();
  CLI::App* cmd = app.add_subcommand(
      "morph",
      "Morph from A to B along their conformal correspondence (ricci match): N meshes with A's "
      "faces, positions interpolated linearly, B first moved rigidly onto A; and a picture strip "
      "(strip.png) with one checkerboard carried through every frame.");
  cmd->add_option("A", args->a, "first mesh")->required();
  cmd->add_option("B", args->b, "second mesh, same topology")->required();
  cmd->add_option("-o,--output", args->output, "output folder (frame_000.obj ...)")->required();
  cmd->add_option("--frames", args->frames, "number of frames, A and B included")
      ->capture_default_str();
  cmd->add_option("--landmarks", args->landmarks, "as for ricci match");
  cmd->add_flag("!--no-align", args->rigid, "keep B where it is (no rigid fit onto A)");
  cmd->add_flag("!--no-strip", args->strip, "write no picture strip");
  cmd->add_flag("--progress", args->progress, "print the flows' iterations on stderr");
  add_input_options(cmd, args->input);
  return {cmd, [args] { return run_morph(*args); }};
}

}  // namespace ricci::cli
