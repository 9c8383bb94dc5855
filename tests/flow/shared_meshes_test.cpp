// Newton's flow on every manifold mesh of ../shared/meshes (skipped when the folder is missing):
// closed surfaces to the uniform target 2 pi chi / n (flat for genus 1), surfaces with boundary
// to the flat metric with free boundary and, for disks, with the disk boundary too.
#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/io.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

void expect_converged(const MeshFlowResult& r, const std::string& what) {
  EXPECT_TRUE(r.converged) << what << ": "
                           << (r.components.empty() ? "" : r.components[0].flow.message);
  EXPECT_LE(r.max_error, 1e-10) << what;
  for (const ComponentFlow& c : r.components) {
    EXPECT_LT(c.flow.gauss_bonnet_relative_error, 1e-12) << what;
    EXPECT_LE(c.flow.iterations, 30) << what;
  }
}

TEST(SharedMeshes, NewtonConvergesOnEveryManifoldMesh) {
  RICCI_REQUIRE_SHARED_MESHES();
  int solved = 0;
  for (const auto& shared : testing::shared_meshes()) {
    if (!shared.manifold) continue;
    ReadResult read;
    try {
      read = read_mesh(shared.path);
    } catch (const InvalidInput& e) {
      // Meshes with zero-area faces cannot carry a metric: they must be refused, not solved.
      EXPECT_NE(std::string(e.what()).find("zero area"), std::string::npos) << e.what();
      continue;
    }
    MeshFlowOptions options;
    if (shared.boundary_loops == 0) {
      options.target.kind = TargetKind::Uniform;
      try {
        expect_converged(flow_mesh(read.mesh, options), shared.file + " uniform");
      } catch (const InvalidInput& e) {
        // The Thurston fit may set Phi = pi/2 on every edge around a low-valence vertex, and the
        // single-vertex bound then forbids negative curvature there (fertility.off has such a
        // valence-4 vertex). The message says so; the tangential packing (Phi = 0) has the
        // widest bound and must then succeed.
        EXPECT_NE(std::string(e.what()).find("single-vertex bound"), std::string::npos)
            << shared.file << ": " << e.what();
        options.structure.scheme = Scheme::Tangential;
        expect_converged(flow_mesh(read.mesh, options), shared.file + " uniform, tangential");
      }
    } else {
      options.target.boundary = BoundaryMode::Free;
      expect_converged(flow_mesh(read.mesh, options), shared.file + " free boundary");
      if (shared.boundary_loops == 1 && shared.genus == 0) {
        options.target.boundary = BoundaryMode::DiskUniform;
        expect_converged(flow_mesh(read.mesh, options), shared.file + " disk boundary");
      }
    }
    ++solved;
  }
  EXPECT_GE(solved, 10);
}

}  // namespace
}  // namespace ricci
