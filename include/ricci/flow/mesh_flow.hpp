#pragma once
/// \file
/// The whole job on a mesh: conformal structure, target, admissibility, and the Ricci flow on
/// every connected component, one by one, with the results gathered on the whole mesh.

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/flow_problem.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/flow/target.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// Kinds of target the mesh-level driver builds.
enum class TargetKind {
  /// Per component, the flat target where its topology admits one (any surface with boundary,
  /// boundary as TargetSpec::boundary says; a closed torus), else uniform curvature (closed
  /// genus 0 or >= 2, which need cones to be flat: ricci/param/parameterize.hpp chooses them).
  /// With cones: Flat. In the hyperbolic background: Flat.
  Natural,
  Flat,     ///< zero curvature but at cones; boundary as TargetSpec::boundary says
  Uniform,  ///< 2 pi chi / n on every vertex of each component
  Values,   ///< one value per vertex, given
};

/// Python's target= names.
template <>
struct EnumNames<TargetKind> {
  static constexpr const char* noun = "value";
  static constexpr std::array<EnumName<TargetKind>, 4> names{{
      {TargetKind::Natural, "natural"},
      {TargetKind::Flat, "flat"},
      {TargetKind::Uniform, "uniform"},
      {TargetKind::Values, "values"},
  }};
};

/// The target, in whole-mesh vertex indices.
struct TargetSpec {
  TargetKind kind = TargetKind::Natural;
  std::vector<Cone> cones;                     ///< Flat: cone vertices and curvatures
  BoundaryMode boundary = BoundaryMode::Free;  ///< Flat on meshes with boundary
  Eigen::VectorXd values;                      ///< Values: #V curvatures
};

/// Options of flow_mesh.
struct MeshFlowOptions {
  StructureOptions structure;  ///< scheme and initial packing
  TargetSpec target;           ///< what curvature to reach
  FlowOptions flow;            ///< solver, tolerance, progress
  /// Numbers messages show for vertices (e.g. their index in the file, when the reader dropped
  /// unreferenced vertices); empty: the mesh's own indices.
  std::vector<int> vertex_labels;
};

/// The flow options of a pipeline that holds the metric and the solver's options apart from the
/// target it chooses itself (ParamOptions, SphereOptions, HyperbolicParamOptions): one place
/// that assembles them, for the pipelines and the reports that describe their flows.
inline MeshFlowOptions mesh_flow_options(const StructureOptions& structure, const FlowOptions& flow,
                                         TargetSpec target = {}) {
  MeshFlowOptions options;
  options.structure = structure;
  options.flow = flow;
  options.target = std::move(target);
  return options;
}

/// Result of one component.
struct ComponentFlow {
  std::vector<int> vertices;  ///< whole-mesh index of each component vertex
  int euler_characteristic = 0, genus = 0, boundary_loops = 0;
  /// in component-local indices; for a doubled component, in the doubled surface's
  FlowResult flow;
  /// The flow on the component failed next to its boundary (boundary edges cannot flip) and was
  /// run again on the component glued to its mirror image along the boundary, a closed surface
  /// whose interior flips reach every edge; `flow` is that run. Its vertices are the
  /// component's (local indices) followed by the mirror copies of the interior vertices.
  bool doubled = false;
  std::string first_attempt_message;  ///< why the flow on the component itself failed
  /// The doubled surface before flips (build_doubled_topology; its connectivity is
  /// flow.intrinsic.input(), on which the flow's flip log replays).
  Triangles doubled_triangles;
  std::vector<int> doubled_vertex_original;  ///< doubled vertex -> local vertex
  FaceShapes doubled_shapes;                 ///< the component's faces developed in the metric
};

/// What flow_mesh returns, gathered on the whole mesh.
struct MeshFlowResult {
  bool converged = false;  ///< every component converged
  /// Converged when every component converged; else the first failed component's status.
  FlowStatus status = FlowStatus::MaxIterations;
  /// Why each component stopped, in words (prefixed by the component's index when there are
  /// several).
  std::string message;
  /// The components' FlowResult::fixes, each once, in component order.
  std::vector<OptionFix> fixes;
  double max_error = 0;       ///< over all components
  StructureResult structure;  ///< whole-mesh structure and fit error
  Target target;              ///< whole-mesh target
  /// The whole mesh's triangulation after the flow (edges for `lengths`): its input, or its
  /// intrinsic Delaunay triangulation when edges were flipped (same vertices and face count),
  /// with the structure on it (intrinsic.eta(): structure.structure.eta but on flipped edges;
  /// with it the structure gives `lengths` at `u` on intrinsic.topology()). Its log holds the
  /// flips in whole-mesh edge indices, component after component, each flagged isometric (a
  /// component's initial retriangulation of the input metric) or Ptolemy: replayed on the
  /// input it reproduces intrinsic.topology() exactly. Doubled components (see
  /// ComponentFlow::doubled) keep the input's triangulation here and add no entries, only their
  /// counts (intrinsic.flips(), intrinsic.blocked_flips()); develop_input_faces(mesh, result)
  /// covers every component.
  IntrinsicTriangulation intrinsic;
  Eigen::VectorXd u;                 ///< #V final log radii
  Eigen::VectorXd curvature;         ///< #V final curvature
  Eigen::VectorXd target_curvature;  ///< #V target (final curvature where u was fixed)
  /// #E final lengths, edges as intrinsic.topology().edge_vertices
  Eigen::VectorXd lengths;
  Eigen::VectorXd input_lengths;  ///< #E lengths of the input mesh, its own edges
  std::vector<ComponentFlow> components;
  double setup_seconds = 0;  ///< topology, structure, target, checks
  double total_seconds = 0;
};

/// Builds the target of a spec on a whole mesh.
/// \throw InvalidInput on bad cones or values
Target build_target(const Topology& topology, const Eigen::VectorXd& input_lengths,
                    const TargetSpec& spec, const std::vector<int>& vertex_labels = {});

/// Every input face developed in the final metric (ricci/intrinsic/intrinsic_triangulation.hpp),
/// doubled components included: what the layouts of the input's own faces start from.
/// \pre flow = flow_mesh(mesh, ...) in the Euclidean background
Development develop_input_faces(const Mesh& mesh, const MeshFlowResult& flow);
/// The same with the input's connectivity at hand (build_topology(mesh)).
Development develop_input_faces(const Topology& input, const MeshFlowResult& flow);

/// Runs the flow on every component of a mesh. A component with boundary whose flow fails
/// (vertex scaling with flips, Euclidean background) is flowed again on its double
/// (ComponentFlow::doubled).
/// \pre the mesh passed validate_mesh
/// \throw TopologyError, InvalidInput (inadmissible target, naming the vertex), SolverError
MeshFlowResult flow_mesh(const Mesh& mesh, const MeshFlowOptions& options = {});
/// The same with the mesh's connectivity at hand. \pre topology = build_topology(mesh)
MeshFlowResult flow_mesh(const Mesh& mesh, const Topology& topology,
                         const MeshFlowOptions& options = {});
/// The same on a problem built once (ricci/flow/flow_problem.hpp): its topology, input lengths
/// and structure are used as they are (options.structure is not read).
MeshFlowResult flow_mesh(const FlowProblem& problem, const MeshFlowOptions& options = {});

}  // namespace ricci
