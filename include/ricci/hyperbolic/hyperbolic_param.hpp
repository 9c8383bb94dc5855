#pragma once
/// \file
/// The hyperbolic parameterization pipeline (THEORY.md section 9): the Ricci flow in the
/// hyperbolic background to the uniformization metric (zero vertex curvature, geodesic boundary),
/// the cut graph, the layout of the sliced mesh in the Poincare disk, the deck transformations
/// of the cut segments and, on a closed surface, the canonical generators of its Fuchsian group.
/// Mesh in, texture coordinates in the unit disk out.

#include <string>

#include <Eigen/Core>

#include "ricci/flow/mesh_flow.hpp"
#include "ricci/hyperbolic/fuchsian.hpp"
#include "ricci/hyperbolic/hyperbolic_layout.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/param/cut/cut_graph.hpp"
#include "ricci/param/distortion.hpp"

namespace ricci {

/// Options of parameterize_hyperbolic.
struct HyperbolicParamOptions {
  StructureOptions structure;  ///< scheme and initial packing (the geometry is set to hyperbolic)
  /// Newton to 1e-12, see layout_flow_options.
  FlowOptions flow = layout_flow_options();
  HyperbolicLayoutOptions layout;
  /// Closed surfaces: how many cuts (tree-cotree from different root vertices) to try at most;
  /// the one whose canonical generators satisfy the relation best is kept.
  int cut_candidates = 32;
  /// Stop trying further cuts once the relation residual is this small.
  double good_relation_residual = 1e-11;
  /// Above this relation residual the generators are reported as not computed
  /// (HyperbolicParamResult::group_failure) rather than as a group.
  double usable_relation_residual = 1e-6;
  /// A polygon mesh (ReadResult::polygons): the cuts never run along its polygons' diagonals,
  /// and HyperbolicParamResult::polygons gives the faces to write. Empty: every triangle a face.
  Polygons polygons;
};

/// What parameterize_hyperbolic returns.
struct HyperbolicParamResult {
  bool converged = false;  ///< the flow reached its tolerance
  std::string message;     ///< why not, when it did not
  /// The flow to the hyperbolic metric. With vertex scaling it flips edges (FlowOptions::flips
  /// Auto): its topology is then the intrinsic Delaunay triangulation the metric lives on, and
  /// the input's own faces are developed in it (develop_input_faces_hyperbolic) before the cut
  /// and the layout, which work on the input's faces and edges.
  MeshFlowResult flow;
  /// The converged metric refined in long double (residual curvature about 1e-18), which the
  /// layout uses.
  HyperbolicRefinement refinement;
  /// After flips: max relative difference between the hyperbolic lengths an input edge gets in
  /// its two developed faces (HyperbolicDevelopment::max_length_mismatch); 0 without flips.
  double development_length_mismatch = 0;
  CutGraph cut;  ///< on the input mesh's edges
  CutMesh cut_mesh;
  HyperbolicLayout layout;
  int cut_candidates_tried = 0;  ///< cuts laid out (HyperbolicParamOptions::cut_candidates)
  int cut_root = -1;             ///< root vertex of the kept cut (-1: cut_graph's default)
  /// Closed surfaces (genus >= 2): the canonical generators; has_group false otherwise (a
  /// surface with boundary has a free Fuchsian group, whose generators are the segment maps).
  bool has_group = false;
  /// A closed surface whose canonical generators could not be computed for any cut tried: why
  /// (at high genus the fundamental domain reaches so close to the circle that the segment maps'
  /// entries exceed what double precision rounds faithfully). The layout and the segment maps are
  /// still there.
  std::string group_failure;
  FuchsianGroup group;
  /// The disk layout against the 3D mesh: the Poincare model is conformal, so the angle
  /// distortion is that of the hyperbolic metric against the input (areas shrink towards the
  /// rim: the area figures measure the model, not the metric). With polygons: of their fans as
  /// written (measure_polygon_distortion).
  Distortion distortion;
  /// options.polygons, each listed from a corner whose fan is sound in the disk
  /// (start_fans_where_valid): the faces to write; empty without polygons.
  Polygons polygons;
  double seam_length = 0;  ///< 3D length of the cut edges
  /// Texture coordinates: the disk positions of the cut-mesh vertices (|uv| < 1), indexed per
  /// corner by cut_mesh.triangles (whose faces are the input mesh's, flips or not).
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  double seconds = 0;
};

/// Runs the pipeline on a single-component manifold mesh whose Euler characteristic is negative
/// (genus >= 2 closed, or with enough boundary loops).
/// \throw InvalidInput (several components, chi >= 0, scheme without a hyperbolic energy),
///        TopologyError
HyperbolicParamResult parameterize_hyperbolic(const Mesh& mesh,
                                              const HyperbolicParamOptions& options = {});

}  // namespace ricci
