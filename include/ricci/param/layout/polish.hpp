#pragma once
/// \file
/// Angle polish of a flat layout: moves the layout's interior vertices to lower the mean angle
/// distortion of its faces while keeping every seam, every cone and the boundary where they are.
///
/// A discrete conformal map (vertex scaling) is exact on edge lengths, not on angles: a face whose
/// log scale varies across it, or a sliver whose long edge changes length, is drawn with its
/// angles distorted, more than a harmonic map distorts them on meshes with slivers (camelhead, 4
/// cones: mean sigma ratio 1.0406 against BFF's 1.0389). Moving a vertex that is on no seam and
/// no boundary keeps the layout a flat metric with the same cones and the same seam motions: its
/// faces close up around it as long as none of them flips, the seams are untouched (exact to the
/// last digit), and the cone angles and holonomies do not change. So the map stays a
/// parameterization with the same singularities, only its interior is redrawn.

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Options of polish_angles.
struct PolishOptions {
  /// Run the polish (ParamOptions::polish). Off: the layout is the discrete conformal map itself,
  /// every edge exactly as long as the flat metric says.
  bool enabled = true;
  /// Sweeps over the free vertices at most (each vertex: up to two Newton steps on its own faces).
  int max_sweeps = 10;
  /// Stop when a sweep lowers the mean sigma ratio's excess over 1 by less than this fraction.
  double tolerance = 1e-3;
};

/// What polish_angles did.
struct PolishResult {
  /// #UV by 2: the polished positions (ParamResult::polish swaps them with the layout's: there
  /// it holds the positions from before the polish).
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  int free_vertices = 0;   ///< vertices it may move: on no seam, no boundary, no bad face
  int moved_vertices = 0;  ///< of those, moved at least once
  int sweeps = 0;          ///< sweeps run
  /// Faces drawn flipped that were unflipped first, by moving one of their vertices that is on
  /// no seam and no boundary as little as keeps each of its faces a fraction of its own height.
  int untangled_faces = 0;
  /// Mean over the faces (unweighted, as ../shared/tools/checkuv.py counts it) of sigma_max /
  /// sigma_min, over the faces with positive 3D and layout area, before and after.
  double angle_distortion_before = 0, angle_distortion_after = 0;
  double seconds = 0;
};

/// Lowers the sum over faces of sigma_max / sigma_min (the map from each 3D triangle to its
/// layout) by block coordinate descent: each free vertex in turn takes Newton steps (Hessian
/// clamped positive, backtracking) on the sum over its own faces, never letting one of them
/// flip or degenerate. The sum never rises, no face flips, and the vertices on the layout's
/// boundary (seams, cones on them, the mesh boundary) keep their positions bit for bit. A vertex
/// of a face that is degenerate in 3D, or flipped or degenerate in the layout, is not moved.
/// \param mesh 3D positions (#V by 3) and triangles (#F by 3)
/// \param uv_triangles #F by 3 indices into uv: corner c of face f lies at uv.row(uv_triangles(f,
///        c)); vertices shared by two faces through an edge of both are glued there
/// \param uv #UV by 2 layout positions
/// \throw InvalidInput when uv_triangles has not #F rows, an index is out of range, or an option
///        is out of range (max_sweeps < 0, tolerance < 0)
PolishResult polish_angles(const Mesh& mesh, const Triangles& uv_triangles,
                           const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                           const PolishOptions& options = {});

}  // namespace ricci
