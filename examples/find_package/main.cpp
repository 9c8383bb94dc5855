// Flattens a torus with the installed ricci: exit 0 iff the flow converged to 1e-10.
#include <cstdio>
#include <exception>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/generate.hpp"

int main() {
  try {
    const ricci::Mesh torus = ricci::make_torus(24, 12);
    ricci::MeshFlowOptions options;  // flat target, Newton, tolerance 1e-10
    const ricci::MeshFlowResult result = ricci::flow_mesh(torus, options);
    const bool ok = result.converged && result.max_error <= 1e-10;
    std::printf("torus: %d vertices, %d faces; converged %s, max error %.3g, %.3f s\n",
                torus.num_vertices(), torus.num_faces(), result.converged ? "yes" : "no",
                result.max_error, result.total_seconds);
    return ok ? 0 : 1;
  } catch (const ricci::Error& e) {
    std::fprintf(stderr, "ricci: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
