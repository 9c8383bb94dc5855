#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <tuple>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/mesh/components.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/param/parameterize.hpp"
#include "support/shared_meshes.hpp"
#include "support/test_meshes.hpp"
#include "support/uv_checks.hpp"

namespace ricci {
namespace {

/// Meshes side by side (each scaled, then moved along x): one mesh of several components.
Mesh combine(const std::vector<std::pair<Mesh, double>>& parts) {
  Mesh out;
  int nv = 0, nf = 0;
  for (const auto& [m, s] : parts) nv += m.num_vertices(), nf += m.num_faces();
  out.positions.resize(nv, 3);
  out.triangles.resize(nf, 3);
  int v = 0, f = 0;
  double x = 0;
  for (const auto& [m, s] : parts) {
    Eigen::MatrixXd p = m.positions * s;
    const double lo = p.col(0).minCoeff();
    p.col(0).array() += x - lo;
    x += p.col(0).maxCoeff() - (x - lo) + s;  // past this part, plus a gap
    out.positions.middleRows(v, m.num_vertices()) = p;
    out.triangles.middleRows(f, m.num_faces()) = m.triangles.array() + v;
    v += m.num_vertices(), f += m.num_faces();
  }
  return out;
}

/// The scheme main is moving to (and with flips the mesh stays the input's).
ParamOptions vertex_scaling() {
  ParamOptions options;
  options.structure.scheme = Scheme::VertexScaling;
  return options;
}

Eigen::Vector2d uv_of(const Parameterization& r, int f, int k) {
  return r.uv.row(r.cut_mesh.triangles(f, k)).transpose();
}

double uv_area(const Parameterization& r, int f) {
  const Eigen::Vector2d a = uv_of(r, f, 0), b = uv_of(r, f, 1) - a, c = uv_of(r, f, 2) - a;
  return 0.5 * (b.x() * c.y() - b.y() * c.x());
}

double area_3d(const Mesh& m, int f) {
  const Eigen::Vector3d a = m.positions.row(m.triangles(f, 0)).transpose();
  const Eigen::Vector3d b = m.positions.row(m.triangles(f, 1)).transpose();
  const Eigen::Vector3d c = m.positions.row(m.triangles(f, 2)).transpose();
  return 0.5 * (b - a).cross(c - a).norm();
}

using testing::uv_angle_sum;

/// What every atlas of several components must satisfy, converged or not: faces and corners
/// consistent, uv in the square, no flipped face, no two charts overlapping (counted again here),
/// every component at the same texel density, the whole layout and uv related by uv_scale.
void expect_atlas(const MeshParamResult& r, const std::string& what) {
  ASSERT_FALSE(r.components.empty()) << what;
  ASSERT_EQ(r.cut_mesh.triangles.rows(), r.mesh.num_faces()) << what;
  for (int f = 0; f < r.mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(r.cut_mesh.to_original[r.cut_mesh.triangles(f, k)], r.mesh.triangles(f, k))
          << what << " face " << f;
    }
  }
  const double gutter = r.packing.gutter;
  EXPECT_GE(r.uv.minCoeff(), gutter / 2 - 1e-12) << what;
  EXPECT_LE(r.uv.maxCoeff(), 1 - gutter / 2 + 1e-12) << what;
  EXPECT_EQ(r.distortion.flipped_faces, 0) << what;
  EXPECT_EQ(r.distortion.degenerate_faces, 0) << what;
  EXPECT_EQ(r.packing.overlapping_face_pairs, 0) << what;
  EXPECT_EQ(find_uv_overlaps(r.uv, r.cut_mesh.triangles, r.packing.face_chart).count, 0) << what;
  // Nor within a chart: a layout that overlapped itself was cut into charts that do not.
  EXPECT_EQ(find_uv_overlaps(r.uv, r.cut_mesh.triangles).count, 0) << what;
  EXPECT_LE((r.layout.uv * r.uv_scale - r.uv).cwiseAbs().maxCoeff(), 1e-12) << what;
  // uv area / 3D area per component: the common scale squared (each layout was scaled to its 3D
  // area, then all by one factor), up to rounding.
  const double density = r.uv_scale * r.uv_scale;
  double covered = 0;
  for (std::size_t c = 0; c < r.components.size(); ++c) {
    const ComponentParam& comp = r.components[c];
    double a_uv = 0, a_3d = 0;
    for (int f : comp.face_map) a_uv += std::abs(uv_area(r, f)), a_3d += area_3d(r.mesh, f);
    EXPECT_NEAR(a_uv / a_3d, density, 1e-9 * density) << what << " component " << c;
    covered += a_uv;
    // Patches always count as failed; charts do where the user's own cones were refused.
    if (comp.method == ComponentMethod::Patches) {
      EXPECT_FALSE(comp.parameterized) << what;
    }
    if (comp.method != ComponentMethod::Charts && comp.method != ComponentMethod::Patches) {
      EXPECT_TRUE(comp.parameterized) << what;
    }
    if (comp.method != ComponentMethod::Charts) {
      EXPECT_EQ(comp.charts.size() > 1,
                comp.method == ComponentMethod::Patches || comp.overlapping_face_pairs > 0)
          << what;
    }
  }
  EXPECT_NEAR(r.packing.coverage, covered, 1e-12) << what;
  bool all = true;
  for (const ComponentParam& comp : r.components) all = all && comp.parameterized;
  EXPECT_EQ(r.converged, all) << what;
}

TEST(ParameterizeComponents, TorusSphereDiskTriangleAndTetrahedronAtVeryDifferentScales) {
  const Mesh torus = make_torus(32, 12), sphere = make_icosphere(3), disk = make_disk(8);
  const Mesh triangle = testing::make_mesh({{0, 0, 0}, {1, 0, 0}, {0.2, 0.9, 0}}, {{0, 1, 2}});
  const Mesh input = combine({{torus, 1.0},
                              {sphere, 100.0},
                              {disk, 0.01},
                              {triangle, 10.0},
                              {testing::tetrahedron(), 0.1}});
  const MeshParamResult r = parameterize(input, vertex_scaling());
  expect_atlas(r, "five components");
  ASSERT_TRUE(r.converged) << r.message;
  ASSERT_EQ(r.components.size(), 5u);
  // The tetrahedron goes by the flow too (three cones); the triangle is unfolded as it is.
  const ComponentMethod expected[] = {ComponentMethod::Flow, ComponentMethod::Flow,
                                      ComponentMethod::Flow, ComponentMethod::Unfolded,
                                      ComponentMethod::Flow};
  for (int c = 0; c < 5; ++c) {
    EXPECT_EQ(r.components[c].method, expected[c]) << "component " << c;
    EXPECT_TRUE(r.components[c].message.empty()) << r.components[c].message;
  }
  // No edge splits with vertex scaling: the mesh is the input itself.
  EXPECT_EQ(r.mesh.positions, input.positions);
  EXPECT_EQ(r.mesh.triangles, input.triangles);
  // Each component as it would be alone (the same pipeline on the same submesh, bit for bit).
  const Mesh torus_part =
      split_components(input, build_topology(input.triangles, input.num_vertices()))[0].mesh;
  const MeshParamResult torus_alone = parameterize(torus_part, vertex_scaling());
  EXPECT_EQ(r.components[0].distortion.angle_distortion_mean,
            torus_alone.distortion.angle_distortion_mean);
  EXPECT_EQ(r.components[0].param.flow.max_error, torus_alone.flow.max_error);
  // Cone angles read back from the atlas, every component's cones in whole-mesh indices.
  std::size_t cones = 0;
  for (const ComponentParam& comp : r.components) cones += comp.cones.size();
  EXPECT_EQ(r.cones.size(), cones);
  for (const Cone& c : r.cones) {
    EXPECT_NEAR(uv_angle_sum(r, c.vertex), 2 * std::numbers::pi - c.curvature, 1e-8)
        << "cone " << c.vertex;
  }
  // The unfolded triangle keeps its 3D shape exactly (up to the common scale).
  for (int c : {3}) {
    for (int f : r.components[c].face_map) {
      EXPECT_NEAR(std::abs(uv_area(r, f)), area_3d(r.mesh, f) * r.uv_scale * r.uv_scale,
                  1e-12 * area_3d(r.mesh, f) * r.uv_scale * r.uv_scale);
    }
  }
}

/// A unit cube, two triangles per side, outward counter-clockwise.
Mesh cube() {
  Mesh m;
  m.positions.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.positions.row(i) << ((i >> 2) & 1), ((i >> 1) & 1), (i & 1);
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  m.triangles.resize(12, 3);
  for (int q = 0; q < 6; ++q) {
    m.triangles.row(2 * q) << quads[q][0], quads[q][1], quads[q][2];
    m.triangles.row(2 * q + 1) << quads[q][0], quads[q][2], quads[q][3];
  }
  return m;
}

TEST(ParameterizeComponents, ClosedComponentsWhosePipelineFailsUnfold) {
  // No cones asked for: the torus flattens, the tetrahedron and the cube cannot (a closed
  // genus-0 surface needs cones) and are unfolded, their cones where their 3D shape curves.
  ParamOptions options = vertex_scaling();
  options.cone_mode = ConeMode::None;
  const MeshParamResult r = parameterize(
      combine({{make_torus(24, 10), 1.0}, {testing::tetrahedron(), 1.0}, {cube(), 1.0}}), options);
  expect_atlas(r, "torus, tetrahedron, cube");
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_EQ(r.components[0].method, ComponentMethod::Flow);
  for (const auto& [c, cones, curvature] :
       {std::tuple{1, 4u, std::numbers::pi}, std::tuple{2, 8u, std::numbers::pi / 2}}) {
    const ComponentParam& comp = r.components[c];
    EXPECT_EQ(comp.method, ComponentMethod::Unfolded);
    EXPECT_NE(comp.message.find("no flat metric without cones"), std::string::npos) << comp.message;
    ASSERT_EQ(comp.cones.size(), cones);
    for (const Cone& cone : comp.cones) {
      EXPECT_NEAR(cone.curvature, curvature, 1e-12);
      EXPECT_NEAR(uv_angle_sum(r, cone.vertex), 2 * std::numbers::pi - curvature, 1e-12);
    }
    EXPECT_NEAR(comp.distortion.angle_distortion_max, 1.0, 1e-12);
  }
}

TEST(ParameterizeComponents, AFlowLayoutFarFromConformalGivesWayToTheUnfolding) {
  // A needle tetrahedron of the repaired dragon: with the three cones its topology needs, the
  // flow's layout stretches some face by a factor of 1e5 (measured); its own shape unfolds with
  // no distortion and a cone at each corner.
  const Mesh tetrahedron = testing::make_mesh({{0.0339525, 0.0647486, -0.000393758},
                                               {0.0338756, 0.0639078, -0.000273782},
                                               {0.0341065, 0.0642107, 0.000314219},
                                               {0.0342168, 0.0644548, 0.000549007}},
                                              {{1, 0, 2}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}});
  const Mesh triangle = testing::make_mesh({{0, 0, 0}, {1, 0, 0}, {0.2, 0.9, 0}}, {{0, 1, 2}});
  const MeshParamResult alone = parameterize(tetrahedron, vertex_scaling());
  ASSERT_TRUE(alone.converged) << alone.message;
  const MeshParamResult r =
      parameterize(combine({{tetrahedron, 1.0}, {triangle, 0.001}}), vertex_scaling());
  expect_atlas(r, "needle tetrahedron");
  const ComponentParam& comp = r.components[0];
  if (alone.distortion.angle_distortion_max > 10) {
    EXPECT_EQ(comp.method, ComponentMethod::Unfolded);
    EXPECT_NE(comp.message.find("distorts angles"), std::string::npos) << comp.message;
    EXPECT_EQ(comp.cones.size(), 4u);
    EXPECT_NEAR(comp.distortion.angle_distortion_max, 1.0, 1e-9);
  } else {  // the pipeline has improved: its layout stays
    EXPECT_EQ(comp.method, ComponentMethod::Flow);
  }
}

TEST(ParameterizeComponents, TransitionsAndAtlasMoveWithTheCharts) {
  // Two tori: every interior cut edge has a transition taking one side's copy onto the other's.
  const MeshParamResult r = parameterize(
      combine({{make_torus(24, 10), 1.0}, {make_torus(20, 8), 3.0}}), vertex_scaling());
  expect_atlas(r, "two tori");
  ASSERT_TRUE(r.converged) << r.message;
  const Topology t = build_topology(r.mesh.triangles, r.mesh.num_vertices());
  ASSERT_EQ(
      r.layout.transitions.size(),
      static_cast<std::size_t>(std::count(r.cut.is_cut_edge.begin(), r.cut.is_cut_edge.end(), 1)));
  EXPECT_EQ(r.cut.num_generators, 4);
  auto position = [&](int h, int end) {  // the copy of halfedge h's tail (0) or head (1)
    const int f = Topology::face_of(h);
    const int k = (h % 3 + 1 + end) % 3;
    return std::complex<double>(r.layout.uv(r.cut_mesh.triangles(f, k), 0),
                                r.layout.uv(r.cut_mesh.triangles(f, k), 1));
  };
  for (const SeamTransition& s : r.layout.transitions) {
    ASSERT_TRUE(r.cut.is_cut_edge[s.edge]);
    const int h0 = t.edge_halfedges(s.edge, 0), h1 = t.edge_halfedges(s.edge, 1);
    // The halfedges run opposite ways: h0's tail is h1's head.
    double best = 1e300;
    for (int swap = 0; swap < 2; ++swap) {
      const int a = swap ? h1 : h0, b = swap ? h0 : h1;
      const double err =
          std::max(std::abs(s.rotation * position(b, 1) + s.translation - position(a, 0)),
                   std::abs(s.rotation * position(b, 0) + s.translation - position(a, 1)));
      best = std::min(best, err);
    }
    EXPECT_LE(best, 1e-9 * std::abs(position(h0, 0) - position(h0, 1))) << "edge " << s.edge;
  }
  for (const BoundaryChart& bc : r.atlas.boundary_charts) {
    for (std::size_t i = 0; i < bc.faces.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const int v = r.cut_mesh.triangles(bc.faces[i], k);
        std::complex<double> z(r.layout.uv(v, 0), r.layout.uv(v, 1));
        if (bc.side[i]) z = bc.rotation * z + bc.translation;
        EXPECT_LE(
            std::abs(z - std::complex<double>(bc.corner_uv(i, 2 * k), bc.corner_uv(i, 2 * k + 1))),
            1e-12 * (1 + std::abs(z)));
      }
    }
  }
}

TEST(ParameterizeComponents, UserConesGoToTheirComponents) {
  const Mesh sphere = make_icosphere(3);
  const Mesh input = combine({{make_torus(24, 10), 1.0}, {sphere, 1.0}});
  const int offset = make_torus(24, 10).num_vertices();
  ParamOptions options = vertex_scaling();
  options.cone_mode = ConeMode::User;
  for (int v = 0; v < 8; ++v) options.cones.push_back({offset + 10 * v, std::numbers::pi / 2});
  const MeshParamResult r = parameterize(input, options);
  expect_atlas(r, "user cones");
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_TRUE(r.components[0].cones.empty());
  ASSERT_EQ(r.components[1].cones.size(), 8u);
  for (int v = 0; v < 8; ++v) {
    EXPECT_EQ(r.components[1].cones[v].vertex, offset + 10 * v);
    EXPECT_NEAR(uv_angle_sum(r, offset + 10 * v), 1.5 * std::numbers::pi, 1e-8);
  }
  options.cones.push_back({input.num_vertices(), 1.0});
  EXPECT_THROW(parameterize(input, options), InvalidInput);
}

TEST(ParameterizeComponents, AFailedComponentIsReportedAndLaidOutAsPatches) {
  // An inadmissible cone on the saddle (curvature above 2 pi) makes its pipeline throw; its own
  // shape needs two patches or more. The torus goes on.
  const Mesh torus = make_torus(24, 10);
  const Mesh input = combine({{torus, 1.0}, {testing::saddle_fan(), 1.0}});
  ParamOptions options = vertex_scaling();
  options.cone_mode = ConeMode::User;
  options.cones = {{torus.num_vertices(), 7.0}};
  // By default the failed component is laid out as charts with free boundary (fold-free, each
  // seam its 3D length), still reported as failed (its cone was not made); patches are the
  // route without charts.
  const MeshParamResult charts = parameterize(input, options);
  expect_atlas(charts, "torus and saddle, charts");
  EXPECT_FALSE(charts.converged);
  EXPECT_FALSE(charts.components[1].parameterized);
  EXPECT_NE(charts.message.find("component 1"), std::string::npos) << charts.message;
  EXPECT_EQ(charts.components[1].method, ComponentMethod::Charts);
  EXPECT_EQ(charts.distortion.flipped_faces, 0);
  options.fold_free.charts = false;
  const MeshParamResult r = parameterize(input, options);
  expect_atlas(r, "torus and saddle");
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.message.find("component 1"), std::string::npos) << r.message;
  EXPECT_EQ(r.components[0].method, ComponentMethod::Flow);
  const ComponentParam& saddle = r.components[1];
  EXPECT_EQ(saddle.method, ComponentMethod::Patches);
  EXPECT_FALSE(saddle.parameterized);
  EXPECT_NE(saddle.message.find("below"), std::string::npos) << saddle.message;
  EXPECT_GE(saddle.charts.size(), 2u);
  // Patches keep the faces' own shapes.
  EXPECT_NEAR(saddle.distortion.angle_distortion_max, 1.0, 1e-9);
  EXPECT_EQ(find_uv_overlaps(r.uv, r.cut_mesh.triangles).count, 0);
}

TEST(ParameterizeComponents, ManyTinyComponents) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<std::pair<Mesh, double>> parts;
  for (int i = 0; i < 60; ++i) {
    const double s = std::pow(10.0, -1 + 2 * unit(rng));
    if (i % 3 == 0) {
      parts.emplace_back(
          testing::make_mesh({{0, 0, 0}, {1, 0, 0}, {unit(rng), 0.2 + unit(rng), unit(rng)}},
                             {{0, 1, 2}}),
          s);
    } else if (i % 3 == 1) {
      parts.emplace_back(
          testing::make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {1.5, 1, unit(rng)}},
                             {{0, 1, 2}, {1, 3, 2}}),
          s);
    } else {
      parts.emplace_back(testing::tetrahedron(), s);
    }
  }
  const MeshParamResult r = parameterize(combine(parts), vertex_scaling());
  expect_atlas(r, "60 tiny components");
  ASSERT_TRUE(r.converged) << r.message;
  for (const ComponentParam& comp : r.components) {
    // One or two faces are unfolded; the tetrahedra go by the flow.
    EXPECT_EQ(comp.method,
              comp.faces.size() <= 2 ? ComponentMethod::Unfolded : ComponentMethod::Flow);
    if (comp.method != ComponentMethod::Unfolded) continue;
    // Every uv edge is its 3D edge times the common scale.
    for (int f : comp.face_map) {
      for (int k = 0; k < 3; ++k) {
        const double l3 = (r.mesh.positions.row(r.mesh.triangles(f, k)) -
                           r.mesh.positions.row(r.mesh.triangles(f, (k + 1) % 3)))
                              .norm();
        const double luv = (uv_of(r, f, k) - uv_of(r, f, (k + 1) % 3)).norm();
        EXPECT_NEAR(luv, l3 * r.uv_scale, 1e-12 * l3 * r.uv_scale);
      }
    }
  }
  // Sixty small charts pack well (measured 0.45: a triangle fills half its rectangle).
  EXPECT_GT(r.packing.coverage, 0.4);
}

TEST(ParameterizeComponents, EdgeSplitsInOneComponentKeepTheOthersFaces) {
  // One cone of 2 pi chi = -4 pi on the genus-2 surface: the Thurston scheme raises its valence
  // (edges split, faces added). The triangle and the disk (whose pipeline refuses one cone)
  // unfold, their faces where the input has them.
  const Mesh triangle = testing::make_mesh({{0, 0, 0}, {1, 0, 0}, {0.2, 0.9, 0}}, {{0, 1, 2}});
  const Mesh surface = make_closed_surface(2);
  const Mesh input = combine({{triangle, 1.0}, {surface, 1.0}, {make_disk(4), 1.0}});
  ParamOptions options;
  options.structure.scheme = Scheme::Thurston;
  options.cone_mode = ConeMode::OneCone;
  const MeshParamResult r = parameterize(input, options);
  expect_atlas(r, "one cone");
  ASSERT_TRUE(r.converged) << r.message;
  const ComponentParam& split = r.components[1];
  ASSERT_EQ(split.method, ComponentMethod::Flow);
  ASSERT_GT(split.param.edge_splits, 0);
  EXPECT_EQ(r.edge_splits, split.param.edge_splits);
  EXPECT_EQ(r.components[0].method, ComponentMethod::Unfolded);
  EXPECT_EQ(r.components[2].method, ComponentMethod::Unfolded);
  // Input vertices keep their index and position; added ones follow, midpoints of their parents.
  const int added = r.mesh.num_vertices() - input.num_vertices();
  ASSERT_EQ(added, static_cast<int>(r.added_vertex_parents.size()));
  EXPECT_EQ(r.mesh.positions.topRows(input.num_vertices()), input.positions);
  for (int i = 0; i < added; ++i) {
    const int v = input.num_vertices() + i;
    EXPECT_EQ(r.vertex_origin[v], -1);
    const auto [a, b] = r.added_vertex_parents[i];
    EXPECT_LE((r.mesh.positions.row(v) - 0.5 * (r.mesh.positions.row(a) + r.mesh.positions.row(b)))
                  .norm(),
              1e-12);
  }
  // The triangle's face comes first as in the input; the surface's faces follow; the disk's
  // faces keep their input order after them.
  EXPECT_EQ(r.mesh.triangles.row(0), input.triangles.row(0));
  EXPECT_EQ(r.components[1].face_map.front(), 1);
  const int disk_faces = make_disk(4).num_faces();
  EXPECT_EQ(r.mesh.triangles.bottomRows(disk_faces), input.triangles.bottomRows(disk_faces));
  EXPECT_NEAR(uv_angle_sum(r, split.cones.front().vertex),
              2 * std::numbers::pi + 4 * std::numbers::pi, 1e-8);
}

TEST(ParameterizeComponents, ALayoutThatOverlapsItselfIsCutIntoChartsThatDoNot) {
  // Genus 3 with 8 holes, cut open into one disk with a free boundary: the layout winds over
  // itself (3367 face pairs measured); the atlas cuts it into charts (10 measured), and no two
  // faces of the atlas overlap (expect_atlas counts every pair).
  const Mesh triangle = testing::make_mesh({{0, 0, 0}, {1, 0, 0}, {0.2, 0.9, 0}}, {{0, 1, 2}});
  const MeshParamResult r = parameterize(
      combine({{make_surface_with_holes(3, 8), 1.0}, {triangle, 1.0}}), vertex_scaling());
  expect_atlas(r, "genus 3 with 8 holes");
  ASSERT_TRUE(r.converged) << r.message;
  const ComponentParam& comp = r.components[0];
  EXPECT_EQ(comp.method, ComponentMethod::Flow);
  EXPECT_GT(comp.overlapping_face_pairs, 0);
  EXPECT_GE(comp.charts.size(), 2u);
  // The pieces are the flow's layout, cut and moved: every edge is its own layout's edge times
  // the component's area scale and the atlas's scale.
  const double ratio = comp.area_scale * r.uv_scale;
  for (int j = 0; j < comp.param.mesh.num_faces(); ++j) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d own =
          comp.param.layout.uv.row(comp.param.cut_mesh.triangles(j, (k + 1) % 3)) -
          comp.param.layout.uv.row(comp.param.cut_mesh.triangles(j, k));
      const int f = comp.face_map[j];
      const double atlas = (uv_of(r, f, (k + 1) % 3) - uv_of(r, f, k)).norm();
      ASSERT_NEAR(atlas, own.norm() * ratio, 1e-12 * own.norm() * ratio) << "face " << j;
    }
  }
}

TEST(ParameterizeComponents, CancellingStopsEverything) {
  ParamOptions options = vertex_scaling();
  int calls = 0;
  options.flow.progress = [&](const IterationRecord&) { return ++calls < 2; };
  const MeshParamResult r =
      parameterize(combine({{make_torus(24, 10), 1.0}, {make_icosphere(3), 1.0}}), options);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.message.find("cancelled in component 0"), std::string::npos) << r.message;
  EXPECT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.uv.rows(), 0);
  EXPECT_EQ(calls, 2);
}

TEST(ParameterizeComponents, OneComponentIsUnchanged) {
  const MeshParamResult r = parameterize(make_torus(24, 10));
  EXPECT_TRUE(r.components.empty());
  EXPECT_TRUE(r.packing.charts.empty());
  // Its route is the exact map's, and the whole mesh's fields are that map's own.
  ASSERT_EQ(r.routes.size(), 1u);
  EXPECT_EQ(r.routes[0].method, ComponentMethod::Flow);
  EXPECT_EQ(r.routes[0].seam_length, r.seam_length);
  EXPECT_FALSE(r.layout.lattice.empty());
  EXPECT_NEAR(std::max(r.uv.col(0).maxCoeff(), r.uv.col(1).maxCoeff()), 1.0, 1e-12);
}

// What each component's pipeline measured (its automatic cones, its development) travels with
// its route: the whole mesh's Parameterization has no field that means one component's.
TEST(ParameterizeComponents, EachRouteCarriesItsPipelinesDiagnostics) {
  const MeshParamResult one = parameterize(make_icosphere(3));
  ASSERT_TRUE(one.converged) << one.message;
  ASSERT_EQ(one.routes.size(), 1u);
  EXPECT_EQ(one.routes[0].pipeline.cone_selection.vertices.size(), one.cones.size());
  EXPECT_GT(one.cones.size(), 0u);  // a sphere: automatic cones

  const MeshParamResult r =
      parameterize(combine({{make_torus(24, 10), 1.0}, {make_icosphere(3), 1.0}}));
  ASSERT_TRUE(r.converged) << r.message;
  ASSERT_EQ(r.routes.size(), 2u);
  for (std::size_t c = 0; c < r.routes.size(); ++c) {
    const ParamResult& own = r.components[c].param;
    const PipelineDiagnostics& carried = r.routes[c].pipeline;
    EXPECT_EQ(carried.cone_selection.vertices, own.cone_selection.vertices) << c;
    EXPECT_EQ(carried.log_scale_spread, own.log_scale_spread) << c;
    EXPECT_EQ(carried.cone_rounds, own.cone_rounds) << c;
    EXPECT_EQ(carried.development_length_mismatch, own.development_length_mismatch) << c;
  }
  // The sphere's automatic cones: as many as the single sphere had (which of its symmetric
  // vertices win depends on rounding, and combine moves the sphere).
  EXPECT_EQ(r.routes[1].pipeline.cone_selection.vertices.size(),
            one.routes[0].pipeline.cone_selection.vertices.size());
  EXPECT_TRUE(r.routes[0].pipeline.cone_selection.vertices.empty());  // a torus needs none
}

/// A shared mesh after repair (nullopt when missing).
std::optional<Mesh> repaired(const std::string& file) {
  const auto dir = testing::shared_meshes_dir();
  if (!dir) return std::nullopt;
  ReadOptions options;
  options.repair = true;
  return read_mesh(*dir + "/" + file, options).mesh;
}

TEST(ParameterizeComponents, TeapotAndTripleVierbeinAfterRepair) {
  RICCI_REQUIRE_SHARED_MESHES();
  // Measured coverage: teapot 0.59, triple_vierbein 0.28 (two spidery charts in their boxes).
  for (const auto& [file, components, coverage] :
       {std::tuple{"teapot.obj", 4u, 0.5}, std::tuple{"triple_vierbein.obj", 2u, 0.25}}) {
    const auto mesh = repaired(file);
    ASSERT_TRUE(mesh);
    const MeshParamResult r = parameterize(*mesh, vertex_scaling());
    expect_atlas(r, file);
    EXPECT_TRUE(r.converged) << file << ": " << r.message;
    EXPECT_EQ(r.components.size(), components) << file;
    for (const ComponentParam& comp : r.components) {
      EXPECT_EQ(comp.method, ComponentMethod::Flow) << file;
    }
    EXPECT_GT(r.packing.coverage, coverage) << file;
  }
  // triple_vierbein's larger part, flattened with a free boundary, winds over itself where its
  // arms meet (27 pairs of faces, measured): two charts that do not.
  const MeshParamResult r = parameterize(*repaired("triple_vierbein.obj"), vertex_scaling());
  EXPECT_GT(r.components[0].overlapping_face_pairs, 0);
  EXPECT_GE(r.components[0].charts.size(), 2u);
  EXPECT_TRUE(r.components[0].parameterized);
}

TEST(ParameterizeComponents, DragonAfterRepairWithoutItsLargestComponent) {
  RICCI_REQUIRE_SHARED_MESHES();
  // The repaired dragon has 820 components; the largest (200100 faces) takes minutes, the other
  // 819 (one to seven faces, 20 closed tetrahedra among them) are what this test is about.
  const auto mesh = repaired("dragon_vrip_res2.ply");
  ASSERT_TRUE(mesh);
  const Topology t = build_topology(mesh->triangles, mesh->num_vertices());
  ASSERT_EQ(t.components.size(), 820u);
  std::vector<std::pair<Mesh, double>> small;
  for (Submesh& s : split_components(*mesh, t)) {
    if (s.mesh.num_faces() < 1000) small.emplace_back(std::move(s.mesh), 1.0);
  }
  ASSERT_EQ(small.size(), 819u);
  Mesh rest;
  int nv = 0, nf = 0;
  for (const auto& [m, s] : small) nv += m.num_vertices(), nf += m.num_faces();
  rest.positions.resize(nv, 3);
  rest.triangles.resize(nf, 3);
  nv = nf = 0;
  for (const auto& [m, s] : small) {  // in place: the components' own positions
    rest.positions.middleRows(nv, m.num_vertices()) = m.positions;
    rest.triangles.middleRows(nf, m.num_faces()) = m.triangles.array() + nv;
    nv += m.num_vertices(), nf += m.num_faces();
  }
  // Rectangles only: the shape search spends seconds on 819 charts (its coverage, 0.50, is in
  // docs/parameterization.md).
  ParamOptions options = vertex_scaling();
  options.packing.raster_resolution = 0;
  const MeshParamResult r = parameterize(rest, options);
  expect_atlas(r, "dragon's small components");
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_EQ(r.components.size(), 819u);
  int unfolded = 0;
  for (const ComponentParam& comp : r.components) {
    unfolded += comp.method == ComponentMethod::Unfolded;
  }
  EXPECT_GE(unfolded, 791);  // every one of one or two faces (768 + 23)
  EXPECT_GT(r.packing.coverage, 0.3);
}

}  // namespace
}  // namespace ricci
