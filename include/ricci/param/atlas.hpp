#pragma once
/// \file
/// The affine atlas of a flat metric (tutorial section 5.4, fig. 17): the central chart (the
/// layout of the sliced mesh) plus one boundary chart per cut segment covering the union of the
/// one-rings of the segment's vertices; chart transitions are rigid motions.

#include <complex>
#include <vector>

#include <Eigen/Core>

#include "ricci/param/layout.hpp"

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
};

/// The whole atlas.
struct AffineAtlas {
  std::vector<BoundaryChart> boundary_charts;  ///< one per cut segment
  /// Largest mismatch, over faces shared by a boundary chart and the central chart, between the
  /// chart position and the transition applied to the central position (rounding only).
  double max_transition_error = 0;
};

/// Builds the boundary charts of a layout.
AffineAtlas affine_atlas(const Topology& topology, const CutGraph& cut, const CutMesh& cut_mesh,
                         const Layout& layout);

}  // namespace ricci
