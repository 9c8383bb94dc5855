// The parameterization pipeline builds the mesh's connectivity, input lengths, conformal
// structure and cone model once per run, whatever the cone mode (ricci/flow/flow_problem.hpp),
// counted by ricci/mesh/build_counts.hpp. Before the FlowProblem, a run with automatic cones built
// the topology 3 times, the input lengths 4 and the structure 3 (Thurston: the radius fit three
// times), plus once more per round of automatic cones.
#include <gtest/gtest.h>

#include "ricci/mesh/build_counts.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/hard_cases.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci {
namespace {

/// parameterize, with the builds it made.
BuildCounts builds_of(const Mesh& mesh, const ParamOptions& options,
                      MeshParamResult* out = nullptr) {
  const BuildCounts before = build_counts();
  MeshParamResult r = parameterize(mesh, options);
  const BuildCounts made = build_counts() - before;
  EXPECT_TRUE(r.converged) << r.message;
  if (out) *out = std::move(r);
  return made;
}

/// One structure, one set of input lengths, one topology of the input (the others are cut
/// meshes: one through the final cones, and one through the first when the cut made beside the
/// first flow was overtaken by a round of more cones).
void expect_built_once(const BuildCounts& made, long cone_models, const std::string& what) {
  EXPECT_EQ(made.topologies - made.cut_meshes, 1) << what << ": the input's";
  EXPECT_LE(made.cut_meshes, 2) << what;
  EXPECT_EQ(made.input_lengths, 1) << what;
  EXPECT_EQ(made.structures, 1) << what;
  EXPECT_EQ(made.cone_models, cone_models) << what;
}

TEST(PipelineBuilds, AutomaticConesBuildEachThingOnce) {
  ParamOptions options;
  options.cone_mode = ConeMode::Auto;
  expect_built_once(builds_of(make_icosphere(3), options), 1, "icosphere, automatic cones");
}

TEST(PipelineBuilds, RoundsOfAutomaticConesReuseTheProblemAndTheModel) {
  // The CAD cylinder needs rounds of more cones (see parameterize_test.cpp); each round used to
  // build the topology, the lengths, the structure and the cone model again.
  MeshParamResult r;
  const BuildCounts made = builds_of(make_cad_cylinder(360), ParamOptions{}, &r);
  ASSERT_GE(r.routes.front().pipeline.cone_rounds, 1);
  expect_built_once(made, 1, "CAD cylinder with rounds");
}

TEST(PipelineBuilds, EveryConeModeBuildsTheStructureOnce) {
  ParamOptions none;
  none.cone_mode = ConeMode::None;
  expect_built_once(builds_of(make_disk(8), none), 0, "disk, no cones");
  ParamOptions one;
  one.cone_mode = ConeMode::OneCone;
  // One cone of -4 pi on ten segments folds faces around it: the charts route would build the
  // topology again for each chart; the exact pipeline's builds are the ones counted here.
  one.fold_free.charts = false;
  expect_built_once(builds_of(make_closed_surface(2, 10), one), 1, "genus 2, one cone");
  ParamOptions user;
  user.cone_mode = ConeMode::User;
  const Mesh sphere = make_icosphere(2);
  for (int v : {0, 1, 2, 3}) user.cones.push_back({v, 3.14159265358979323846});
  expect_built_once(builds_of(sphere, user), 0, "sphere, the user's cones");
  ParamOptions torus;  // needed: none on a torus
  expect_built_once(builds_of(make_torus(24, 12), torus), 0, "torus");
}

TEST(PipelineBuilds, ThurstonFitsTheRadiiOnceWithAutomaticCones) {
  ParamOptions options;
  options.structure.scheme = Scheme::Thurston;
  options.cone_mode = ConeMode::Auto;
  options.modify_connectivity = false;  // no edge splits: one mesh throughout
  expect_built_once(builds_of(make_icosphere(3), options), 1, "Thurston, automatic cones");
}

}  // namespace
}  // namespace ricci
