/// Hyperbolic uniformization with and without intrinsic Delaunay flips (docs/hyperbolic.md), one
/// line per mesh and variant:
///
///   ricci_hyperbolic_flips [--meshes DIR] [--only NAME] [--skip-large] [--param] [--verbose]
///
/// Meshes: generated closed surfaces of genus 2, 3, 5 and 20; eight.off, 3holes.off and
/// fertility.off from DIR (default ../shared/meshes); and hard cases made from generated ones
/// (tests/support/hard_meshes.hpp): valence-3 spikes, 0.1-degree needles, both together, and a
/// 100k-face genus-2 surface with scan-like tangential noise (--skip-large leaves it out).
/// Variants: the default Thurston packing, vertex scaling with flips off, vertex scaling with
/// flips (Auto). With --param, parameterize_hyperbolic with Thurston and with vertex scaling
/// (flips) as well: relation residual of the Fuchsian group, cuts tried, flipped faces, time.
///
/// Prints a tab-separated table (mesh, vertices, faces, variant, status, iterations, max_error,
/// flips, seconds, extra); exits 0 whatever the outcome.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/hyperbolic/hyperbolic_param.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "support/hard_meshes.hpp"

namespace {

using Clock = std::chrono::steady_clock;
bool verbose = false;

struct Case {
  std::string name;
  ricci::Mesh mesh;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void run_flow(const Case& c, const char* variant, ricci::Scheme scheme, ricci::EdgeFlips flips) {
  ricci::MeshFlowOptions o;
  o.structure.scheme = scheme;
  o.structure.geometry = ricci::Geometry::Hyperbolic;
  o.target.boundary = ricci::BoundaryMode::Geodesic;
  o.flow.flips = flips;
  if (verbose) {
    o.flow.progress = [](const ricci::IterationRecord& r) {
      std::fprintf(stderr, "  iteration %3d  max error %.3e  step %.3g  flips %d  %.2f s\n",
                   r.iteration, r.max_error, r.step_length, r.flips, r.seconds);
      return true;
    };
  }
  const auto start = Clock::now();
  try {
    const ricci::MeshFlowResult r = ricci::flow_mesh(c.mesh, o);
    const ricci::FlowResult& f = r.components.front().flow;
    std::printf("%s\t%d\t%d\t%s\t%s\t%d\t%.3g\t%d\t%.2f\t%s\n", c.name.c_str(),
                c.mesh.num_vertices(), c.mesh.num_faces(), variant,
                ricci::flow_status_name(f.status), f.iterations, f.max_error, f.intrinsic.flips(),
                seconds_since(start),
                ("isometric " + std::to_string(f.intrinsic.isometric_flips()) + ", area " +
                 std::to_string(f.total_area))
                    .c_str());
  } catch (const ricci::Error& e) {
    std::printf("%s\t%d\t%d\t%s\terror\t0\tnan\t0\t%.2f\t%s\n", c.name.c_str(),
                c.mesh.num_vertices(), c.mesh.num_faces(), variant, seconds_since(start), e.what());
  }
  std::fflush(stdout);
}

void run_param(const Case& c, const char* variant, ricci::Scheme scheme) {
  ricci::HyperbolicParamOptions o;
  o.structure.scheme = scheme;
  const auto start = Clock::now();
  try {
    const ricci::HyperbolicParamResult r = ricci::parameterize_hyperbolic(c.mesh, o);
    const ricci::FlowResult& f = r.flow.components.front().flow;
    char extra[256];
    std::snprintf(extra, sizeof extra,
                  "relation %.2g, nodes %.2g, cuts %d, length error %.2g, flipped faces %d, "
                  "development mismatch %.2g, |z| max %.4f",
                  r.group.relation_residual, r.group.node_residual, r.cut_candidates_tried,
                  r.layout.max_length_relative_error, r.layout.num_flipped_faces,
                  r.development_length_mismatch, r.layout.max_radius);
    std::printf("%s\t%d\t%d\t%s\t%s\t%d\t%.3g\t%d\t%.2f\t%s\n", c.name.c_str(),
                c.mesh.num_vertices(), c.mesh.num_faces(), variant,
                ricci::flow_status_name(f.status), f.iterations, f.max_error, f.intrinsic.flips(),
                seconds_since(start), r.converged ? extra : r.message.c_str());
  } catch (const ricci::Error& e) {
    std::printf("%s\t%d\t%d\t%s\terror\t0\tnan\t0\t%.2f\t%s\n", c.name.c_str(),
                c.mesh.num_vertices(), c.mesh.num_faces(), variant, seconds_since(start), e.what());
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string meshes = "../shared/meshes", only;
  bool skip_large = false, param = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--meshes" && i + 1 < argc) {
      meshes = argv[++i];
    } else if (a == "--only" && i + 1 < argc) {
      only = argv[++i];
    } else if (a == "--skip-large") {
      skip_large = true;
    } else if (a == "--param") {
      param = true;
    } else if (a == "--verbose") {
      verbose = true;
    } else {
      std::fprintf(stderr,
                   "usage: ricci_hyperbolic_flips [--meshes DIR] [--only NAME] [--skip-large] "
                   "[--param] [--verbose]\n");
      return 2;
    }
  }
  using namespace ricci;
  std::vector<Case> cases;
  auto add = [&](const std::string& name, auto make) {
    if (only.empty() || only == name) cases.push_back({name, make()});
  };
  add("genus2", [] { return make_closed_surface(2, 12); });
  add("genus3", [] { return make_closed_surface(3, 14); });
  add("genus5", [] { return make_closed_surface(5, 22); });
  add("genus20", [] { return make_closed_surface(20, 82); });
  for (const char* file : {"eight.off", "3holes.off", "fertility.off"}) {
    const std::filesystem::path path = std::filesystem::path(meshes) / file;
    if (std::filesystem::exists(path)) add(file, [&] { return read_mesh(path.string()).mesh; });
  }
  add("genus2-spikes",
      [] { return testing::with_valence3_spikes(make_closed_surface(2, 12), 5, 1.0); });
  add("genus2-needles",
      [] { return testing::with_needles(make_closed_surface(2, 12), 3, 0.0017); });
  add("genus3-spikes-needles", [] {
    return testing::with_needles(testing::with_valence3_spikes(make_closed_surface(3, 14), 4, 1.0),
                                 4, 0.0017);
  });
  if (!skip_large) {
    add("genus2-noisy-100k",
        [] { return testing::jitter_tangentially(make_closed_surface(2, 160), 0.45, 1); });
  }
  std::printf(
      "mesh\tvertices\tfaces\tvariant\tstatus\titerations\tmax_error\tflips\tseconds\textra\n");
  for (const Case& c : cases) {
    run_flow(c, "thurston", Scheme::Thurston, EdgeFlips::Auto);
    run_flow(c, "vertex-scaling-no-flips", Scheme::VertexScaling, EdgeFlips::Off);
    run_flow(c, "vertex-scaling-flips", Scheme::VertexScaling, EdgeFlips::Auto);
    if (param) {
      run_param(c, "param-thurston", Scheme::Thurston);
      run_param(c, "param-vertex-scaling-flips", Scheme::VertexScaling);
    }
  }
  return 0;
}
