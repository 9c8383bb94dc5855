// The parameterisation's set-up with automatic cones: how many times the topology, the input
// lengths, the conformal structure and the cone model (the flow linearised at the input metric,
// factorised) are built in one `parameterize` run, and the wall time spent building them
// (ricci/mesh/build_counts.hpp), beside the run's total.
//
// The same source builds against older trees that carry the counters, so a before/after ratio
// comes from one invocation of each binary on the same machine (docs/architecture.md).
//
//   build/bench/ricci_param_setup                     # generated genus-3 surface, about 102k faces
//   build/bench/ricci_param_setup MESH.obj [runs] [scheme]   # MESH "-": the generated one
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ricci/mesh/build_counts.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/param/parameterize.hpp"

int main(int argc, char** argv) {
  const ricci::Mesh mesh = argc > 1 && std::string(argv[1]) != "-"
                               ? ricci::read_mesh(argv[1]).mesh
                               : ricci::make_closed_surface(3, 190);
  const int runs = argc > 2 ? std::atoi(argv[2]) : 3;
  ricci::ParamOptions options;
  options.cone_mode = ricci::ConeMode::Auto;
  if (argc > 3) options.structure.scheme = ricci::parse_scheme(argv[3]);
  std::printf("mesh: %d vertices, %d faces; %d runs (medians)\n", mesh.num_vertices(),
              mesh.num_faces(), runs);
  std::vector<double> setup, total;
  ricci::BuildCounts counts;
  for (int run = 0; run < runs; ++run) {
    const ricci::BuildCounts before = ricci::build_counts();
    const auto start = std::chrono::steady_clock::now();
    const ricci::MeshParamResult result = ricci::parameterize(mesh, options);
    total.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    counts = ricci::build_counts() - before;
    setup.push_back(counts.seconds);
    if (!result.converged)
      std::printf("run %d did not converge: %s\n", run, result.message.c_str());
    std::printf("run %d: %zu cones, %d cone rounds\n", run, result.cones.size(),
                result.routes.front().pipeline.cone_rounds);
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf(
      "builds per run: topology %ld (%ld of them cut meshes), input lengths %ld, structure %ld, "
      "cone model %ld\n",
      counts.topologies, counts.cut_meshes, counts.input_lengths, counts.structures,
      counts.cone_models);
  std::printf("set-up seconds %.4f of %.4f total\n", median(setup), median(total));
  return 0;
}
