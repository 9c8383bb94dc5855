#include "ricci/param/layout.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

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

Complex uv_of(const Layout& layout, int v) {
  return {layout.uv(v, 0), layout.uv(v, 1)};
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

MeshFlowResult flat_flow(const Mesh& mesh, BoundaryMode boundary, Scheme scheme = Scheme::Thurston,
                         const std::vector<Cone>& cones = {}) {
  MeshFlowOptions options;
  options.structure.scheme = scheme;
  options.target.kind = TargetKind::Flat;
  options.target.boundary = boundary;
  options.target.cones = cones;
  MeshFlowResult result = flow_mesh(mesh, options);
  EXPECT_TRUE(result.converged) << result.max_error;
  return result;
}

TEST(Layout, FlatDiskIsReproducedUpToARigidMotion) {
  // Vertex scaling reproduces the input lengths exactly and a planar disk with a free boundary
  // is already flat: u = 0, and the layout must give back the input up to a rigid motion, to
  // rounding (the tree is about 10 faces deep, each placement a few ulps).
  const Mesh mesh = make_disk(12, 0.0);
  const MeshFlowResult flow = flat_flow(mesh, BoundaryMode::Free, Scheme::VertexScaling);
  EXPECT_EQ(flow.u.cwiseAbs().maxCoeff(), 0.0);
  const Uncut u = uncut(flow.topology);
  const Layout layout = layout_flat(flow.topology, flow.lengths, u.cut, u.cut_mesh);
  EXPECT_LE(layout.max_length_relative_error, 1e-12);
  EXPECT_EQ(layout.num_flipped_faces, 0);
  EXPECT_TRUE(layout.transitions.empty());
  EXPECT_TRUE(layout.lattice.empty());
  std::vector<Complex> points, reference;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    points.push_back(uv_of(layout, v));
    reference.emplace_back(mesh.positions(v, 0), mesh.positions(v, 1));
  }
  EXPECT_LE(rigid_distance(points, reference), 1e-12);
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
    const Uncut u = uncut(flow.topology);
    const Layout layout = layout_flat(flow.topology, flow.lengths, u.cut, u.cut_mesh);
    EXPECT_LE(layout.max_length_relative_error, 1e-9);
    EXPECT_NEAR(length_error(flow.topology, u.cut_mesh, flow.lengths, layout),
                layout.max_length_relative_error, 1e-15);
    EXPECT_EQ(layout.num_flipped_faces, 0);
    EXPECT_GT(min_signed_area(u.cut_mesh, layout), 0.0);
    // The curvature the flow reached reads back from the layout: at every vertex, the uv
    // angles around all its copies sum to 2 pi - K (pi - K on the boundary), within the flow's
    // tolerance (1e-10) plus rounding.
    const Eigen::VectorXd sums = uv_angle_sums(flow.topology, u.cut_mesh, layout);
    for (int v = 0; v < flow.topology.num_vertices; ++v) {
      const double full = flow.topology.is_boundary_vertex[v] ? kPi : 2 * kPi;
      EXPECT_NEAR(sums[v], full - flow.target_curvature[v], 1e-8) << "vertex " << v;
    }
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

}  // namespace
}  // namespace ricci
