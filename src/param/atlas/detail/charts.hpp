#pragma once
// Private to the param module: the charts route of parameterize (ComponentMethod::Charts), what
// a component gets when its exact cone map fails its own checks (faces still flipped after
// untangling, a layout that does not close up, a flow that does not converge or refuses the
// component's cones).
//
// The component is cut along a cut graph (through the failed map's cones when it had them, else
// its homology generators and boundaries; a closed sphere between two far vertices) into a disk,
// and the disk is flattened with a free boundary, u = 0 there (flow, layout, polish of the
// pipeline), so that every cut edge keeps its 3D length on both sides: the seams are exact edge
// for edge whatever the rotation across them. Faces still flipped after untangling (boundary
// fixed) are taken out of the chart and laid out in their own 3D shape, the rest flattened
// again with u = 0 on its new boundary too (again exact seams), a few rounds; a layout that
// overlaps itself is split into pieces that do not. No face is flipped at the end.

#include <string>
#include <vector>

#include "param/atlas/detail/unfolding.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci::param_detail {

/// A component laid out as charts.
struct ChartsLayout {
  Triangles triangles;          ///< #F by 3: the chart vertex of each corner
  std::vector<int> vertex;      ///< per chart vertex: the mesh vertex it copies
  Points layout;                ///< per chart vertex, in 3D units along the seams
  std::vector<int> face_chart;  ///< #F: chart of each face
  int num_charts = 0;
  /// Charts flattened by the flow (the rest are faces laid out in their own 3D shape) and the
  /// faces in those.
  int flow_charts = 0;
  int unfolded_faces = 0;
  int rounds = 0;                 ///< flattenings of the remaining faces
  UntangleResult untangle;        ///< summed over the flattened charts (uv empty)
  std::vector<int> cut_vertices;  ///< the vertices the cut was made through
  std::string message;            ///< what happened, for the report
};

/// options.polygons (when not empty: the mesh's polygons) stay whole: the cut never runs along a
/// diagonal, and a polygon leaves a chart, joins a piece or a patch with all its triangles.
/// \param cut_through vertices the cut passes through (the failed exact map's cones), may be
///        empty
/// \pre mesh is one connected, valid component (build_topology succeeds, every face has area)
/// \throw nothing but what build_topology throws on an invalid mesh
ChartsLayout lay_out_charts(const Mesh& mesh, const ParamOptions& options,
                            const std::vector<int>& cut_through);

/// The ParamResult of a component laid out as charts (ComponentMethod::Charts): converged, its
/// mesh, cut (the edges between different charts or copies), cut mesh and layout, distortion,
/// seam length, uv in the unit square, the polygons (when not empty) to write from corners
/// whose fans are sound; no cones (the seams carry the curvature).
ParamResult charts_result(const Mesh& mesh, const ChartsLayout& charts,
                          const Polygons& polygons = {});

}  // namespace ricci::param_detail
