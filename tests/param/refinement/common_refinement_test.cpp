// The common refinement and the exact discrete conformal map on it
// (ricci/param/refinement/common_refinement.hpp), checked step by step against the definitions: the
// pieces are isometric to their shapes in the Delaunay triangulation (T0 -> T1 is an isometry); the
// projective map of every piece takes the circumcircle of its Delaunay triangle onto the
// circumcircle of its final triangle (the Klein-model map between ideal triangles); the texture
// coordinates are a rigid image of the final metric; along every final edge they add up to its
// final length; every piece lies in one input, one Delaunay and one final triangle, and the
// pieces of an input face fill it.
#include "ricci/param/refinement/common_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <numbers>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "ricci/errors.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/hard_cases.hpp"
#include "ricci/mesh/io.hpp"
#include "support/hard_meshes.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;

MeshParamResult param_vertex_scaling(const Mesh& mesh, std::vector<Cone> cones,
                                     double tolerance = 1e-12) {
  ParamOptions options;
  options.structure.scheme = Scheme::VertexScaling;
  options.cone_mode = cones.empty() ? ConeMode::None : ConeMode::User;
  options.cones = std::move(cones);
  options.flow.tolerance = tolerance;
  return parameterize(mesh, options);
}

Complex at(const std::array<Complex, 3>& shape, const Eigen::Vector3d& b) {
  return b[0] * shape[0] + b[1] * shape[1] + b[2] * shape[2];
}

/// Circumcentre of a triangle in the plane.
Complex circumcentre(const std::array<Complex, 3>& s) {
  const Complex b = s[1] - s[0], c = s[2] - s[0];
  const double d = 2 * (b.real() * c.imag() - b.imag() * c.real());
  const double bb = std::norm(b), cc = std::norm(c);
  return s[0] + Complex((c.imag() * bb - b.imag() * cc) / d, (b.real() * cc - c.real() * bb) / d);
}

/// Barycentric coordinates of point z in a triangle of the plane.
Eigen::Vector3d barycentric(const std::array<Complex, 3>& s, Complex z) {
  auto area = [](Complex a, Complex b, Complex c) {
    return ((b - a) * std::conj(c - a)).imag() * -0.5;
  };
  const double total = area(s[0], s[1], s[2]);
  return Eigen::Vector3d(area(z, s[1], s[2]), area(s[0], z, s[2]), area(s[0], s[1], z)) / total;
}

struct RefinementFigures {
  int circle_checks = 0;        // pieces whose projective map was checked on circles
  double circle_error = 0;      // largest relative distance of an image from the circle
  double isometry_error = 0;    // 3D edge vs Delaunay-shape edge, relative to the mean edge
  double rigidity_error = 0;    // uv edge / uv_scale vs final-shape edge, same scale
  double area_error = 0;        // per input face, relative
  double containment = 0;       // most negative barycentric coordinate met
  double continuity_error = 0;  // log weight ratios of an edge seen from its two triangles
};

/// Every check of the file comment; returns the figures for tests to bound.
RefinementFigures check_refinement(const Parameterization& p, const CommonRefinement& r) {
  RefinementFigures fig;
  const Mesh& mesh = p.mesh;
  const int nv = mesh.num_vertices(), nt = static_cast<int>(r.triangles.rows());
  const Topology t0 = build_topology(mesh.triangles, nv);
  const Eigen::VectorXd l0 = input_edge_lengths(mesh, t0);
  const double scale = l0.mean();
  const FaceShapes delaunay = face_shapes_from_lengths(r.delaunay_topology, r.delaunay_lengths);
  // The final triangulation: the flow's, or that of the doubled surface it ran on.
  const FlowResult& component = p.flow.components.front().flow;
  const FaceShapes final_shapes =
      r.doubled ? face_shapes_from_lengths(component.intrinsic.topology(), component.lengths)
                : face_shapes_from_lengths(p.flow.intrinsic.topology(), p.flow.lengths);

  // The input vertices come first, unchanged, with the default output's texture coordinates,
  // or, where the angle polish moved them, with the flat metric's own positions (the layout
  // before the polish) in the same frame.
  EXPECT_EQ(r.positions.topRows(nv), mesh.positions);
  if (p.polish.moved_vertices > 0) {
    const Eigen::Matrix<double, Eigen::Dynamic, 2> exact =
        (p.polish.uv.rowwise() - p.uv_offset.transpose()) * p.uv_scale;
    EXPECT_EQ(r.uv.topRows(p.uv.rows()), exact);
  } else {
    EXPECT_EQ(r.uv.topRows(p.uv.rows()), p.uv);
  }
  EXPECT_LT(r.max_corner_mismatch, 1e-9);

  // Interpolation rows: sum to 1, reproduce the positions, lie in the piece's input face.
  EXPECT_EQ(r.interpolation.rows(), r.positions.rows());
  EXPECT_EQ(r.interpolation.cols(), nv);
  if (r.interpolation.rows() != r.positions.rows() || r.interpolation.cols() != nv) return fig;
  const Eigen::MatrixX3d reproduced = r.interpolation * mesh.positions;
  EXPECT_LT((reproduced - r.positions).cwiseAbs().maxCoeff(),
            1e-12 * mesh.positions.cwiseAbs().maxCoeff() + 1e-15);
  const Eigen::VectorXd sums = r.interpolation * Eigen::VectorXd::Ones(nv);
  EXPECT_LT((sums.array() - 1).abs().maxCoeff(), 1e-14);

  // The map is continuous: along a refinement edge it is the 1-D projective map fixed by the
  // ratio of its ends' weights, which both triangles on the edge must share.
  std::map<std::pair<int, int>, std::vector<double>> edge_ratio;
  for (int t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const int a = r.triangles(t, i), b = r.triangles(t, j);
      const double ratio = std::log(r.projective_uv(3 * t + j, 2) / r.projective_uv(3 * t + i, 2));
      if (a < b) {
        edge_ratio[{a, b}].push_back(ratio);
      } else {
        edge_ratio[{b, a}].push_back(-ratio);
      }
    }
  }
  for (const auto& [edge, ratios] : edge_ratio) {
    if (ratios.size() == 2) {
      fig.continuity_error = std::max(fig.continuity_error, std::abs(ratios[0] - ratios[1]));
    }
  }

  std::vector<double> area(static_cast<std::size_t>(t0.num_faces), 0.0);
  for (int t = 0; t < nt; ++t) {
    const int f = r.input_face[t];
    for (int k = 0; k < 3; ++k) {
      const int v = r.triangles(t, k);
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(r.interpolation, v); it;
           ++it) {
        const bool corner = it.col() == mesh.triangles(f, 0) || it.col() == mesh.triangles(f, 1) ||
                            it.col() == mesh.triangles(f, 2);
        EXPECT_TRUE(corner) << "piece " << t << " leaves input face " << f;
        fig.containment = std::min(fig.containment, it.value());
      }
      fig.containment = std::min({fig.containment, r.delaunay_barycentric.row(3 * t + k).minCoeff(),
                                  r.intrinsic_barycentric.row(3 * t + k).minCoeff()});
      EXPECT_NEAR(r.delaunay_barycentric.row(3 * t + k).sum(), 1, 1e-12);
      EXPECT_NEAR(r.intrinsic_barycentric.row(3 * t + k).sum(), 1, 1e-12);
      const double w = r.projective_uv(3 * t + k, 2);
      EXPECT_GT(w, 0);
      EXPECT_LE(w, 1);
      // (w u, w v, w) divided at the corner is the linear uv.
      const auto uv = r.uv.row(r.uv_triangles(t, k));
      EXPECT_NEAR(r.projective_uv(3 * t + k, 0) / w, uv[0], 1e-12);
      EXPECT_NEAR(r.projective_uv(3 * t + k, 1) / w, uv[1], 1e-12);
    }
    // Area in the input face's plane (signed by its normal).
    const Eigen::Vector3d a = r.positions.row(r.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = r.positions.row(r.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = r.positions.row(r.triangles(t, 2)).transpose();
    const Eigen::Vector3d fa = mesh.positions.row(mesh.triangles(f, 0)).transpose();
    const Eigen::Vector3d fb = mesh.positions.row(mesh.triangles(f, 1)).transpose();
    const Eigen::Vector3d fc = mesh.positions.row(mesh.triangles(f, 2)).transpose();
    const Eigen::Vector3d normal = (fb - fa).cross(fc - fa).normalized();
    area[f] += 0.5 * (b - a).cross(c - a).dot(normal);

    // T0 -> T1 is an isometry: the piece's 3D sides have the lengths its corners have in the
    // Delaunay triangle.  T' -> uv is rigid: its uv sides have the lengths in the final one.
    const auto& ds = delaunay[r.delaunay_face[t]];
    const auto& fs = final_shapes[r.intrinsic_face[t]];
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const double l3 =
          (r.positions.row(r.triangles(t, i)) - r.positions.row(r.triangles(t, j))).norm();
      const double ld = std::abs(at(ds, r.delaunay_barycentric.row(3 * t + i).transpose()) -
                                 at(ds, r.delaunay_barycentric.row(3 * t + j).transpose()));
      fig.isometry_error = std::max(fig.isometry_error, std::abs(l3 - ld) / scale);
      const double luv =
          (r.uv.row(r.uv_triangles(t, i)) - r.uv.row(r.uv_triangles(t, j))).norm() / p.uv_scale;
      const double lf = std::abs(at(fs, r.intrinsic_barycentric.row(3 * t + i).transpose()) -
                                 at(fs, r.intrinsic_barycentric.row(3 * t + j).transpose()));
      fig.rigidity_error = std::max(fig.rigidity_error, std::abs(luv - lf) / scale);
    }

    // The projective map of the piece (Delaunay barycentrics -> final homogeneous barycentrics
    // with the weights w) takes the Delaunay triangle's circumcircle onto the final triangle's.
    Eigen::Matrix3d B, Q;
    for (int k = 0; k < 3; ++k) {
      B.col(k) = r.delaunay_barycentric.row(3 * t + k).transpose();
      Q.col(k) = r.projective_uv(3 * t + k, 2) * r.intrinsic_barycentric.row(3 * t + k).transpose();
    }
    // Rounding in the corners' coordinates reaches the map amplified by up to 1 / |det B|: pieces
    // below 1e-3 of their Delaunay triangle are left out (1e-10 then keeps a margin of 30 over
    // the largest error measured, 3e-12 on the doubled CAD disk).
    if (std::abs(B.determinant()) < 1e-3) continue;
    const Eigen::Matrix3d A = Q * B.inverse();
    const Complex cd = circumcentre(ds), cf = circumcentre(fs);
    const double rd = std::abs(ds[0] - cd), rf = std::abs(fs[0] - cf);
    for (int i = 0; i < 8; ++i) {
      const Complex z = cd + std::polar(rd, 2 * std::numbers::pi * (i + 0.5) / 8);
      Eigen::Vector3d y = A * barycentric(ds, z);
      y /= y.sum();
      fig.circle_error = std::max(fig.circle_error, std::abs(std::abs(at(fs, y) - cf) - rf) / rf);
    }
    ++fig.circle_checks;
  }
  for (int f = 0; f < t0.num_faces; ++f) {
    const Eigen::Vector3d fa = mesh.positions.row(mesh.triangles(f, 0)).transpose();
    const Eigen::Vector3d fb = mesh.positions.row(mesh.triangles(f, 1)).transpose();
    const Eigen::Vector3d fc = mesh.positions.row(mesh.triangles(f, 2)).transpose();
    const double face_area = 0.5 * (fb - fa).cross(fc - fa).norm();
    fig.area_error = std::max(fig.area_error, std::abs(area[f] - face_area) / face_area);
  }
  EXPECT_LT(r.max_intrinsic_length_error, 1e-9);
  EXPECT_LT(fig.isometry_error, 1e-9);
  EXPECT_LT(fig.rigidity_error, 1e-9);
  EXPECT_LT(fig.area_error, 1e-12);
  EXPECT_LT(fig.continuity_error, 1e-9);
  EXPECT_GT(fig.containment, -1e-9);
  EXPECT_EQ(r.inverted_triangles, 0);
  return fig;
}

TEST(CommonRefinement, WithoutFlipsThePiecesAreTheInputFacesWithWeightsEToTheMinusU) {
  const Mesh sphere = make_icosphere(3);
  const MeshParamResult p = param_vertex_scaling(
      sphere, {{0, 1.5 * std::numbers::pi}, {5, 1.5 * std::numbers::pi}, {20, std::numbers::pi}});
  ASSERT_TRUE(p.converged) << p.message;
  ASSERT_EQ(p.flow.intrinsic.flips(), 0);
  const CommonRefinement r = common_refinement(p);
  EXPECT_EQ(r.positions.rows(), sphere.num_vertices());
  EXPECT_EQ(r.triangles.rows(), sphere.num_faces());
  const RefinementFigures fig = check_refinement(p, r);
  EXPECT_EQ(fig.circle_checks, sphere.num_faces());
  EXPECT_LT(fig.circle_error, 1e-10);
  // diag(e^{-u}): the weights of a face's corners are in the ratios of e^{-u}.
  for (int t = 0; t < r.triangles.rows(); ++t) {
    for (int k = 1; k < 3; ++k) {
      const int a = r.triangles(t, 0), b = r.triangles(t, k);
      EXPECT_NEAR(std::log(r.projective_uv(3 * t + k, 2) / r.projective_uv(3 * t, 2)),
                  p.flow.u[a] - p.flow.u[b], 1e-12);
    }
  }
}

TEST(CommonRefinement, ValenceThreeSphereWithStrongConesFlipsBothWays) {
  const Mesh mesh = testing::icosphere_split_near_corners(1, 0.05);
  const MeshParamResult p = param_vertex_scaling(
      mesh, {{0, 1.5 * std::numbers::pi}, {5, 1.5 * std::numbers::pi}, {20, std::numbers::pi}});
  ASSERT_TRUE(p.converged) << p.message;
  const CommonRefinement r = common_refinement(p);
  EXPECT_GT(r.isometric_flips, 50);
  EXPECT_GT(r.ptolemy_flips, 5);
  EXPECT_GT(r.delaunay_intrinsic_points, 0);
  EXPECT_GT(r.interior_points, 0);
  const RefinementFigures fig = check_refinement(p, r);
  EXPECT_GT(fig.circle_checks, 100);
  EXPECT_LT(fig.circle_error, 1e-10);
}

TEST(CommonRefinement, IcosphereWithNegativeConesFlipsDuringTheFlow) {
  const Mesh sphere = make_icosphere(3);
  const MeshParamResult p = param_vertex_scaling(sphere,
                                                 {{0, -std::numbers::pi},
                                                  {100, -std::numbers::pi},
                                                  {1, 1.95 * std::numbers::pi},
                                                  {2, 1.95 * std::numbers::pi},
                                                  {3, 1.95 * std::numbers::pi},
                                                  {50, 0.15 * std::numbers::pi}},
                                                 1e-10);
  ASSERT_TRUE(p.converged) << p.message;
  const CommonRefinement r = common_refinement(p);
  EXPECT_GT(r.ptolemy_flips, 10);
  const RefinementFigures fig = check_refinement(p, r);
  EXPECT_LT(fig.circle_error, 1e-10);
}

TEST(CommonRefinement, CadFanWithFreeBoundaryIsCutAlongItsDelaunayTriangulation) {
  const Mesh strip = testing::cad_strip(40, 0.01);
  const MeshParamResult p = param_vertex_scaling(strip, {});
  ASSERT_TRUE(p.converged) << p.message;
  const CommonRefinement r = common_refinement(p);
  EXPECT_GT(r.isometric_flips, 40);
  // Every input edge of the fans crosses many Delaunay edges.
  EXPECT_GT(r.input_delaunay_points, 10 * strip.num_faces());
  const RefinementFigures fig = check_refinement(p, r);
  EXPECT_LT(fig.circle_error, 1e-10);
}

TEST(CommonRefinement, ADiskFlowedOnItsDoubleKeepsItsOwnHalf) {
  // A CAD cylinder without one pole: fans of needles along the boundary, whose triangles break
  // on the disk itself; the flow runs on the disk glued to its mirror image, and the refinement
  // is that of the doubled surface cut back to the disk's faces.
  const Mesh cylinder = make_cad_cylinder(120);
  std::vector<int> to(static_cast<std::size_t>(cylinder.num_vertices()), -1);
  int n = 0;
  for (int v = 1; v < cylinder.num_vertices(); ++v) to[v] = n++;
  std::vector<Eigen::RowVector3i> faces;
  for (int f = 0; f < cylinder.num_faces(); ++f) {
    const Eigen::RowVector3i c = cylinder.triangles.row(f);
    if (c[0] != 0 && c[1] != 0 && c[2] != 0) faces.emplace_back(to[c[0]], to[c[1]], to[c[2]]);
  }
  Mesh disk;
  disk.positions = cylinder.positions.bottomRows(n);
  disk.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    disk.triangles.row(static_cast<Eigen::Index>(f)) = faces[f];
  ParamOptions options;
  options.structure.scheme = Scheme::VertexScaling;
  options.cone_mode = ConeMode::None;
  options.boundary = BoundaryMode::DiskLength;
  const MeshParamResult p = parameterize(disk, options);
  ASSERT_TRUE(p.converged) << p.message;
  ASSERT_TRUE(p.flow.components.front().doubled);
  const CommonRefinement r = common_refinement(p);
  EXPECT_TRUE(r.doubled);
  EXPECT_GT(r.isometric_flips + r.ptolemy_flips, 100);
  EXPECT_GT(r.triangles.rows(), disk.num_faces());
  for (int f : r.input_face) EXPECT_LT(f, disk.num_faces());
  const RefinementFigures fig = check_refinement(p, r);
  EXPECT_GT(fig.circle_checks, 100);
  EXPECT_LT(fig.circle_error, 1e-10);
}

TEST(CommonRefinement, SharedMeshesWithAutomaticCones) {
  RICCI_REQUIRE_SHARED_MESHES();
  int tested = 0;
  for (const testing::SharedMesh& m : testing::shared_meshes()) {
    // Small meshes whose vertex-scaling flows flip both ways (about a second together).
    if (m.file != "eight.off" && m.file != "spot.obj" && m.file != "bob_tri.obj") continue;
    const ReadResult read = read_mesh(m.path);
    ParamOptions options;
    options.structure.scheme = Scheme::VertexScaling;
    options.cone_mode = ConeMode::Auto;
    const MeshParamResult p = parameterize(read.mesh, options);
    ASSERT_TRUE(p.converged) << m.file << ": " << p.message;
    const CommonRefinement r = common_refinement(p);
    EXPECT_GT(r.isometric_flips, 100) << m.file;
    EXPECT_GT(r.ptolemy_flips, 10) << m.file;
    const RefinementFigures fig = check_refinement(p, r);
    EXPECT_LT(fig.circle_error, 1e-8) << m.file;
    EXPECT_EQ(r.degenerate_triangles, 0) << m.file;
    ++tested;
  }
  if (tested == 0) GTEST_SKIP() << "eight.off, spot.obj and bob_tri.obj not found";
}

// The refinement is the exact map: the angle polish of the default output (which moves the
// input's vertices inside the charts) changes nothing in it.
TEST(CommonRefinement, IsTheSameWithAndWithoutTheAnglePolish) {
  const Mesh mesh = make_icosphere(2);
  std::vector<Cone> cones;
  cones.reserve(4);
  for (int v = 0; v < 4; ++v) cones.push_back({3 * v, std::numbers::pi});
  MeshParamResult polished = param_vertex_scaling(mesh, cones);
  ASSERT_TRUE(polished.converged) << polished.message;
  ASSERT_GT(polished.polish.moved_vertices, 0);
  ParamOptions options;
  options.structure.scheme = Scheme::VertexScaling;
  options.cone_mode = ConeMode::User;
  options.cones = cones;
  options.polish.enabled = false;
  const MeshParamResult exact = parameterize(mesh, options);
  ASSERT_TRUE(exact.converged) << exact.message;
  EXPECT_EQ(exact.polish.moved_vertices, 0);
  const CommonRefinement a = common_refinement(polished), b = common_refinement(exact);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.uv, b.uv);
  EXPECT_EQ(a.projective_uv, b.projective_uv);
  // Without the positions from before the polish there is nothing exact to refine.
  polished.polish.uv.resize(0, 2);
  EXPECT_THROW(common_refinement(polished), InvalidInput);
}

TEST(CommonRefinement, RefusesOtherSchemes) {
  ParamOptions options;
  options.cone_mode = ConeMode::None;
  options.structure.scheme = Scheme::Thurston;
  const MeshParamResult p = parameterize(make_torus(12, 6), options);
  ASSERT_TRUE(p.converged);
  EXPECT_THROW(common_refinement(p), InvalidInput);
}

}  // namespace
}  // namespace ricci
