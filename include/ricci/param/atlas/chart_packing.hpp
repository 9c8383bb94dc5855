#pragma once
/// \file
/// Packing the charts of a texture atlas into the unit square. Each chart is turned to the
/// orientation of its minimal-area bounding rectangle (one side along an edge of its convex
/// hull), all charts are scaled by one common factor (so that their relative sizes, and with them
/// the texel density, stay as given), and packed without overlap, the largest factor that fits
/// found by search: first their rectangles, each grown by a gutter (MaxRects with
/// best-short-side fit, quarter turns allowed; shelves past 2000 charts), then their shapes on a
/// grid (conservative rasterisation grown by half the gutter, bottom-left first fit), whichever
/// reaches the larger factor. Charts in disjoint rectangles, or on disjoint sets of cells, cannot
/// overlap; find_uv_overlaps checks it anyway, exactly, triangle against triangle.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/param/atlas/uv_overlaps.hpp"

namespace ricci {

/// Options of pack_charts.
struct ChartPackingOptions {
  /// Free space between the bounding rectangles of two charts, in uv units (the square has side
  /// 1); between a rectangle and the square's edge half of it. 0.002 is two texels of a 1024 x
  /// 1024 texture, enough for bilinear filtering not to mix charts. Whatever the value, at least
  /// 1e-9 is kept, so that rounding in the placement can never make two charts touch.
  double gutter = 0.002;
  /// Turn each chart to its minimal-area bounding rectangle and let the packer add quarter
  /// turns; false: charts are only translated (and scaled).
  bool rotate = true;
  /// The common scale factor is searched (steps down from the area bound by 0.8, then
  /// bisection, each step a full packing attempt) until it is known to this relative precision:
  /// 1e-3 costs about ten attempts and at most 0.2% of coverage.
  double scale_tolerance = 1e-3;
  /// Also pack by shape: each chart rasterised on a grid of about this many cells across the
  /// square (every cell its triangles meet, grown by half the gutter), placed bottom-left first
  /// fit in one of four quarter turns, so that charts nest into each other's free space; the
  /// result replaces the rectangles' when its scale is larger. 0: rectangles only.
  int raster_resolution = 1024;
  /// The shape search's work (grid rows and positions tried, counted, so that results do not
  /// depend on the machine): past it the search stops with the best packing found so far. The
  /// teapot's four charts need 6e4; the 819 small components of the dragon 5e7 for coverage
  /// 0.50 (a few seconds; 2e8 reaches 0.54), where rectangles give 0.41.
  long long raster_work_limit = 50'000'000;
};

/// One chart as placed: uv = scale * R(rotation) * layout + translation for its vertices.
struct PackedChart {
  std::vector<int> faces;  ///< faces of the chart, ascending
  double rotation = 0;     ///< radians, counter-clockwise (a quarter turn by the packer included)
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
  Eigen::Vector2d box_min = Eigen::Vector2d::Zero();  ///< bounding box of its uv (after placement)
  Eigen::Vector2d box_max = Eigen::Vector2d::Zero();
  double area = 0;  ///< uv area of its faces (absolute values summed)
};

/// What pack_charts returns.
struct ChartPacking {
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;  ///< #V by 2 in [0, 1]^2 (vertices of no face: 0)
  std::vector<int> face_chart;                  ///< #F: chart of each face
  std::vector<PackedChart> charts;
  double scale = 0;   ///< the common factor (uv units per layout unit)
  double gutter = 0;  ///< gutter used: options.gutter unless too many charts forced it smaller
  /// Total uv area of the charts' faces: the fraction of the unit square they cover.
  double coverage = 0;
  /// Total area of the charts' minimal bounding rectangles (gutter not included): coverage /
  /// rectangle_coverage is how well the charts fill them. Packed by shape, rectangles overlap
  /// and this can pass 1.
  double rectangle_coverage = 0;
  /// Pairs of faces of different charts whose uv triangles overlap (find_uv_overlaps): 0 always,
  /// checked after the placement rather than assumed.
  int overlapping_face_pairs = 0;
  /// The charts were placed by shape (ChartPackingOptions::raster_resolution), not in their
  /// rectangles (which may then overlap; the charts do not).
  bool by_shape = false;
  /// Work the shape search did (ChartPackingOptions::raster_work_limit).
  long long raster_work = 0;
  int packing_attempts = 0;  ///< packings tried (rectangles and shapes) during the searches
  double seconds = 0;
};

/// Places the charts of a layout in the unit square (see the file comment).
/// \param layout #V by 2 positions (any units; the charts' relative sizes are kept)
/// \param triangles #F by 3 indices into layout
/// \param face_chart #F chart index per face (0 .. #charts - 1, every index used), or empty:
///        one chart per connected piece of the triangles (faces sharing a layout vertex)
/// \return the placed uv and per chart its rotation and translation
/// \throw InvalidInput for an index out of range, a non-finite position, a face_chart of the
///        wrong size or with an unused index, no faces, or a gutter that is negative or not
///        below 0.5
ChartPacking pack_charts(const Eigen::Matrix<double, Eigen::Dynamic, 2>& layout,
                         const Triangles& triangles, const std::vector<int>& face_chart = {},
                         const ChartPackingOptions& options = {});

}  // namespace ricci
