#include "ricci/param/layout/layout.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/mesh/split.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/param/cut/cut_graph.hpp"
#include "support/flat_layout.hpp"
#include "support/shared_meshes.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using testing::flat_flow;
using testing::flatten;
using testing::Flattened;
using testing::uv_of;

/// A mesh that is already a disk, "sliced" along nothing: the identity cut mesh.
struct Uncut {
  CutGraph cut;
  CutMesh cut_mesh;
};

Uncut uncut(const Topology& topology) {
  Uncut u;
  u.cut.is_cut_edge.assign(topology.num_edges, 0);
  u.cut_mesh.triangles = topology.triangles;
  u.cut_mesh.to_original.resize(topology.num_vertices);
  for (int v = 0; v < topology.num_vertices; ++v) u.cut_mesh.to_original[v] = v;
  u.cut_mesh.topology = build_topology(topology.triangles, topology.num_vertices);
  return u;
}

/// Recomputes the layout's length error from scratch: every face's three sides.
double length_error(const Topology& topology, const CutMesh& cut_mesh,
                    const Eigen::VectorXd& lengths, const Layout& layout) {
  double worst = 0;
  for (int f = 0; f < topology.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const double l = lengths[topology.face_edges(f, k)];
      const double d = std::abs(uv_of(layout, cut_mesh.triangles(f, (k + 1) % 3)) -
                                uv_of(layout, cut_mesh.triangles(f, (k + 2) % 3)));
      worst = std::max(worst, std::abs(d - l) / l);
    }
  }
  return worst;
}

double signed_area(const CutMesh& cut_mesh, const Layout& layout, int f) {
  const Complex a = uv_of(layout, cut_mesh.triangles(f, 0)),
                b = uv_of(layout, cut_mesh.triangles(f, 1)),
                c = uv_of(layout, cut_mesh.triangles(f, 2));
  return 0.5 * std::imag(std::conj(b - a) * (c - a));
}

double min_signed_area(const CutMesh& cut_mesh, const Layout& layout) {
  double smallest = std::numeric_limits<double>::infinity();
  for (int f = 0; f < cut_mesh.triangles.rows(); ++f) {
    smallest = std::min(smallest, signed_area(cut_mesh, layout, f));
  }
  return smallest;
}

/// Largest distance between `points` and `reference` after the best rigid motion (orientation
/// kept) moves the points onto the reference: 2-D Procrustes, computed here independently.
double rigid_distance(const std::vector<Complex>& points, const std::vector<Complex>& reference) {
  Complex pm{0}, rm{0};
  for (std::size_t i = 0; i < points.size(); ++i) {
    pm += points[i];
    rm += reference[i];
  }
  pm /= static_cast<double>(points.size());
  rm /= static_cast<double>(points.size());
  Complex h{0};
  for (std::size_t i = 0; i < points.size(); ++i)
    h += (reference[i] - rm) * std::conj(points[i] - pm);
  const Complex a = h / std::abs(h);
  double worst = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    worst = std::max(worst, std::abs(a * (points[i] - pm) + rm - reference[i]));
  }
  return worst;
}

/// Per original vertex: the sum of the uv corner angles of all the faces around all its copies,
/// measured in the layout (not from the lengths).
Eigen::VectorXd uv_angle_sums(const Topology& topology, const CutMesh& cut_mesh,
                              const Layout& layout) {
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(topology.num_vertices);
  for (int f = 0; f < topology.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const Complex p = uv_of(layout, cut_mesh.triangles(f, k)),
                    q = uv_of(layout, cut_mesh.triangles(f, (k + 1) % 3)),
                    r = uv_of(layout, cut_mesh.triangles(f, (k + 2) % 3));
      sums[topology.triangles(f, k)] += std::arg((r - p) / (q - p));
    }
  }
  return sums;
}

/// The flow's lengths laid out on its own triangulation, uncut: for meshes that are disks.
Layout layout_uncut(const MeshFlowResult& flow) {
  const Uncut u = uncut(flow.intrinsic.topology());
  return layout_flat(flow.intrinsic.topology(), flow.lengths, u.cut, u.cut_mesh);
}

/// rigid_distance from the layout of `vertices` to their input positions, read in the xy-plane.
double distance_to_input(const Layout& layout, const Mesh& mesh, const std::vector<int>& vertices) {
  std::vector<Complex> points, reference;
  for (int v : vertices) {
    points.push_back(uv_of(layout, v));
    reference.emplace_back(mesh.positions(v, 0), mesh.positions(v, 1));
  }
  return rigid_distance(points, reference);
}

TEST(Layout, FlatDiskIsReproducedUpToARigidMotion) {
  // Vertex scaling reproduces the input lengths exactly and a planar disk with a free boundary
  // is already flat: u = 0, and the layout must give back the input up to a rigid motion, to
  // rounding (the tree is about 10 faces deep, each placement a few ulps).
  const Mesh mesh = make_disk(12, 0.0);
  const MeshFlowResult flow = flat_flow(mesh, BoundaryMode::Free, Scheme::VertexScaling);
  EXPECT_EQ(flow.u.cwiseAbs().maxCoeff(), 0.0);
  const Layout layout = layout_uncut(flow);
  EXPECT_LE(layout.max_length_relative_error, 1e-12);
  EXPECT_EQ(layout.num_flipped_faces, 0);
  EXPECT_TRUE(layout.transitions.empty());
  EXPECT_TRUE(layout.lattice.empty());
  std::vector<int> every_vertex(mesh.num_vertices());
  std::iota(every_vertex.begin(), every_vertex.end(), 0);
  EXPECT_LE(distance_to_input(layout, mesh, every_vertex), 1e-12);
}

TEST(Layout, RootFaceIsFarthestFromTheBoundaryAndSitsAtTheOrigin) {
  const Mesh mesh = make_disk(6, 0.0);
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  const Uncut u = uncut(topology);
  Eigen::VectorXd lengths(topology.num_edges);
  for (int e = 0; e < topology.num_edges; ++e) {
    lengths[e] = (mesh.positions.row(topology.edge_vertices(e, 0)) -
                  mesh.positions.row(topology.edge_vertices(e, 1)))
                     .norm();
  }
  const Layout layout = layout_flat(topology, lengths, u.cut, u.cut_mesh);
  // The six faces around the centre are 5 dual steps from the rim; every other face is closer.
  const int root = layout.root_face;
  ASSERT_GE(root, 0);
  EXPECT_TRUE(mesh.triangles(root, 0) == 0 || mesh.triangles(root, 1) == 0 ||
              mesh.triangles(root, 2) == 0);
  // The root's first corner at 0, its second on the positive real axis.
  EXPECT_EQ(uv_of(layout, mesh.triangles(root, 0)), Complex(0.0));
  EXPECT_EQ(layout.uv(mesh.triangles(root, 1), 1), 0.0);
  EXPECT_GT(layout.uv(mesh.triangles(root, 1), 0), 0.0);

  // A requested root moves the layout rigidly, nothing more.
  LayoutOptions options;
  options.root_face = topology.num_faces - 1;
  const Layout other = layout_flat(topology, lengths, u.cut, u.cut_mesh, options);
  EXPECT_EQ(other.root_face, topology.num_faces - 1);
  EXPECT_EQ(uv_of(other, mesh.triangles(options.root_face, 0)), Complex(0.0));
  std::vector<Complex> a, b;
  for (int v = 0; v < topology.num_vertices; ++v) {
    a.push_back(uv_of(layout, v));
    b.push_back(uv_of(other, v));
  }
  EXPECT_LE(rigid_distance(a, b), 1e-13);
}

TEST(Layout, CurvedDiskWithFreeAndDiskBoundaries) {
  // A spherical cap flattened conformally: free boundary (u = 0 there) and the disk target
  // (uniform boundary curvature 2 pi / m). The flow's curvature error (1e-10 rad by default)
  // does not enter the lengths' consistency: the layout follows the lengths face by face, so
  // the length error is rounding only; no face flips because all angles are positive.
  const Mesh mesh = make_disk(16, 0.8);
  for (BoundaryMode boundary : {BoundaryMode::Free, BoundaryMode::DiskUniform}) {
    const MeshFlowResult flow = flat_flow(mesh, boundary);
    const Uncut u = uncut(flow.intrinsic.topology());
    const Layout layout = layout_flat(flow.intrinsic.topology(), flow.lengths, u.cut, u.cut_mesh);
    EXPECT_LE(layout.max_length_relative_error, 1e-9);
    EXPECT_NEAR(length_error(flow.intrinsic.topology(), u.cut_mesh, flow.lengths, layout),
                layout.max_length_relative_error, 1e-15);
    EXPECT_EQ(layout.num_flipped_faces, 0);
    EXPECT_GT(min_signed_area(u.cut_mesh, layout), 0.0);
    // The curvature the flow reached reads back from the layout: at every vertex, the uv
    // angles around all its copies sum to 2 pi - K (pi - K on the boundary), within the flow's
    // tolerance (1e-10) plus rounding.
    const Eigen::VectorXd sums = uv_angle_sums(flow.intrinsic.topology(), u.cut_mesh, layout);
    for (int v = 0; v < flow.intrinsic.topology().num_vertices; ++v) {
      const double full =
          flow.intrinsic.topology().is_boundary_vertex[v] ? std::numbers::pi : 2 * std::numbers::pi;
      EXPECT_NEAR(sums[v], full - flow.target_curvature[v], 1e-8) << "vertex " << v;
    }
  }
}

TEST(Layout, EachComponentFromItsOwnRoot) {
  // Two planar disks side by side, vertex scaling (lengths exact): each component is laid out
  // from its own root and reproduces its own input rigidly.
  const Mesh small = make_disk(4, 0.0), large = make_disk(7, 0.0);
  Mesh both;
  both.positions.resize(small.num_vertices() + large.num_vertices(), 3);
  both.positions << small.positions, large.positions.rowwise() + Eigen::RowVector3d(5, 0, 0);
  both.triangles.resize(small.num_faces() + large.num_faces(), 3);
  both.triangles << small.triangles, large.triangles.array() + small.num_vertices();
  const MeshFlowResult flow = flat_flow(both, BoundaryMode::Free, Scheme::VertexScaling);
  const Layout layout = layout_uncut(flow);
  EXPECT_LE(layout.max_length_relative_error, 1e-12);
  EXPECT_EQ(layout.num_flipped_faces, 0);
  for (const Component& c : flow.intrinsic.topology().components) {
    EXPECT_LE(distance_to_input(layout, both, c.vertices), 1e-12);
  }
}

TEST(Layout, RejectsBrokenInputs) {
  const Mesh mesh = make_disk(3, 0.0);
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  const Uncut u = uncut(topology);
  Eigen::VectorXd lengths = Eigen::VectorXd::Ones(topology.num_edges);
  EXPECT_NO_THROW(layout_flat(topology, lengths, u.cut, u.cut_mesh));
  // A side longer than the two others together: the message names the face.
  Eigen::VectorXd broken = lengths;
  broken[topology.face_edges(7, 1)] = 2.5;
  try {
    layout_flat(topology, broken, u.cut, u.cut_mesh);
    ADD_FAILURE() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("layout_flat"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("triangle inequality"), std::string::npos) << e.what();
  }
  broken = lengths;
  broken[0] = std::nan("");
  EXPECT_THROW(layout_flat(topology, broken, u.cut, u.cut_mesh), InvalidInput);
  EXPECT_THROW(layout_flat(topology, Eigen::VectorXd::Ones(3), u.cut, u.cut_mesh), InvalidInput);
  LayoutOptions options;
  options.root_face = topology.num_faces;
  EXPECT_THROW(layout_flat(topology, lengths, u.cut, u.cut_mesh, options), InvalidInput);
  // A cut mesh that is not a disk (a torus left uncut) breaks the precondition.
  const Mesh torus = make_torus(8, 6);
  const Topology torus_topology = build_topology(torus.triangles, torus.num_vertices());
  const Uncut torus_uncut = uncut(torus_topology);
  EXPECT_THROW(layout_flat(torus_topology, Eigen::VectorXd::Ones(torus_topology.num_edges),
                           torus_uncut.cut, torus_uncut.cut_mesh),
               InvalidInput);
  // A cut mesh whose corners copy other vertices than the mesh's.
  Uncut wrong = u;
  std::swap(wrong.cut_mesh.to_original[0], wrong.cut_mesh.to_original[1]);
  EXPECT_THROW(layout_flat(topology, lengths, wrong.cut, wrong.cut_mesh), InvalidInput);
}

/// The rigid motion z -> a z + b applied to z.
Complex apply(const SeamTransition& t, Complex z) {
  return t.rotation * z + t.translation;
}

/// Invariants every layout of a converged flat metric must meet:
/// - the uv edges reproduce the metric to 1e-9 (rounding over a tree of a few hundred levels);
/// - one transition per cut edge, each a rotation (|a| = 1) whose two ends match to 1e-9 of the
///   edge length; each segment transition agrees with its edges' (up to which side is A);
/// - the flow's curvature reads back from the uv corner angles at every vertex, all copies
///   together (2 pi - K, pi - K on the boundary) to 1e-8;
/// - no face is flipped: the cut mesh's interior vertices are flat, so the faces around each of
///   them close up without overlap.
void expect_valid_layout(const Flattened& f, const std::string& what) {
  SCOPED_TRACE(what);
  const Topology& topology = f.flow.intrinsic.topology();
  const Layout& layout = f.layout;
  EXPECT_LE(layout.max_length_relative_error, 1e-9);
  EXPECT_NEAR(length_error(topology, f.cut_mesh, f.flow.lengths, layout),
              layout.max_length_relative_error, 1e-15);
  EXPECT_EQ(layout.num_flipped_faces, 0);
  EXPECT_GT(min_signed_area(f.cut_mesh, layout), 0.0);

  int cut_edges = 0;
  for (int e = 0; e < topology.num_edges; ++e) cut_edges += f.cut.is_cut_edge[e];
  EXPECT_EQ(static_cast<int>(layout.transitions.size()), cut_edges);
  ASSERT_EQ(layout.segment_transitions.size(), f.cut.segments.size());
  double scale = 0;  // size of the layout, for comparing translations
  for (int v = 0; v < layout.uv.rows(); ++v) scale = std::max(scale, std::abs(uv_of(layout, v)));
  for (const SeamTransition& t : layout.transitions) {
    ASSERT_TRUE(f.cut.is_cut_edge.at(t.edge));
    EXPECT_NEAR(std::abs(t.rotation), 1.0, 1e-15);
    EXPECT_LE(t.mismatch, 1e-9) << "edge " << t.edge;
    // arg(a), with a half turn always +pi (never -pi by rounding): (-pi, pi].
    EXPECT_NEAR(std::remainder(t.angle - std::arg(t.rotation), 2 * std::numbers::pi), 0.0, 1e-15);
    EXPECT_GT(t.angle, -std::numbers::pi + 1e-9);
    EXPECT_LE(t.angle, std::numbers::pi + 1e-9);
    // Side B of the edge lands on side A: check the ends directly.
    const int ha = topology.edge_halfedges(t.edge, 0), hb = topology.edge_halfedges(t.edge, 1);
    const Topology& ct = f.cut_mesh.topology;
    EXPECT_LE(std::abs(apply(t, uv_of(layout, ct.head(hb))) - uv_of(layout, ct.tail(ha))),
              1e-9 * f.flow.lengths[t.edge]);
    EXPECT_LE(std::abs(apply(t, uv_of(layout, ct.tail(hb))) - uv_of(layout, ct.head(ha))),
              1e-9 * f.flow.lengths[t.edge]);
    // Its segment's transition is the same motion or its inverse.
    ASSERT_GE(t.segment, 0);
    const SeamTransition& s = layout.segment_transitions.at(t.segment);
    const Complex inverse_translation = -std::conj(s.rotation) * s.translation;
    const double same = std::abs(s.rotation - t.rotation) * scale +
                        std::abs(s.translation - t.translation),
                 inverse = std::abs(std::conj(s.rotation) - t.rotation) * scale +
                           std::abs(inverse_translation - t.translation);
    EXPECT_LE(std::min(same, inverse), 1e-8 * scale) << "edge " << t.edge;
  }
  for (const SeamTransition& s : layout.segment_transitions) {
    EXPECT_NEAR(std::abs(s.rotation), 1.0, 1e-15);
    EXPECT_LE(s.mismatch, 1e-9) << "segment " << s.segment;
  }

  const Eigen::VectorXd sums = uv_angle_sums(topology, f.cut_mesh, layout);
  for (int v = 0; v < topology.num_vertices; ++v) {
    const double full = topology.is_boundary_vertex[v] ? std::numbers::pi : 2 * std::numbers::pi;
    ASSERT_NEAR(sums[v], full - f.flow.target_curvature[v], 1e-8) << "vertex " << v;
  }
}

/// Distance from x to the nearest integer multiple of `step`.
double off_multiple(double x, double step) {
  return std::abs(x - step * std::round(x / step));
}

TEST(Layout, FlatTorusTilesThePlanePeriodically) {
  const Mesh mesh = make_torus(48, 20);
  const Flattened f = flatten(mesh, BoundaryMode::Free);
  expect_valid_layout(f, "torus");
  // Pure translations across every cut edge.
  for (const SeamTransition& t : f.layout.transitions) {
    EXPECT_LE(std::abs(t.rotation - 1.0), 1e-9) << "edge " << t.edge;
  }
  // Two independent lattice vectors, a reduced basis, counter-clockwise.
  ASSERT_EQ(f.layout.lattice.size(), 2u);
  const Complex b1 = f.layout.lattice[0], b2 = f.layout.lattice[1];
  const double covolume = std::imag(std::conj(b1) * b2);
  EXPECT_GT(covolume, 0.0);
  EXPECT_LE(std::abs(b1), std::abs(b2) * (1 + 1e-12));
  EXPECT_LE(std::abs(std::real(std::conj(b1) * b2)), 0.5 * std::norm(b1) * (1 + 1e-12));
  // The fundamental domain has the flat torus's area: the lattice is the whole period lattice,
  // not a sublattice. The area of the flat metric, face by face (Heron, from the uv sides).
  double area = 0;
  for (int face = 0; face < f.flow.intrinsic.topology().num_faces; ++face) {
    area += signed_area(f.cut_mesh, f.layout, face);
  }
  EXPECT_NEAR(covolume, area, 1e-9 * area);
  // The tiling is consistent: every translation is an integer combination of the two vectors.
  for (const SeamTransition& t : f.layout.transitions) {
    const double x = std::imag(std::conj(t.translation) * b2) / covolume,
                 y = std::imag(std::conj(b1) * t.translation) / covolume;
    const Complex rounded = std::round(x) * b1 + std::round(y) * b2;
    EXPECT_LE(std::abs(t.translation - rounded), 1e-8) << "edge " << t.edge;
  }
}

/// The curvature of the cones on one side of segment s of a cut tree (genus 0): the segments
/// other than s, walked from the first vertex of s's path, reach the nodes on that side.
double cones_beside(const CutGraph& cut, std::size_t s, const std::vector<Cone>& cones) {
  std::vector<int> reached = {cut.segments[s].front()};
  std::vector<char> used(cut.segments.size(), 0);
  used[s] = 1;
  for (std::size_t head = 0; head < reached.size(); ++head) {
    for (std::size_t o = 0; o < cut.segments.size(); ++o) {
      if (used[o]) continue;
      const int a = cut.segments[o].front(), b = cut.segments[o].back();
      if (a == reached[head] || b == reached[head]) {
        used[o] = 1;
        reached.push_back(a == reached[head] ? b : a);
      }
    }
  }
  double total = 0;
  for (const Cone& cone : cones) {
    if (std::find(reached.begin(), reached.end(), cone.vertex) != reached.end()) {
      total += cone.curvature;
    }
  }
  return total;
}

TEST(Layout, SphereWithFourAndEightCones) {
  // Four cones of pi (a tetrahedron's corners) and eight of pi/2 (a cube's): the cut is a tree
  // through the cones, and across each of its segments the layout turns by the curvature of the
  // cones on one side of it (the holonomy of a loop around them), a multiple of pi/2 here.
  const Mesh sphere = make_icosphere(3);
  const std::vector<Cone> four = testing::tetrahedron_cones(sphere);
  const std::vector<Cone> eight = testing::cube_cones(sphere);
  for (const auto& cones : {four, eight}) {
    const std::string what = std::to_string(cones.size()) + " cones";
    const Flattened f = flatten(sphere, BoundaryMode::Free, cones);
    expect_valid_layout(f, what);
    EXPECT_TRUE(f.layout.lattice.empty());
    for (std::size_t s = 0; s < f.cut.segments.size(); ++s) {
      const SeamTransition& t = f.layout.segment_transitions[s];
      EXPECT_LE(off_multiple(t.angle, std::numbers::pi / 2), 1e-8) << what << ", segment " << s;
      const double enclosed = cones_beside(f.cut, s, cones);
      EXPECT_LE(std::min(off_multiple(t.angle - enclosed, 2 * std::numbers::pi),
                         off_multiple(t.angle + enclosed, 2 * std::numbers::pi)),
                1e-8)
          << what << ", segment " << s << ": angle " << t.angle << ", cones beside " << enclosed;
    }
    for (const SeamTransition& t : f.layout.transitions) {
      EXPECT_LE(off_multiple(t.angle, std::numbers::pi / 2), 1e-8) << what << ", edge " << t.edge;
    }
  }
}

TEST(Layout, DiskWithOneConeTurnsByItsCurvatureAcrossTheCut) {
  // A cap with a cone of pi/2 at its centre (vertex 0): the cut runs from the cone to the
  // boundary, and the two sides of it differ by a rotation of +-pi/2, the holonomy around the
  // cone.
  const Flattened f = flatten(make_disk(10, 0.5), BoundaryMode::Free, {{0, std::numbers::pi / 2}});
  expect_valid_layout(f, "disk with a cone");
  ASSERT_FALSE(f.layout.segment_transitions.empty());
  for (const SeamTransition& t : f.layout.segment_transitions) {
    EXPECT_NEAR(std::abs(t.angle), std::numbers::pi / 2, 1e-8) << "segment " << t.segment;
  }
}

TEST(Layout, Genus2WithOneConeOfTwoPiChi) {
  // chi = -2: all the curvature, -4 pi, on one vertex (cone angle 6 pi). Its valence is raised
  // first and the mesh subdivided once, as in the Newton test of genus 3, so that the
  // single-vertex bound and Thurston's conditions around it hold.
  const ValenceResult refined = raise_valence(make_closed_surface(2, 10), 0, 16);
  const Mesh mesh = subdivide_midpoint(refined.mesh);
  const Flattened f = flatten(mesh, BoundaryMode::Free, {{0, -4 * std::numbers::pi}});
  expect_valid_layout(f, "genus 2");
  EXPECT_TRUE(f.layout.lattice.empty());
  // The cone angle 6 pi reads back from the uv angles around the cone's copies. (The segments'
  // rotations are the holonomy of non-contractible loops, which a flat metric with cones leaves
  // free: nothing to assert about them.)
  const Eigen::VectorXd sums = uv_angle_sums(f.flow.intrinsic.topology(), f.cut_mesh, f.layout);
  EXPECT_NEAR(sums[0], 6 * std::numbers::pi, 1e-8);
}

/// Reads a shared mesh by file name, or nothing when it is not there.
std::optional<Mesh> shared_mesh(const std::string& name) {
  for (const auto& shared : testing::shared_meshes()) {
    if (shared.file == name) return read_mesh(shared.path).mesh;
  }
  return std::nullopt;
}

TEST(Layout, SharedMeshesOnePerTopologyClass) {
  RICCI_REQUIRE_SHARED_MESHES();
  struct TopologyCase {
    std::string file;
    BoundaryMode boundary;
  };
  // A disk with the disk target, a closed torus, a torus with a hole and a free boundary.
  for (const TopologyCase& c : {TopologyCase{"camelhead.off", BoundaryMode::DiskUniform},
                                TopologyCase{"bob_tri.obj", BoundaryMode::Free},
                                TopologyCase{"punctured-torus.obj", BoundaryMode::Free}}) {
    const std::optional<Mesh> mesh = shared_mesh(c.file);
    if (!mesh) continue;
    const Flattened f = flatten(*mesh, c.boundary);
    expect_valid_layout(f, c.file);
    if (c.file == "bob_tri.obj") {
      EXPECT_EQ(f.layout.lattice.size(), 2u);
      for (const SeamTransition& t : f.layout.transitions) {
        EXPECT_LE(std::abs(t.rotation - 1.0), 1e-9) << c.file << ", edge " << t.edge;
      }
    }
  }
}

TEST(Layout, SharedGenus3WithEightCones) {
  RICCI_REQUIRE_SHARED_MESHES();
  const std::optional<Mesh> mesh = shared_mesh("3holes.off");
  if (!mesh) GTEST_SKIP() << "3holes.off missing";
  // chi = -4 spread over eight cones of -pi (cone angle 3 pi), far apart (farthest-point
  // sampling in R^3 from vertex 0): each stays within its single-vertex bound at valence 6.
  std::vector<int> picked = {0};
  Eigen::VectorXd distance = (mesh->positions.rowwise() - mesh->positions.row(0)).rowwise().norm();
  while (picked.size() < 8) {
    int farthest = 0;
    distance.maxCoeff(&farthest);
    picked.push_back(farthest);
    distance = distance.cwiseMin(
        (mesh->positions.rowwise() - mesh->positions.row(farthest)).rowwise().norm());
  }
  std::vector<Cone> cones;
  cones.reserve(picked.size());
  for (int v : picked) cones.push_back({v, -std::numbers::pi});
  const Flattened f = flatten(*mesh, BoundaryMode::Free, cones);
  expect_valid_layout(f, "3holes.off");
  EXPECT_TRUE(f.layout.lattice.empty());
}

}  // namespace
}  // namespace ricci
