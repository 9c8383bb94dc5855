/// The robustness stress suite (issue 5): many flows on hard targets, one line per case.
///
///   ricci_stress [--sphere-runs N] [--meshes DIR] [--seed S] [--flips auto|off|delaunay]
///                [--skip-sphere] [--skip-meshes] [--only MESH] [--verbose]
///
/// 1. On a 10242-vertex icosphere, N random admissible cone sets (default 1000): 3 to 12 cones at
///    distinct random vertices, curvatures drawn uniformly in [-pi, 1.5 pi] and shifted to sum to
///    4 pi, redrawn while one reaches 2 pi - 0.05 (a cone angle under 0.05 rad) or goes below
///    -3 pi; vertex scaling with intrinsic Delaunay flips, Newton to 1e-10.
/// 2. On every manifold mesh of DIR/MANIFEST.tsv (default ../shared/meshes): the parameterization
///    with automatic cones (Thurston, the default, and vertex scaling with flips), and a random
///    admissible target for vertex scaling with flips: uniform noise in [-0.25, 0.25] rad added
///    to 2 pi chi / n (closed) or to the input's curvature (with boundary; boundary vertices of
///    one face excepted), the noise's mean removed so that Gauss-Bonnet holds.
///
/// Prints a tab-separated table (suite, case, vertices, success, status, iterations, max_error,
/// flips, seconds, note) and a summary; exits 0 whatever the outcome (a stress suite reports, it
/// does not gate).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/param/parameterize.hpp"
#include "support/random_targets.hpp"

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;

struct Row {
  std::string suite, name;
  int vertices = 0;
  bool success = false;
  std::string status;
  int iterations = 0;
  double max_error = 0;
  int flips = 0;
  double seconds = 0;
  std::string note;
};

std::vector<Row> rows;
bool verbose = false;
ricci::EdgeFlips flips_mode = ricci::EdgeFlips::Auto;  // --flips
std::string only;  // --only: one shared mesh  // --verbose: every flow iteration on stderr

ricci::FlowProgress progress() {
  if (!verbose) return {};
  return [](const ricci::IterationRecord& r) {
    std::fprintf(stderr,
                 "  iteration %3d  max error %.3e  step %.3g  backtracks %d  flips %d  %.2f s\n",
                 r.iteration, r.max_error, r.step_length, r.backtracks, r.flips, r.seconds);
    return true;
  };
}

void print(const Row& r) {
  std::printf("%s\t%s\t%d\t%s\t%s\t%d\t%.3g\t%d\t%.3f\t%s\n", r.suite.c_str(), r.name.c_str(),
              r.vertices, r.success ? "yes" : "no", r.status.c_str(), r.iterations, r.max_error,
              r.flips, r.seconds, r.note.c_str());
  std::fflush(stdout);
  rows.push_back(r);
}

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Iterations over all components (the flows run one after another).
int total_iterations(const ricci::MeshFlowResult& r) {
  int n = 0;
  for (const auto& c : r.components) n += c.flow.iterations;
  return n;
}

std::string first_failure(const ricci::MeshFlowResult& r) {
  for (const auto& c : r.components) {
    if (!c.flow.converged) return ricci::flow_status_name(c.flow.status);
  }
  return "converged";
}

/// Runs a vertex-scaling flow (flips as --flips says), fills the row's outcome and prints it.
void run_flow_case(Row row, const ricci::Mesh& mesh, ricci::MeshFlowOptions options) {
  options.structure.scheme = ricci::Scheme::VertexScaling;
  options.flow.progress = progress();
  options.flow.flips = flips_mode;
  const auto start = Clock::now();
  try {
    const ricci::MeshFlowResult r = ricci::flow_mesh(mesh, options);
    row.success = r.converged;
    row.status = first_failure(r);
    row.iterations = total_iterations(r);
    row.max_error = r.max_error;
    row.flips = r.intrinsic.flips();
    for (const auto& c : r.components) {
      if (!c.flow.converged) row.note += (row.note.empty() ? "" : " ") + c.flow.message;
    }
  } catch (const std::exception& e) {
    row.status = "exception";
    row.note += (row.note.empty() ? "" : " ") + std::string(e.what());
  }
  row.seconds = seconds_since(start);
  print(row);
}

std::vector<ricci::Cone> random_cones(const ricci::Mesh& sphere, std::mt19937_64& random,
                                      std::string& text) {
  const std::vector<ricci::Cone> cones =
      ricci::testing::random_sphere_cones(sphere.num_vertices(), random);
  std::ostringstream out;
  out.precision(4);
  for (std::size_t i = 0; i < cones.size(); ++i) {
    out << (i ? "," : "") << cones[i].vertex << ":" << cones[i].curvature / kPi << "pi";
  }
  text = out.str();
  return cones;
}

void sphere_suite(int runs, std::uint64_t seed) {
  const ricci::Mesh sphere = ricci::make_icosphere(5);
  for (int run = 0; run < runs; ++run) {
    std::mt19937_64 random(seed + static_cast<std::uint64_t>(run));
    Row row;
    row.suite = "sphere-cones";
    row.name = "run " + std::to_string(run);
    row.vertices = sphere.num_vertices();
    ricci::MeshFlowOptions options;
    options.target.kind = ricci::TargetKind::Flat;
    options.target.cones = random_cones(sphere, random, row.note);
    run_flow_case(row, sphere, options);
  }
}

/// Manifold meshes named by the manifest (column `manifold` = yes).
std::vector<std::string> manifold_meshes(const std::filesystem::path& dir) {
  std::ifstream in(dir / "MANIFEST.tsv");
  std::vector<std::string> names;
  std::string line;
  int manifold_column = -1;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream split(line);
    for (std::string cell; std::getline(split, cell, '\t');) cells.push_back(cell);
    if (manifold_column < 0) {
      const auto it = std::find(cells.begin(), cells.end(), "manifold");
      manifold_column = it == cells.end() ? -2 : static_cast<int>(it - cells.begin());
      continue;
    }
    if (manifold_column >= 0 && static_cast<int>(cells.size()) > manifold_column &&
        cells[manifold_column] == "yes") {
      names.push_back(cells[0]);
    }
  }
  return names;
}

void param_case(const std::string& name, const ricci::Mesh& mesh, ricci::Scheme scheme) {
  Row row;
  row.suite = std::string("auto-cones-") + ricci::scheme_name(scheme);
  row.name = name;
  row.vertices = mesh.num_vertices();
  ricci::ParamOptions options;
  options.structure.scheme = scheme;
  if (scheme == ricci::Scheme::VertexScaling) options.flow.flips = flips_mode;
  const auto start = Clock::now();
  try {
    const ricci::MeshParamResult r = ricci::parameterize(mesh, options);
    row.success = r.converged && r.distortion.flipped_faces == 0;
    row.status = r.converged ? "converged" : first_failure(r.flow);
    row.iterations = total_iterations(r.flow);
    row.max_error = r.flow.max_error;
    row.flips = r.flow.intrinsic.flips();
    std::ostringstream note;
    note << r.cones.size() << " cones, " << r.edge_splits << " edge splits"
         << (r.subdivided ? " (subdivided)" : "") << ", " << r.distortion.flipped_faces
         << " flipped uv faces";
    if (!r.converged) note << ": " << r.message;
    row.note = note.str();
  } catch (const std::exception& e) {
    row.status = "exception";
    row.note = e.what();
  }
  row.seconds = seconds_since(start);
  print(row);
}

void random_target_case(const std::string& name, const ricci::Mesh& mesh, std::uint64_t seed) {
  Row row;
  row.suite = "random-target-vertex-scaling";
  row.name = name;
  row.vertices = mesh.num_vertices();
  const ricci::Topology t = ricci::build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd values = ricci::testing::random_admissible_curvature(mesh, t, seed);
  ricci::MeshFlowOptions options;
  options.target.kind = ricci::TargetKind::Values;
  options.target.values = values;
  run_flow_case(row, mesh, options);
}

void mesh_suite(const std::filesystem::path& dir, std::uint64_t seed) {
  if (!std::filesystem::exists(dir / "MANIFEST.tsv")) {
    std::fprintf(stderr, "ricci_stress: no %s: skipping the shared meshes\n",
                 (dir / "MANIFEST.tsv").c_str());
    return;
  }
  for (const std::string& name : manifold_meshes(dir)) {
    if (!only.empty() && name != only) continue;
    ricci::Mesh mesh;
    try {
      mesh = ricci::read_mesh((dir / name).string()).mesh;
    } catch (const std::exception& e) {
      Row row;
      row.suite = "input";
      row.name = name;
      row.status = "rejected";
      row.success = true;  // a clear error is the right answer for a broken file
      row.note = e.what();
      print(row);
      continue;
    }
    const ricci::Topology t = ricci::build_topology(mesh.triangles, mesh.num_vertices());
    if (t.components.size() == 1) {
      param_case(name, mesh, ricci::Scheme::Thurston);
      param_case(name, mesh, ricci::Scheme::VertexScaling);
    }
    random_target_case(name, mesh, seed);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int sphere_runs = 1000;
  std::filesystem::path meshes = "../shared/meshes";
  std::uint64_t seed = 20261123;
  bool sphere = true, shared = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "ricci_stress: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--sphere-runs") {
      sphere_runs = std::stoi(value());
    } else if (a == "--meshes") {
      meshes = value();
    } else if (a == "--seed") {
      seed = std::stoull(value());
    } else if (a == "--skip-sphere") {
      sphere = false;
    } else if (a == "--only") {
      only = value();
    } else if (a == "--flips") {
      flips_mode = ricci::parse_edge_flips(value());
    } else if (a == "--verbose") {
      verbose = true;
    } else if (a == "--skip-meshes") {
      shared = false;
    } else {
      std::fprintf(stderr,
                   "usage: ricci_stress [--sphere-runs N] [--meshes DIR] [--seed S] "
                   "[--flips auto|off|delaunay] [--skip-sphere] [--skip-meshes] [--only MESH] "
                   "[--verbose]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  std::printf(
      "suite\tcase\tvertices\tsuccess\tstatus\titerations\tmax_error\tflips\tseconds\tnote\n");
  if (shared) mesh_suite(meshes, seed);
  if (sphere) sphere_suite(sphere_runs, seed);

  // Summary per suite: successes, and the slowest case.
  std::vector<std::string> suites;
  for (const Row& r : rows) {
    if (std::find(suites.begin(), suites.end(), r.suite) == suites.end()) suites.push_back(r.suite);
  }
  for (const std::string& s : suites) {
    int n = 0, ok = 0;
    const Row* slowest = nullptr;
    double worst_error = 0;
    for (const Row& r : rows) {
      if (r.suite != s) continue;
      ++n;
      ok += r.success;
      if (r.success) worst_error = std::max(worst_error, r.max_error);
      if (!slowest || r.seconds > slowest->seconds) slowest = &r;
    }
    std::fprintf(stderr,
                 "# %s: %d/%d succeeded; largest final error of a success %.3g; slowest %s "
                 "(%.2f s)\n",
                 s.c_str(), ok, n, worst_error, slowest->name.c_str(), slowest->seconds);
  }
  return 0;
}
