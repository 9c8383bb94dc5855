#pragma once
/// \file
/// How the intrinsic triangulation a flow with edge flips ends on corresponds to the input
/// triangulation, and how the input's own faces sit in the final metric.
///
/// A flow with Ptolemy flips (ricci/intrinsic/delaunay_flips.hpp) ends on a triangulation T' of the
/// same surface with the same vertices: the input triangulation T after a sequence of flips.
/// flip_edge is a deterministic function of the topology and the edge, so the list of flipped
/// edges is the whole correspondence: replaying it on T gives T', and every intermediate
/// triangulation on the way.
///
/// The final metric is flat (or has its target curvature) at the vertices and is a Euclidean
/// triangle on every face of T'. A face of T is a disk on the surface with no vertex inside, so
/// the metric develops it into the plane; its three corners land at three points, the exact
/// images of the input vertices. develop_input_faces computes them by undoing the flips one by
/// one: undoing the flip of edge e glues its two current faces along e (a rigid motion taking
/// one face's copy of e onto the other's) and reads the old faces' corners off that quad. No
/// flip changes a face's index, so every face of T ends with its own corners. Delta-complexes
/// (double edges, loops, a face using a vertex twice) need nothing special: faces are developed
/// as abstract triangles, corner by corner.
///
/// A hyperbolic metric (curvature -1 in every triangle) is developed the same way into the
/// Poincare disk, with hyperbolic isometries (Moebius maps of the disk) in place of rigid motions,
/// in long double: the hyperbolic layout and the Fuchsian group it leads to amplify every rounding
/// error (ricci/hyperbolic/hyperbolic_refinement.hpp).
///
/// IntrinsicTriangulation is the one home of such a triangulation: the input connectivity, the
/// current (flipped) one, the conformal structure carried onto it (eta per intrinsic edge) and
/// the flip log that is its correspondence to the input. The flow (RicciFlow) flips it, and the
/// flow's and the mesh flow's results (FlowResult::intrinsic, MeshFlowResult::intrinsic), the
/// layouts and the writers read it; the common refinement replays its log through
/// replay_flips_with_overlay and reads what that returns. The Topology arrays of a flipped
/// triangulation are written by this module only (flip_edge and the functions built on it).

#include <array>
#include <complex>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/intrinsic/edge_overlay.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// Per face of a triangulation, its three corners in a plane of its own (corner k is the vertex
/// triangles(f, k)); the faces of one development are each placed up to a rigid motion.
using FaceShapes = std::vector<std::array<std::complex<double>, 3>>;

/// Applies flip_edge to each edge in order, on a copy of `input`.
/// \throw InvalidInput naming the position in the list when an edge is out of range or cannot be
///        flipped (boundary edge, or inside one self-glued face)
Topology replay_flips(const Topology& input, const std::vector<int>& flipped_edges);

/// What replay_flips_with_overlay returns: the start triangulation after the flips, its edges as
/// curves over the result, and the lengths the flips give the new edges.
struct OverlaidReplay {
  Topology topology;        ///< the start triangulation after the flips
  EdgeOverlay overlay;      ///< the start's edges over `topology`
  Eigen::VectorXd lengths;  ///< #E: the start's lengths, each flipped edge given its new one
};

/// How replay_flips_with_overlay lengthens a flipped edge.
enum class FlipLength {
  Isometric,  ///< isometric_diagonal: the same surface, retriangulated
  Ptolemy,    ///< ptolemy_diagonal: the same conformal class
};

/// Applies flip_edge_with_overlay to each edge in order, on a copy of `start` with the start's
/// edges as curves (identity_overlay), and gives each flipped edge the diagonal of its quad at
/// the lengths before that flip (ricci/intrinsic/delaunay_flips.hpp, in `geometry`). This is how
/// the common refinement replays a flow's flip log: T0 over T1 by isometric flips, T1 over T' by
/// Ptolemy flips.
/// \param lengths #E lengths of start's edges
/// \throw InvalidInput naming the position in the list when an edge is out of range or cannot be
///        flipped; as flip_edge_with_overlay
OverlaidReplay replay_flips_with_overlay(const Topology& start, const Eigen::VectorXd& lengths,
                                         const std::vector<int>& flipped_edges, FlipLength kind,
                                         Geometry geometry = Geometry::Euclidean);

/// What develop_input_faces returns.
struct Development {
  FaceShapes shapes;  ///< #F: the input faces' corners, each face in a frame of its own
  /// #E of the input: each input edge's length in the final metric (the distance between its
  /// developed ends), as seen from its first face.
  Eigen::VectorXd lengths;
  /// max over interior input edges of the relative difference between the lengths the edge gets
  /// in its two faces (0 in exact arithmetic; a few ulps times the number of flips undone
  /// across the edge in practice).
  double max_length_mismatch = 0;
  int flipped_faces = 0;     ///< input faces developed with negative orientation
  int degenerate_faces = 0;  ///< input faces developed with (relative) zero area
};

/// Develops every face of the input triangulation in the final metric (see the file comment).
/// \param input the input triangulation T (edges as in the flow's input)
/// \param flipped_edges the flips that turned T into the final triangulation T' (replayed here)
/// \param final_lengths #E lengths of T''s edges (a flip reuses the index of the edge it removes)
/// \pre final_lengths satisfy the triangle inequalities on every face of T'
/// \throw InvalidInput when the flips cannot be replayed or a final face breaks a triangle
///        inequality
Development develop_input_faces(const Topology& input, const std::vector<int>& flipped_edges,
                                const Eigen::VectorXd& final_lengths);

/// The shapes of a triangulation's faces from its edge lengths: corner 0 at 0, corner 1 on the
/// positive real axis, corner 2 above it (angles by the half-angle formula).
/// \throw InvalidInput naming the face when its lengths break a triangle inequality
FaceShapes face_shapes_from_lengths(const Topology& topology, const Eigen::VectorXd& lengths);

/// Per face of a triangulation, its three corners in the Poincare disk (|z| < 1), in long double;
/// each face in a frame of its own: corner 0 at the centre, corner 1 on the positive real axis.
using WideFaceShapes = std::vector<std::array<std::complex<long double>, 3>>;

/// What develop_input_faces_hyperbolic returns.
struct HyperbolicDevelopment {
  WideFaceShapes shapes;  ///< #F: the input faces' corners in the disk, each in its own frame
  /// #E of the input: each input edge's hyperbolic length in the final metric, as seen from its
  /// first face.
  WideVector lengths;
  /// max over interior input edges of the relative difference between the hyperbolic lengths the
  /// edge gets in its two faces (0 in exact arithmetic).
  double max_length_mismatch = 0;
  int flipped_faces = 0;     ///< input faces developed with negative orientation
  int degenerate_faces = 0;  ///< input faces developed with (relative) zero area
};

/// develop_input_faces for a hyperbolic metric: every face of the input triangulation developed
/// into the Poincare disk, in long double, by undoing the flips with hyperbolic isometries.
/// \param final_lengths #E hyperbolic lengths of T''s edges (refine_hyperbolic_metric's)
/// \pre final_lengths satisfy the triangle inequalities on every face of T'
/// \throw InvalidInput when the flips cannot be replayed or a final face breaks a triangle
///        inequality
HyperbolicDevelopment develop_input_faces_hyperbolic(const Topology& input,
                                                     const std::vector<int>& flipped_edges,
                                                     const WideVector& final_lengths);

/// The shapes of a triangulation's hyperbolic faces from their edge lengths: corner 0 at the
/// centre of the disk, corner 1 on the positive real axis at tanh(l / 2), corner 2 above it.
/// \throw InvalidInput naming the face when its lengths break a triangle inequality
WideFaceShapes hyperbolic_face_shapes_from_lengths(const Topology& topology,
                                                   const WideVector& lengths);

/// A triangulation of the input surface with the input's vertices, reached from the input
/// triangulation by edge flips (see the file comment): its connectivity, the conformal structure
/// on it, and the flips that made it.
///
/// Copy-on-write: it starts as the input itself, shared and never copied, and makes its own copy
/// of the connectivity at the first flip, so a mesh that is Delaunay already (the usual case, on
/// a million faces too) costs no copy. Copies of an IntrinsicTriangulation share their
/// connectivity until one of them flips. The input is held by a shared pointer: owned (shared),
/// or only referred to (the constructor from a reference; adopt_input hands it over later).
///
/// The structure is the input's, except that eta on flipped edges is what the flips set (a flip
/// reuses the index of the edge it removes), so that edge_lengths of structure() on topology()
/// gives the metric's lengths at any u. The flip log lists the flipped edges in order (replayed
/// on the input it gives topology()), with a flag per flip saying whether it was isometric.
///
/// Design: the structure is held here rather than passed to flip_to_delaunay, since its eta is
/// per intrinsic edge (a structure passed in would carry a second eta, stale after a flip). The
/// correspondence to the input is the log: how each intrinsic edge crosses the input edges
/// (normal coordinates, ricci/intrinsic/edge_overlay.hpp) is replayed from it where needed
/// (ricci/param/refinement/common_refinement.hpp). Components of a mesh flow on their own
/// triangulations and are gathered into the whole mesh's with gather_component.
class IntrinsicTriangulation {
 public:
  /// Empty: no input, no connectivity (a result not filled in).
  IntrinsicTriangulation() = default;
  /// The input triangulation itself, not copied, with its conformal structure.
  /// \pre structure belongs to *input (#V epsilon and initial_u, #E eta)
  /// \throw InvalidInput when input is null or the structure's sizes do not match
  IntrinsicTriangulation(std::shared_ptr<const Topology> input, ConformalStructure structure);
  /// The same, referring to `input` without owning it: the caller keeps it alive while this
  /// object or a copy reads it (or hands it over with adopt_input).
  IntrinsicTriangulation(const Topology& input, ConformalStructure structure);

  /// Hands over the input: `input` replaces the one referred to (e.g. an owned copy, or the same
  /// connectivity moved elsewhere), and topology() reads it while no edge is flipped.
  /// \throw InvalidInput when its vertex, edge or face count differs from the current input's
  void adopt_input(std::shared_ptr<const Topology> input);

  bool empty() const { return input_ == nullptr; }
  /// The input triangulation (before any flip); an empty Topology when empty().
  const Topology& input() const;
  const std::shared_ptr<const Topology>& shared_input() const { return input_; }
  /// The current connectivity: the input's object itself until the first flip, then this
  /// triangulation's own; an empty Topology when empty().
  const Topology& topology() const;
  /// Whether topology() is a connectivity of its own (some edge was flipped).
  bool owns_topology() const { return flipped_ != nullptr; }
  /// The conformal structure on topology(): the input's, eta set by the flips on flipped edges.
  const ConformalStructure& structure() const { return structure_; }
  /// #E eta per intrinsic edge (structure().eta).
  const Eigen::VectorXd& eta() const { return structure_.eta; }
  /// Replaces eta (the whole mesh's, gathered from its components' flows).
  /// \throw InvalidInput when the size is not #E
  void set_eta(Eigen::VectorXd eta);

  /// Edges flipped, counting the flips of parts whose connectivity is not kept here (see
  /// add_flip_counts); flipped_edges().size() otherwise.
  int flips() const { return flips_; }
  /// The flip log: flip_edge applied to these edges in order on input() gives topology().
  const std::vector<int>& flipped_edges() const { return flipped_edges_; }
  /// Per entry of flipped_edges(): 1 for an isometric flip (the input metric retriangulated into
  /// its intrinsic Delaunay triangulation), 0 for a Ptolemy flip (the same conformal class).
  const std::vector<char>& flip_is_isometric() const { return flip_is_isometric_; }
  /// How many flips of the log were isometric (in a flow: the first ones).
  int isometric_flips() const;
  /// Non-Delaunay edges left unflipped by the last flip_to_delaunay (DelaunayFlipResult::blocked),
  /// summed over the parts gathered.
  int blocked_flips() const { return blocked_; }

  /// flip_to_delaunay (ricci/intrinsic/delaunay_flips.hpp) on this triangulation at log radii u,
  /// its flips appended to the log (flagged isometric when options.isometric) and blocked_flips
  /// set to the result's. The connectivity is copied first only when some edge fails the
  /// Delaunay test and none is owned yet (or it is shared with a copy).
  /// \param[in,out] lengths #E current lengths l(u), updated on flipped edges
  /// \throw InvalidInput when the structure is not vertex scaling
  DelaunayFlipResult flip_to_delaunay(const Eigen::VectorXd& u, Eigen::VectorXd& lengths,
                                      const DelaunayFlipOptions& options = {});

  /// Whether topology() is a simplicial complex (ricci::is_simplicial).
  bool is_simplicial() const;
  /// The log replayed on the input (replay_flips): equal to topology(), array by array.
  /// \throw InvalidInput as replay_flips
  Topology replayed() const;

  /// Every input face developed in the final metric (ricci::develop_input_faces with this log).
  /// \param final_lengths #E lengths of topology()'s edges
  Development develop_input_faces(const Eigen::VectorXd& final_lengths) const;
  /// The same in a hyperbolic metric (ricci::develop_input_faces_hyperbolic).
  HyperbolicDevelopment develop_input_faces_hyperbolic(const WideVector& final_lengths) const;

  /// Gathers the flows of a whole mesh's components: writes a component's triangulation into
  /// this one, the whole mesh's (the component's faces and edges keep their whole-mesh indices,
  /// only what they join changes), appends its log in whole-mesh edge indices and adds its
  /// counts. eta is left to set_eta. Components gathered one after the other give the log that,
  /// replayed on the whole input, reproduces topology().
  /// \param part the component's triangulation, in component-local indices
  /// \param faces, vertex_map, edge_map component-local face, vertex and edge -> whole mesh;
  ///        part.input()'s faces keep their corner order and its edges their first halfedge
  ///        (as the whole mesh's), vertex_map ascending
  /// \throw InvalidInput when the maps do not match the part's sizes
  void gather_component(const IntrinsicTriangulation& part, const std::vector<int>& faces,
                        const std::vector<int>& vertex_map, const std::vector<int>& edge_map);
  /// Adds a part's flip and blocked counts only (its connectivity and log stay with it: a
  /// component flowed on its double, or a separately parameterized component).
  void add_flip_counts(const IntrinsicTriangulation& part);

 private:
  /// The connectivity the next flip may change: owned and not shared with a copy.
  Topology& own_topology();

  std::shared_ptr<const Topology> input_;
  std::shared_ptr<Topology> flipped_;  // null until the first flip; shared by copies until then
  ConformalStructure structure_;
  int flips_ = 0, blocked_ = 0;
  std::vector<int> flipped_edges_;
  std::vector<char> flip_is_isometric_;
};

}  // namespace ricci
