#pragma once
/// \file
/// Spherical conformal map of a closed genus-0 mesh onto the unit sphere (issue 6, docs/sphere.md).
///
/// Method: one vertex, the pole, is removed with its star; the rest is a topological disk, which
/// the Euclidean Ricci flow flattens (K-bar = 0 inside, the boundary turning by 2 pi in proportion
/// to its input length: BoundaryMode::DiskLength) and a layout grown from the smallest faces up
/// places in the plane. The layout is moved and scaled so that the least-squares circle through
/// its boundary is the unit circle, then sent onto the sphere by inverse stereographic
/// projection, the pole at the north pole (0, 0, 1). Finally a Moebius transformation of the
/// sphere puts the centre of mass of the input surface's area, carried by the map, at the
/// origin, and the vertices of faces the map inverts move into their stars (untangling). The
/// layout, projection and normalisation run in double, long double or quad, whichever resolves
/// the smallest faces (a conformal map shrinks a long limb exponentially); the output is
/// rounded to double (docs/sphere.md, Precision).
///
/// Centre of mass of the area: c = sum over faces f of w_f n_f, where w_f = A_f / sum A is the
/// face's share of the input mesh's 3D area and n_f = (P_i + P_j + P_k) / |P_i + P_j + P_k| the
/// normalised centroid of its image. (The images' own spherical areas would not do: for any
/// embedding they tile the sphere, whose centre of mass is the origin whatever the map.) The
/// Moebius maps that move it are the boosts
///     phi_a(x) = (1 - |a|^2) (x - a) / |x - a|^2 - a,  |a| < 1,
/// the restriction to the sphere of the hyperbolic isometry of the unit ball taking a to 0; they
/// spread the sphere out around a / |a| and gather it towards -a / |a|. Near a = 0,
/// phi_a(x) = x - 2 (I - x x^T) a + O(|a|^2), so c moves by about -2 M a with
/// M = sum_f w_f (I - n_f n_f^T): a damped Newton iteration solves for a, applies phi_a to the
/// positions and repeats until |c| <= SphereOptions::centre_tolerance. The result is unique up to
/// a rotation (Douady and Earle 1986) whenever no vertex carries half the area.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Options of sphere_map.
struct SphereOptions {
  /// Vertex sent to the north pole before the Moebius normalisation; -1 picks one (see
  /// choose_pole_vertex).
  int pole = -1;
  /// Discrete metric of the disk's flow; StructureOptions' default, vertex scaling (discrete
  /// conformal equivalence with intrinsic Delaunay flips), reaches every target. Thurston's
  /// packings (Scheme::Thurston) never break a triangle, and with Phi in [0, pi/2] and a convex
  /// boundary their layout is an embedding.
  StructureOptions structure;
  /// Newton to 1e-12, see layout_flow_options. Edge flips (vertex scaling) change the disk's
  /// triangulation but the output keeps the input's faces, whose images are then checked like any
  /// other.
  FlowOptions flow = layout_flow_options();
  /// Stop the Moebius normalisation when |centre of mass| is at most this.
  double centre_tolerance = 1e-12;
  int max_centre_iterations = 100;  ///< most Newton steps of the normalisation
  /// Move the vertices of faces the map inverts into the cone where their whole star keeps its
  /// orientation (see SphereResult::untangled_vertices), then centre again; up to 3 rounds.
  bool untangle = true;
  /// Make the map exactly Moebius-invariant (vertex scaling only; other schemes ignore it): with
  /// the pole at infinity its star's faces stay in the surface's discrete conformal class only
  /// when every spoke (pole, i) has the same length in the plane's metric, that is u_i =
  /// -2 ln l(pole, i) + C on the disk's boundary, held fixed while the interior flattens. Two
  /// discretely conformally equivalent meshes (say one the image of the other under a Moebius
  /// transformation of space) then get maps that differ by a Moebius transformation of the
  /// sphere, to the flow's tolerance, whatever the pole; the default boundary, turning in
  /// proportion to its length, is right only to the mesh's resolution (about 1e-3 on a
  /// 642-vertex sphere). Matching (ricci/match) turns it on. The boundary is then no circle
  /// (boundary_circle_deviation says how far).
  bool exact_pole_star = false;
};

/// What sphere_map returns. Per-face statistics are over the input's faces.
struct SphereResult {
  bool converged = false;  ///< the flow converged and the normalisation reached its tolerance
  /// converged, no face of the output inverted (inverted_faces == 0) and every figure finite:
  /// the map to use. When not, `message` says why and `fixes` what may work.
  bool valid = false;
  std::string message;           ///< why not converged or not valid, when not
  std::vector<OptionFix> fixes;  ///< settings that may give a valid map, best first
  /// #V by 3 positions on the unit sphere (rows of unreferenced vertices: 0), counter-clockwise
  /// faces seen from outside where the map has no inverted face.
  Positions positions;
  int pole = -1;  ///< the vertex removed for the flow (at the north pole before normalisation)
  /// Poles tried: 2 when the default pole squeezed the plane more than the sphere (the tip of a
  /// limb) and the widest star of that first map was tried too; the better map is returned.
  int poles_tried = 1;
  /// SphereOptions::exact_pole_star held: false when it was off, or when its boundary broke a
  /// triangle of the disk or stalled the flow and the length-proportional one was used instead.
  bool exact_pole_star = false;

  // The flow on the disk (the mesh without the pole and its faces).
  MeshFlowResult flow;             ///< in disk vertex indices
  std::vector<int> disk_vertices;  ///< per disk vertex: its vertex in the mesh
  /// Disk faces whose shape in the flat metric is reversed (Development::flipped_faces): the
  /// metric itself inverts them (vertex scaling bends needles over), whatever the arithmetic.
  int reversed_disk_faces = 0;
  /// Layout of the disk, in mesh vertex indices (#V by 2; the pole's row is NaN), after the
  /// translation and scale that make the boundary's least-squares circle the unit circle
  /// (rounded to double from the precision of `precision_bits`).
  Eigen::Matrix<double, Eigen::Dynamic, 2> plane;
  /// max over edges of the disk of | |p_i - p_j| - l_ij | / l_ij, l_ij the edge's length in
  /// the shape of the face it is measured in: how well the layout closes up.
  double layout_length_error = 0;
  /// max over boundary vertices of | |p| - 1 | in the normalised plane: how far the disk's
  /// boundary is from the circle the stereographic projection sends to the equator.
  double boundary_circle_deviation = 0;
  /// Boundary edges (i, j) of the disk (each the image of a face (i, j, pole)) with
  /// det(p_i, p_j) <= 0: faces around the pole that the projection inverts. 0 expected.
  int inverted_pole_faces = 0;

  // Precision. The layout, the projection and the normalisation run in the narrowest of double,
  // long double and quad (__float128 where the compiler has it) that resolves every face: a
  // conformal map shrinks a long limb exponentially (area e^-50 at the fingertips of a body),
  // and a face whose smallest altitude is near the arithmetic's resolution (2^-52 of the unit
  // disk or sphere) loses its shape.
  int precision_bits = 53;  ///< significand bits used: 53 (double), 64 (long double) or 113
  /// min over disk faces of the smallest altitude in the normalised plane (unit circle):
  /// what chose the precision.
  double min_plane_altitude = 0;
  /// min over faces of the smallest altitude of the chordal triangle on the sphere, computed
  /// before rounding to double.
  double min_sphere_altitude = 0;
  /// Faces whose smallest altitude on the sphere is below 2^-46 (1.4e-14, 64 units in the
  /// last place of a coordinate): the double positions of the output keep their shape only
  /// roughly, and rounding may invert them (inverted_by_rounding).
  int unresolved_faces = 0;

  // The Moebius normalisation.
  int centre_iterations = 0;  ///< Newton steps taken
  double initial_centre = 0;  ///< |centre of mass| right after the projection
  double centre_of_mass = 0;  ///< |centre of mass| at the end
  double max_boost_norm = 0;  ///< largest |a| of a single step

  // Untangling (SphereOptions::untangle). The exact map can invert a face: vertex scaling's flat
  // metric reverses needles (reversed_disk_faces), and the projection bends the long side of a
  // very obtuse face over its third corner. Such a vertex moves, along the great circle towards
  // the mean of its link, a quarter of the way into the positions where its whole star keeps
  // its orientation; the map is then conformal everywhere but at the moved vertices.
  int untangled_vertices = 0;             ///< vertex moves made (a vertex may move twice)
  double max_untangle_move = 0;           ///< largest move, as a chord of the unit sphere
  double max_untangle_relative_move = 0;  ///< largest move over the vertex's shortest edge

  // Invariants of the final map (faces as geodesic triangles between their images).
  double max_radius_deviation = 0;  ///< max over vertices of | |P_i| - 1 |
  /// Faces with det(P_i, P_j, P_k) <= 0 in the output's double positions (the determinant from
  /// the differences P_j - P_i, P_k - P_i, in long double): 0 for a valid map.
  int inverted_faces = 0;
  /// Of those, the faces the map keeps (det > 0 before rounding) but the rounding of the
  /// positions to double inverts: faces below double resolution (unresolved_faces).
  int inverted_by_rounding = 0;
  /// Sum of the signed spherical areas 2 atan2(det, 1 + P_i.P_j + P_j.P_k + P_k.P_i) of the faces:
  /// 4 pi when the images cover the sphere once; with no inverted face, an embedding.
  double spherical_area = 0;

  // Distortion, against the input's 3D triangles (from the positions before rounding).
  /// sigma_max / sigma_min of the linear map from each 3D triangle to its chordal triangle
  /// P_i P_j P_k (1: conformal): mean weighted by 3D area, max, and the 95th percentile over
  /// faces (unweighted).
  double angle_distortion_mean = 0, angle_distortion_max = 0, angle_distortion_p95 = 0;
  /// |corner angle of the chordal triangle - corner angle in 3D| over all corners, radians:
  /// unweighted mean and max.
  double angle_error_mean = 0, angle_error_max = 0;
  /// ln((spherical area / 4 pi) / (3D area / total 3D area)) per face with positive spherical
  /// area: min, max, mean and standard deviation weighted by 3D area. min and max say how far
  /// the conformal factor reaches: a face of area share s on a limb at log_area_min is about
  /// sqrt(4 pi s) e^(log_area_min / 2) across on the unit sphere.
  double log_area_min = 0, log_area_max = 0, log_area_mean = 0, log_area_stddev = 0;

  // Timings, seconds.
  double flow_seconds = 0, layout_seconds = 0, normalisation_seconds = 0, seconds = 0;
};

/// The default pole: the vertex whose removal leaves the easiest disk for the flow. Each vertex w
/// of its link becomes a boundary vertex with the interior angle it had outside the star, where
/// the disk-length target asks for about pi - 2 pi / valence; the score is the largest such
/// difference (boundary edges cannot flip, so the flow must bridge it near the boundary) and the
/// pole's own angle defect |2 pi - sum of its angles|, plus pi for valence below 5. The lowest
/// score wins, ties to the lowest index. On a scan full of needles this keeps them away from
/// the star; on a regular mesh it picks a flat, well-surrounded vertex.
/// \pre the mesh is closed (every vertex of a face has a full fan)
int choose_pole_vertex(const Mesh& mesh);
/// The same with the mesh's connectivity at hand. \pre topology = build_topology(mesh)
int choose_pole_vertex(const Mesh& mesh, const Topology& topology);

/// Maps a closed genus-0 mesh conformally onto the unit sphere (see the file comment).
/// Non-convergence of the flow or the normalisation is reported in the result, not thrown.
/// \param mesh #V by 3 positions, #F by 3 counter-clockwise triangles; one closed genus-0
///        component (unreferenced vertices allowed)
/// \throw InvalidInput when the mesh has defects (validate_mesh), is not one connected component,
///        has a boundary or has genus > 0, when options.pole is out of range or on no face, or
///        when an option is out of range
/// \throw TopologyError for non-manifold or inconsistently oriented meshes
SphereResult sphere_map(const Mesh& mesh, const SphereOptions& options = {});

}  // namespace ricci
