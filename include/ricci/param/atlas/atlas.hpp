#pragma once
/// \file
/// The affine atlas of a flat metric (tutorial section 5.4, fig. 17): the central chart (the
/// layout of the sliced mesh) plus one boundary chart per cut segment covering the union of the
/// one-rings of the segment's vertices; chart transitions are rigid motions.

#include <complex>
#include <vector>

#include <Eigen/Core>

#include "ricci/param/layout/layout.hpp"

namespace ricci {

/// A boundary chart: the faces around one cut segment, laid out so that the segment's two sides
/// meet (side A as in the central chart, side B moved by the segment's transition).
struct BoundaryChart {
  int segment = -1;
  std::vector<int> faces;  ///< faces of the original mesh in the chart
  /// Per chart face, per corner: position in the chart (faces.size() by 6: u0 v0 u1 v1 u2 v2).
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv;
  /// Per chart face: 0 when the chart takes its central-chart position unchanged (side A),
  /// 1 when it takes it through `to_chart` (side B).
  std::vector<char> side;
  /// Transition from the central chart to this chart on side B: z -> rotation z + translation
  /// (the identity on side A).
  std::complex<double> rotation{1}, translation{0};
  /// Largest distance, over the ends of the segment's edges, between the side-A copy of a vertex
  /// and its side-B copy moved by the transition, relative to the edge's length: rounding only.
  double max_gap = 0;
};

/// The whole atlas.
struct AffineAtlas {
  std::vector<BoundaryChart> boundary_charts;  ///< one per cut segment
  /// Largest max_gap of the boundary charts: how far apart the two sides of a segment land in
  /// its chart, relative to the edge length (rounding only).
  double max_transition_error = 0;
};

/// Builds the boundary charts of a layout. A chart takes the faces on both sides of its
/// segment's edges and the one-rings of its vertices that are not nodes; a face is on side A when
/// it lies, in the cut mesh, on the same side of the segment as the side-A face of the first
/// edge (edge_halfedges(e, 0)), which is the side layout_flat's segment transition maps onto.
/// \param layout layout_flat's result for the same cut and cut mesh
/// \throw InvalidInput when the layout has not one transition per segment, or a segment steps
///        across no interior edge
AffineAtlas affine_atlas(const Topology& topology, const CutGraph& cut, const CutMesh& cut_mesh,
                         const Layout& layout);

}  // namespace ricci
