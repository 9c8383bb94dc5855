#pragma once
/// \file
/// Untangling a layout: the faces a layout draws flipped (or degenerate) are made positive again
/// by moving the vertices around them, without touching what makes the layout a parameterization
/// with exact seams: cones stay where they are, and a vertex on a seam moves with every copy of
/// it, each copy by the rigid motion that relates it to the others, so that the two sides of
/// every seam stay congruent edge for edge.
///
/// A discrete conformal layout drawn on the input's own faces places every vertex at its exact
/// image; a face whose vertices' images come out in clockwise order (needles of CAD tessellations,
/// faces around strong cones) is flipped, and the angle polish (polish.hpp) can free only the
/// vertices on no seam. Here the vertices of a region around the flipped faces move together to
/// minimise the untangling energy of Garanzha, Kaporin, Kudryavtseva, Protais, Ray and Sokolov
/// (2021, "Foldover-free maps in 50 lines of code"):
///     sum_f (1 - theta) |J_f|^2 / chi(det J_f, eps) + theta (det J_f^2 + 1) / chi(det J_f, eps),
///     chi(D, eps) = (D + sqrt(eps^2 + D^2)) / 2,
/// J_f the Jacobian from the face's 3D shape (scaled to the layout's local scale) to its layout:
/// finite for flipped faces while eps > 0, a barrier as eps -> 0; eps follows the paper's
/// sequence, driven by the smallest det J (with a larger floor on the assumed energy decrease,
/// so that eps shrinks faster). Each eps stage is minimised by Newton's method with
/// per-face Hessians projected to be positive semi-definite. A region that does not untangle is
/// grown (more rings) and tried again; nothing outside the region moves.

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Options of untangle_layout.
struct UntangleOptions {
  /// #V (or empty): 1 keeps every copy of that mesh vertex where it is (the cones; vertices whose
  /// copies are not related by rigid motions, or whose copies' motions disagree around them,
  /// which is what a cone looks like, are kept in place anyway).
  std::vector<char> fixed;
  /// #V (or empty): the angle each interior vertex must have in the result, summed over the
  /// corners of all its copies (2 pi minus a cone's curvature; 2 pi elsewhere). A region whose
  /// faces come out positive but wrap a vertex to another angle (twice around, or a cone once
  /// less) is not kept. Empty: 2 pi for the vertices that may move, the others unchecked.
  std::vector<double> angles;
  /// Vertices on the mesh boundary move too (a free boundary's shape is not prescribed).
  bool move_boundary = false;
  /// When some flipped face has no vertex that may move, try nothing (the layout cannot come
  /// out fold-free, and a caller with another route for it saves the work).
  bool give_up_when_stuck = false;
  /// The first region: faces with a vertex within this many rings of a flipped face's vertices.
  int rings = 2;
  /// Regions grow (doubling the rings) up to this many rings.
  int max_rings = 8;
  /// Newton iterations per eps stage, and eps stages, at most; a cluster whose smallest det J
  /// has not risen by a tenth of its distance to min_det over `stall_stages` stages is given up.
  int newton_iterations = 3;
  int max_stages = 40;
  int stall_stages = 4;
  /// Work at most: Newton iterations times the faces in their energies, over all regions;
  /// 0: 50 #F + 100,000 (a layout that will not untangle gives up in proportion to its size).
  long long max_face_iterations = 0;
  /// theta: weight of the area term against the shape term.
  double area_weight = 1.0 / 128;
  /// A face counts as untangled when det J exceeds this (J relative to its face's reference
  /// shape at the local scale): it keeps at least this fraction of its expected area, enough to
  /// stay positive through rescaling and printing.
  double min_det = 1e-6;
};

/// What untangle_layout did.
struct UntangleResult {
  /// #UV by 2: the layout, untangled where it could be (unchanged elsewhere, bit for bit).
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  int flipped_before = 0;  ///< faces with positive 3D area and layout signed area <= 0 on entry
  int flipped_after = 0;   ///< the same at the end
  /// Flipped faces none of whose vertices may move (all fixed, on the boundary or cones):
  /// no untangling reaches them.
  int stuck_faces = 0;
  int moved_vertices = 0;  ///< mesh vertices moved (each with all its copies)
  int region_faces = 0;    ///< faces in the energies of the accepted regions
  int rounds = 0;          ///< regions tried
  int newton_iterations = 0;
  double seconds = 0;
};

/// Makes the flipped faces of a layout positive (see the file comment), moving only vertices
/// near them; a region's moves are kept only when its flipped faces all untangle without
/// flipping another, so the result never has more flipped faces than the input, the copies of
/// every seam vertex stay related by the same rigid motions, and fixed vertices, cones and
/// (unless options.move_boundary) the mesh boundary keep their positions bit for bit.
/// \param mesh 3D positions and triangles (#F by 3)
/// \param uv_triangles #F by 3 indices into uv: the layout vertex of each corner (a vertex on a
///        seam has a copy per side)
/// \param uv #UV by 2 layout positions
/// \throw InvalidInput when the arrays disagree (rows, index ranges) or options are out of range
UntangleResult untangle_layout(const Mesh& mesh, const Triangles& uv_triangles,
                               const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                               const UntangleOptions& options = {});

}  // namespace ricci
