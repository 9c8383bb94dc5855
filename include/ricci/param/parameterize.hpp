#pragma once
/// \file
/// The global conformal parameterization pipeline (tutorial sections 5 and 6): singularity
/// selection, local connectivity modification, Ricci flow to a flat metric with cones, cut graph,
/// planar layout, affine atlas and distortion figures. Mesh in, texture coordinates out.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/mesh_flow.hpp"
#include "ricci/param/atlas.hpp"
#include "ricci/param/cones.hpp"
#include "ricci/param/cut_graph.hpp"
#include "ricci/param/distortion.hpp"
#include "ricci/param/layout.hpp"

namespace ricci {

/// Where the cones come from.
enum class ConeMode {
  /// Cones only where the topology needs them: none on a torus or a surface with boundary (its
  /// flat metric exists without), automatic (Auto) on closed surfaces of genus 0 or >= 2.
  Needed,
  None,     ///< no cones: genus 1 closed, or any surface with boundary (free or disk boundary)
  User,     ///< ParamOptions::cones as given
  Auto,     ///< select_cones (a count, or until the log scale bound holds), also on surfaces
            ///< that need none
  OneCone,  ///< all curvature 2 pi chi at one vertex (genus >= 2), chosen by select_cones
};

/// "needed", "none", "user", "auto", "one". \throw InvalidInput otherwise
ConeMode parse_cone_mode(const std::string& name);
const char* cone_mode_name(ConeMode mode);

/// Options of parameterize.
struct ParamOptions {
  ConeMode cone_mode = ConeMode::Needed;
  std::vector<Cone> cones;          ///< ConeMode::User: vertices (input indices) and curvatures
  ConeSelectionOptions auto_cones;  ///< ConeMode::Auto: count or log-scale bound
  bool quantize = false;            ///< round cone curvatures to multiples of pi/2
  BoundaryMode boundary = BoundaryMode::Free;  ///< free or disk boundary
  StructureOptions structure;                  ///< discrete metric scheme
  /// Newton to 1e-12: the layout closes around each interior vertex only as well as the metric
  /// is flat there, and 1e-10 leaves length errors of 2e-9 on meshes of ~5k vertices.
  FlowOptions flow = [] {
    FlowOptions f;
    f.tolerance = 1e-12;
    return f;
  }();
  /// Without edge flips (the circle packings): split edges around cones whose valence breaks the
  /// single-vertex bound (tutorial 5.3), and subdivide once when the flow still degenerates.
  /// With flips (vertex scaling, the default) every admissible target is reached on the input's
  /// own triangulation, which is never modified.
  bool modify_connectivity = true;
};

/// Wall time of each stage of parameterize, seconds.
struct ParamTimings {
  double cones = 0;        ///< topology checks and cone selection
  double flow = 0;         ///< connectivity modification and the Ricci flow
  double cut = 0;          ///< cut graph and slicing
  double development = 0;  ///< the input's faces developed in the flow's metric
  double layout = 0;       ///< planar layout (with its least-squares refinement)
  double atlas = 0;        ///< affine atlas
  double distortion = 0;   ///< distortion figures
};

/// What parameterize returns.
struct ParamResult {
  bool converged = false;  ///< the flow reached its tolerance
  std::string message;     ///< why not, when it did not
  /// The mesh parameterized: the input itself (same vertices, faces and order), except that the
  /// Thurston scheme's valence raising (modify_connectivity) appends the vertices its edge splits
  /// add. With edge flips the flat metric lives on the flow's intrinsic triangulation
  /// (flow.topology, flow.flipped_edges), and the layout places the input's own faces in it.
  Mesh mesh;
  std::vector<int> vertex_origin;  ///< per output vertex: input vertex, or -1 when added
  std::vector<std::array<int, 2>> added_vertex_parents;  ///< per added vertex: the edge it splits
  int edge_splits = 0;  ///< connectivity modifications made (edges split)
  /// The flow degenerated around a strong cone even after raising its valence, so the whole mesh
  /// was subdivided once (every edge split at its midpoint) and the flow run again.
  bool subdivided = false;
  std::vector<Cone> cones;       ///< final cones (output vertex indices) and curvatures
  ConeSelection cone_selection;  ///< ConeMode::Auto / OneCone: the greedy history
  MeshFlowResult flow;           ///< the Ricci flow to the flat metric
  /// With flips: how well the development of the input faces in the intrinsic metric closes up
  /// (largest relative difference of an input edge's length seen from its two faces).
  double development_length_mismatch = 0;
  CutGraph cut;
  CutMesh cut_mesh;
  Layout layout;  ///< raw layout (metric units)
  AffineAtlas atlas;
  Distortion distortion;
  double seam_length = 0;  ///< 3D length of the cut edges
  /// Texture coordinates in the unit square (aspect ratio kept): one per cut-mesh vertex;
  /// uv_triangles = cut_mesh.triangles indexes them per corner.
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  double uv_scale = 1;  ///< uv = (layout - offset) * uv_scale
  Eigen::Vector2d uv_offset = Eigen::Vector2d::Zero();
  double seconds = 0;
  ParamTimings timings;
};

/// Runs the pipeline on a single-component manifold mesh.
/// \throw InvalidInput (bad cones, inadmissible target, several components), TopologyError
ParamResult parameterize(const Mesh& mesh, const ParamOptions& options = {});

}  // namespace ricci
