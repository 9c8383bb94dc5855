// The hyperbolic parameterization: the uniformization metric laid out in the Poincare disk, the
// deck transformations of the cut segments, and the Fuchsian group's canonical generators with
// the surface-group relation a1 b1 a1^-1 b1^-1 ... ag bg ag^-1 bg^-1 = identity.

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/hyperbolic/hyperbolic_param.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "support/hard_meshes.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

void expect_hyperbolic_parameterization(const HyperbolicParamResult& r, int genus, bool closed) {
  ASSERT_TRUE(r.converged) << r.message;
  const HyperbolicLayout& l = r.layout;
  EXPECT_LT(l.max_length_relative_error, 1e-9);
  EXPECT_EQ(l.num_flipped_faces, 0);
  EXPECT_LT(l.max_radius, 1.0);
  EXPECT_EQ(r.distortion.flipped_faces, 0);
  ASSERT_EQ(l.segment_maps.size(), r.cut.segments.size());
  for (const SegmentIsometry& s : l.segment_maps) {
    // Both sides of a segment are one geodesic path: the deck transformation matches them all.
    EXPECT_LT(s.mismatch, 1e-8) << "segment " << s.segment;
    // A deck transformation of a closed hyperbolic surface has no fixed point in the disk.
    if (closed) {
      EXPECT_GT(half_trace(s.map), 1.0 + 1e-6) << "segment " << s.segment;
    }
  }
  EXPECT_EQ(r.has_group, closed);
  if (!closed) return;
  const FuchsianGroup& g = r.group;
  EXPECT_EQ(g.genus, genus);
  ASSERT_EQ(static_cast<int>(g.a.size()), genus);
  ASSERT_EQ(static_cast<int>(g.b.size()), genus);
  EXPECT_LT(g.node_residual, 1e-8);
  EXPECT_LT(g.relation_residual, 1e-8);
  for (int i = 0; i < genus; ++i) {
    EXPECT_GT(half_trace(g.a[i]), 1.0 + 1e-6);
    EXPECT_GT(half_trace(g.b[i]), 1.0 + 1e-6);
  }
}

TEST(HyperbolicParam, GeneratedGenus2To5) {
  // Several resolutions: the cut, its words and their conditioning change with the mesh.
  for (int genus : {2, 3, 4, 5}) {
    for (int resolution : {8, 16, 24}) {
      SCOPED_TRACE("genus " + std::to_string(genus) + ", resolution " + std::to_string(resolution));
      const HyperbolicParamResult r =
          parameterize_hyperbolic(make_closed_surface(genus, resolution));
      expect_hyperbolic_parameterization(r, genus, true);
      EXPECT_EQ(r.cut.num_generators, 2 * genus);
      EXPECT_GE(r.cut_candidates_tried, 1);
      // The metric refined in long double: far below the double flow's rounding floor.
      EXPECT_LT(r.refinement.max_error_after, 1e-16);
      EXPECT_LT(r.layout.max_length_relative_error, 1e-12);
    }
  }
}

/// The vertex-scaling pipeline with flips: the metric lives on the intrinsic Delaunay
/// triangulation, the output on the input's own faces, and the group relation holds to 1e-10.
/// \param refined the residual curvature the long double refinement must reach (its floor rises
///        with needles, whose angles long double resolves less finely)
void expect_flipped_parameterization_on_input_faces(const Mesh& mesh,
                                                    const HyperbolicParamResult& r, int genus,
                                                    double refined = 1e-16) {
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_GT(r.flow.intrinsic.flips(), 0);
  // Faces, cut and uv are the input's: every cut-mesh corner copies the input corner.
  ASSERT_EQ(r.cut_mesh.triangles.rows(), mesh.triangles.rows());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(r.cut_mesh.to_original[r.cut_mesh.triangles(f, k)], mesh.triangles(f, k));
    }
  }
  EXPECT_EQ(r.uv.rows(), r.cut_mesh.topology.num_vertices);
  // Undoing the flips in long double: an input edge gets the same length in its two faces.
  EXPECT_LT(r.development_length_mismatch, 1e-14);
  EXPECT_LT(r.refinement.max_error_after, refined);
  EXPECT_EQ(r.group.genus, genus);
  EXPECT_LT(r.group.relation_residual, 1e-10);
  // The segment maps come from disk positions, whose rounding grows as 1 / (1 - |z|)^2 towards
  // the boundary: genus 5 at resolution 24 reaches |z| = 0.99984, and its node words closed to
  // 2.3e-10 on one machine of this project's kind (below 1e-10 on another with the same code;
  // 1e-13 or less on every other case here).
  const double reach = 1 / (1 - r.uv.rowwise().norm().maxCoeff());
  EXPECT_LT(r.group.node_residual, std::max(1e-10, 1e-16 * reach * reach));
  for (const SegmentIsometry& s : r.layout.segment_maps) {
    EXPECT_LT(s.mismatch, 1e-8) << "segment " << s.segment;
  }
}

HyperbolicParamResult parameterize_with_flips(const Mesh& mesh) {
  HyperbolicParamOptions o;
  o.structure.scheme = Scheme::VertexScaling;  // flips: FlowOptions::flips Auto
  return parameterize_hyperbolic(mesh, o);
}

TEST(HyperbolicParam, VertexScalingWithFlipsOnGeneratedGenus2To5) {
  for (int genus : {2, 3, 4, 5}) {
    for (int resolution : {8, 16, 24}) {
      SCOPED_TRACE("genus " + std::to_string(genus) + ", resolution " + std::to_string(resolution));
      const Mesh mesh = make_closed_surface(genus, resolution);
      const HyperbolicParamResult r = parameterize_with_flips(mesh);
      expect_flipped_parameterization_on_input_faces(mesh, r, genus);
      expect_hyperbolic_parameterization(r, genus, true);
    }
  }
}

TEST(HyperbolicParam, VertexScalingWithFlipsOnBadlyShapedMeshes) {
  // Valence-3 spikes and 0.1-degree needles, which vertex scaling cannot uniformize without
  // flips: the input faces developed in the final metric, a few of them reversed (a spike's
  // sliver can be folded over in the uniformized metric), and the group intact.
  const Mesh spikes = testing::with_valence3_spikes(make_closed_surface(2, 12), 5, 1.0);
  const Mesh both = testing::with_needles(
      testing::with_valence3_spikes(make_closed_surface(3, 14), 4, 1.0), 4, 0.0017);
  for (const auto& [mesh, genus] : {std::pair{&spikes, 2}, std::pair{&both, 3}}) {
    SCOPED_TRACE("genus " + std::to_string(genus));
    const HyperbolicParamResult r = parameterize_with_flips(*mesh);
    expect_flipped_parameterization_on_input_faces(*mesh, r, genus, 1e-15);
    EXPECT_LT(r.layout.max_length_relative_error, 1e-9);
    EXPECT_LT(r.layout.max_radius, 1.0);
    EXPECT_LE(r.layout.num_flipped_faces, mesh->num_faces() / 50);
    EXPECT_EQ(r.distortion.flipped_faces, r.layout.num_flipped_faces);
  }
}

TEST(HyperbolicLayout, FromFaceShapesIsTheLayoutFromLengths) {
  // Without flips (Thurston's packing) the faces' shapes are those of their lengths: the two
  // layouts agree.
  HyperbolicParamOptions thurston;
  thurston.structure.scheme = Scheme::Thurston;
  const HyperbolicParamResult r = parameterize_hyperbolic(make_closed_surface(3, 10), thurston);
  ASSERT_TRUE(r.converged);
  const Topology& t = r.flow.intrinsic.topology();
  const HyperbolicLayout from_lengths =
      layout_hyperbolic(t, r.refinement.lengths, r.cut, r.cut_mesh);
  const HyperbolicLayout from_shapes = layout_hyperbolic(
      t, hyperbolic_face_shapes_from_lengths(t, r.refinement.lengths), r.cut, r.cut_mesh);
  EXPECT_LT((from_lengths.uv - from_shapes.uv).cwiseAbs().maxCoeff(), 1e-13);
  ASSERT_EQ(from_lengths.segment_maps.size(), from_shapes.segment_maps.size());
  for (std::size_t s = 0; s < from_shapes.segment_maps.size(); ++s) {
    EXPECT_LT(distance_to_identity(compose(from_lengths.segment_maps[s].map,
                                           inverse(from_shapes.segment_maps[s].map))),
              1e-10);
  }
  EXPECT_EQ(from_shapes.node_words, from_lengths.node_words);
  EXPECT_THROW(layout_hyperbolic(t, WideFaceShapes(3), r.cut, r.cut_mesh), InvalidInput);
}

TEST(HyperbolicParam, EverySchemeGivesAGroup) {
  const Mesh mesh = make_closed_surface(2, 10);
  for (Scheme scheme : {Scheme::Tangential, Scheme::InversiveDistance, Scheme::VertexScaling}) {
    SCOPED_TRACE(scheme_name(scheme));
    HyperbolicParamOptions o;
    o.structure.scheme = scheme;
    expect_hyperbolic_parameterization(parameterize_hyperbolic(mesh, o), 2, true);
  }
}

TEST(HyperbolicParam, SurfaceWithBoundaryHasGeodesicBoundaryAndNoCanonicalGroup) {
  const HyperbolicParamResult r = parameterize_hyperbolic(make_surface_with_holes(1, 2, 12));
  expect_hyperbolic_parameterization(r, 1, false);
}

TEST(HyperbolicParam, ThePerturbedRelationFails) {
  // The relation check can fail: move one generator a little and the product is no identity.
  HyperbolicParamResult r = parameterize_hyperbolic(make_closed_surface(2, 10));
  ASSERT_TRUE(r.has_group);
  FuchsianGroup& g = r.group;
  g.a[0] = compose(g.a[0], rotation(1e-6));
  Mobius product;
  for (int i = 0; i < g.genus; ++i) {
    product = compose(product,
                      compose(compose(g.a[i], g.b[i]), compose(inverse(g.a[i]), inverse(g.b[i]))));
  }
  EXPECT_GT(distance_to_identity(product), 1e-7);
}

TEST(HyperbolicParam, RefusesSurfacesWithoutHyperbolicMetric) {
  EXPECT_THROW(parameterize_hyperbolic(make_torus(16, 8)), InvalidInput);
  EXPECT_THROW(parameterize_hyperbolic(make_icosphere(2)), InvalidInput);
  EXPECT_THROW(parameterize_hyperbolic(make_disk(4)), InvalidInput);
}

TEST(HyperbolicParam, EveryClosedSharedMeshOfGenusAtLeastTwo) {
  RICCI_REQUIRE_SHARED_MESHES();
  const std::vector<testing::SharedMesh> meshes = testing::closed_hyperbolic_shared_meshes();
  EXPECT_GE(meshes.size(), 3u);
  for (const auto& m : meshes) {
    SCOPED_TRACE(m.file);
    const Mesh mesh = read_mesh(m.path).mesh;
    const HyperbolicParamResult r = parameterize_hyperbolic(mesh);
    expect_hyperbolic_parameterization(r, m.genus, true);
    // And with vertex scaling, whose flow flips edges (eight.off 223 flips, 3holes.off 253,
    // fertility.off 1788).
    const HyperbolicParamResult flipped = parameterize_with_flips(mesh);
    expect_flipped_parameterization_on_input_faces(mesh, flipped, m.genus);
    expect_hyperbolic_parameterization(flipped, m.genus, true);
  }
}

}  // namespace
}  // namespace ricci
