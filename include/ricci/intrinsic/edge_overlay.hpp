#pragma once
/// \file
/// How the edges of one triangulation cross another reached from it by edge flips: normal
/// coordinates (Gillespie, Sharp and Crane, "Integer coordinates for intrinsic geometry
/// processing", 2021) with every crossing labelled by the edge it belongs to.
///
/// Start from a triangulation S whose edges we call curves, and flip edges of a copy of it, the
/// host H. Every curve is then either an edge of H or a path that crosses edges of H; between
/// two crossings it runs inside one face of H. The overlay stores, per edge of H, the curves that
/// cross it in their order along the edge (a normal coordinate is the length of that list), and
/// per edge of H the curve it coincides with, if any. Nothing else: the arcs inside a face follow
/// from the numbers of crossings on its three sides, because arcs never cross one another, never
/// return to the side they came from, and at most one corner of a face sends arcs (to the
/// opposite side); the crossings on a side are, from its first end, the arcs cutting its first
/// corner, the arcs from the opposite corner, the arcs cutting its second corner.
///
/// Those three facts hold when every flip happens in a quad that is strictly convex in a chart
/// where the curves are straight lines: an isometric flip of a non-Delaunay edge of a flat
/// surface (the curves are the input's edges, straight in the flat metric), or a Ptolemy flip
/// (the curves are the edges of an earlier triangulation of the same decorated ideal hyperbolic
/// surface: geodesics, straight in every face's Klein model, where the quad is inscribed in a
/// circle). Then the flip is exact integer work: the new diagonal crosses the arcs of the quad
/// whose ends lie on different sides of it, in the order their ends take around the quad.
/// Delta-complexes (loops, double edges, a face using a vertex twice) need nothing special.

#include <vector>

#include "ricci/mesh/topology.hpp"

namespace ricci {

/// The curves of a start triangulation over a host triangulation (see the file comment). A curve
/// is an edge c of the start triangulation, run from the tail to the head of its halfedge
/// edge_halfedges(c, 0) there.
struct EdgeOverlay {
  int num_curves = 0;  ///< edges of the start triangulation
  /// Per host edge e, the crossings in order from the tail to the head of its halfedge
  /// edge_halfedges(e, 0): +(c + 1) where curve c passes from the face of edge_halfedges(e, 1)
  /// into the face of edge_halfedges(e, 0) (from the right of the halfedge to its left),
  /// -(c + 1) the other way.
  std::vector<std::vector<int>> crossings;
  /// Per host edge: +(c + 1) when the edge is curve c run along its halfedge 0, -(c + 1) when
  /// run against it, 0 when the edge is no curve.
  std::vector<int> coincident;

  /// Crossings on edge e (the normal coordinate), or -1 when the edge is a curve itself.
  int normal_coordinate(int e) const {
    return coincident[e] != 0 ? -1 : static_cast<int>(crossings[e].size());
  }
};

/// The overlay of a triangulation on itself: every edge is its own curve, nothing crosses.
EdgeOverlay identity_overlay(const Topology& host);

/// Flips host edge e with flip_edge and updates the overlay (the new diagonal's crossings and
/// coincidence; the other edges' lists do not change).
/// \pre can_flip_edge(host, e), and the flip is one of those the file comment allows
/// \throw InvalidInput when e cannot be flipped; SolverError when the crossings around the quad
///        are inconsistent (an overlay not built by these functions)
void flip_edge_with_overlay(Topology& host, EdgeOverlay& overlay, int e);

/// One end of an arc inside a face: a crossing on side k (the halfedge 3 f + k), numbered from
/// 0 along that halfedge's direction among the crossings of that side, or a corner.
struct ArcEnd {
  int side = -1;    ///< side 0..2, or -1 for a corner
  int index = -1;   ///< position along the side
  int corner = -1;  ///< corner 0..2 when side is -1
  bool is_corner() const { return side < 0; }
};

/// A piece of a curve inside one face, oriented as the curve runs.
struct FaceArc {
  int curve = -1;
  ArcEnd from, to;
};

/// The arcs of the curves inside face f of the host.
/// \throw SolverError when the crossing counts of its sides admit no arcs (parity) or the labels
///        at the two ends of an arc differ
std::vector<FaceArc> face_arcs(const Topology& host, const EdgeOverlay& overlay, int f);

/// One crossing of a curve with a host edge, as the curve runs.
struct CurveCrossing {
  int edge = -1;   ///< host edge
  int index = -1;  ///< position in overlay.crossings[edge]
  /// The host halfedge the curve leaves its face through (in the face before the crossing); its
  /// twin lies in the face after.
  int halfedge = -1;
};

/// A curve as a path over the host.
struct CurvePath {
  /// The host halfedge running along the curve, in its direction, when the curve is a host edge
  /// (then the other fields are empty); -1 otherwise.
  int coincident_halfedge = -1;
  int start_face = -1, start_corner = -1;  ///< the corner of the host the curve leaves
  int end_face = -1, end_corner = -1;      ///< the corner it arrives at
  std::vector<CurveCrossing> crossings;    ///< in order along the curve
};

/// Every curve as a path over the host, in time linear in the number of crossings.
/// \throw SolverError when a curve cannot be followed (an inconsistent overlay)
std::vector<CurvePath> trace_curves(const Topology& host, const EdgeOverlay& overlay);

/// The same relation seen the other way: the host's edges as curves over the start
/// triangulation. `paths` = trace_curves(host, overlay); `start` is the start triangulation
/// (whose edges are the curves). Entry j of the result's crossings[c] is the crossing
/// paths[c].crossings[j].
EdgeOverlay transpose_overlay(const Topology& host, const EdgeOverlay& overlay,
                              const std::vector<CurvePath>& paths, const Topology& start);

}  // namespace ricci
