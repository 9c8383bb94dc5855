#pragma once
/// \file
/// Singularity selection (tutorial section 5.2): where to put cones, and how much curvature each
/// carries, so that the flat metric distorts area little.
///
/// The model is the flow linearised at the input metric: K(u) ~ K + L u, with L the cotangent
/// Laplacian of the input's intrinsic Delaunay triangulation (the scheme's own Hessian for the
/// circle packings). A flat metric with cones k_s at the vertices s of S (and u = 0 on a free
/// boundary) has log scale u(k) = A^-1 (sum_s k_s e_s - K): affine in the curvatures. For a cone
/// set S the curvatures minimise
///     log(1 + E(u)) + smoothness D(u) / #F,
/// E = sum_f a_f (e^{2 u_f} / Z - 1)^2 (Z = sum_f a_f e^{2 u_f}; u_f the mean of u over face f,
/// a_f its share of the 3D area) the area distortion energy of the tutorial's eq. 9, and
/// D = u^T L u the Dirichlet energy of u, the angle distortion's stand-in (a discrete conformal
/// map distorts a face's angles by about |grad u| h). They are subject to Gauss-Bonnet on a closed
/// surface (sum k = 2 pi chi) and to bounds that keep every cone drawable on the input's own
/// faces: a cone's angle 2 pi - k spread over its faces as straight uv triangles needs every
/// corner there below pi (max_face_angle, max_corner_angle), and k <= max_curvature. The
/// minimisation (quasi-Newton with bounded quadratic steps) starts from the minimiser of the
/// L2 norm J = sum_v a_v (u_v - mean u)^2, a quadratic programme.
/// Cones are added greedily where the objective's gradient with respect to a new cone's
/// curvature (one solve for every vertex at once) is largest, at least 3 rings from the cones
/// already there, until max |u - mean u| <= max_log_scale and every cone is within its bounds.
/// One factorisation serves the whole selection (the cones are sources, not constraints).

#include <memory>
#include <vector>

#include "ricci/flow/flow_problem.hpp"
#include "ricci/flow/mesh_flow.hpp"

namespace ricci {

/// Options of select_cones.
struct ConeSelectionOptions {
  int count = 0;  ///< place exactly this many cones; 0: as many as max_log_scale needs
  /// Add cones until max |u - mean u| (the largest log area scale factor of the linearised flat
  /// metric, relative to its mean) is at most this.
  double max_log_scale = 1.0;
  /// Never more than this many; 0: no cap (a count places that many; the automatic count stops
  /// at max_log_scale, or once doubling the cones lowers its measure by less than 5 %).
  int max_cones = 0;
  /// On a closed surface the first cone is needed before anything can be solved; try this many
  /// well-spread candidates for it (farthest-point samples) and keep the least distorting one.
  int try_first_cone_candidates = 8;
  /// Largest average uv corner angle a cone may ask of the faces around it (radians): a cone at
  /// a vertex of valence deg gets curvature at least 2 pi - max_face_angle deg (pi is the hard
  /// limit of straight uv triangles).
  double max_face_angle = 0.6 * 3.14159265358979323846;
  /// Largest uv corner angle at a cone, estimated as the largest input corner there scaled by
  /// (cone angle) / (input angle sum): bounds the curvature of a cone at an irregular vertex.
  /// On eight.off cones at the average bound alone flipped the faces whose input corner at the
  /// cone was 105 and 107 degrees (scaled to about 190).
  double max_corner_angle = 0.75 * 3.14159265358979323846;
  /// Largest curvature of a cone (radians; its angle is 2 pi - this).
  double max_curvature = 4.71238898038469;  // 1.5 pi
  /// Boundary treatment while cones are chosen: Free holds the boundary at u = 0 (it flattens
  /// with no cone needed); the disk modes leave it free as well during selection.
  BoundaryMode boundary = BoundaryMode::Free;
  /// Weight of the angle distortion against the area distortion: the curvatures minimise
  /// log(1 + E) + smoothness D / #F, D the Dirichlet energy of the linearised log scale u (a
  /// discrete conformal map distorts a face's angles by about |grad u| h). 0: E alone, which
  /// pairs strong cones of both signs (angle distortion 1.077 on spot with 32 cones, BFF 1.058);
  /// 1000: 1.058 there (docs/cones.md has the sweep).
  double smoothness = 1000;
  /// Curvatures in multiples of pi/2 (seamless maps, quad meshing), chosen in the model: the
  /// minimiser rounded with its sum kept, then quarter turns moved between cones while the
  /// objective falls. A cone left at 0 has no curvature (parameterize drops it).
  bool quantize = false;
  StructureOptions structure;  ///< the scheme whose Hessian linearises the flow
};

/// What select_cones returns.
struct ConeSelection {
  std::vector<int> vertices;          ///< cone vertices in the order they were chosen
  std::vector<double> max_log_scale;  ///< max |u - mean u| after each addition (linearised)
  /// The curvature of each cone minimising J (in the order of `vertices`): on a closed surface
  /// they sum to 2 pi chi; with a boundary the boundary takes the rest.
  std::vector<double> linear_curvature;
  double log_scale_rms = 0;  ///< sqrt(J / total area) at the end
  /// The area distortion E (tutorial eq. 9) of the linearised flat metric at the end.
  double area_energy = 0;
  /// Whether every cone's curvature lies within its bounds. Automatic count: when the selection
  /// ends out of bounds (the cap on the number of cones, or an infeasible bounded problem), the
  /// last cone set that met them is returned (`vertices` cut back to it; `max_log_scale` keeps
  /// the whole history); false only when none did. A fixed count: false when no curvatures of
  /// that many cones meet the bounds (the least-squares curvatures are returned as they are).
  bool within_bounds = true;
};

/// The flow linearised at the input metric (the Laplacian of the problem's structure, or of the
/// input's intrinsic Delaunay triangulation), factorised once, with the areas and angles the
/// selection reads: what every cone selection on one mesh shares. parameterize builds it once
/// per run and selects from it as often as its rounds need.
class ConeModel {
 public:
  struct Data;  ///< defined in cones.cpp
  explicit ConeModel(std::unique_ptr<Data> data);
  ConeModel(ConeModel&&) noexcept;
  ConeModel& operator=(ConeModel&&) noexcept;
  ~ConeModel();
  const Data& data() const { return *data_; }

 private:
  std::unique_ptr<Data> data_;
};

/// Builds the cone model of a problem (ricci/flow/flow_problem.hpp). The model reads the
/// problem's topology: the problem must outlive it.
/// \pre the problem's mesh is a single connected component that passed validate_mesh
/// \throw InvalidInput when it has several components or its initial metric breaks a triangle
///        inequality
ConeModel build_cone_model(const FlowProblem& problem);

/// Chooses cone vertices and curvatures (see the file comment) on a model built once
/// (options.structure is not read: the model's problem has its structure).
/// \throw InvalidInput when options are out of range
ConeSelection select_cones(const ConeModel& model, const ConeSelectionOptions& options);

/// `count` cones where the linearised flat metric scales most, each cone's log scale held at one
/// common level (the greedy placement of Ben-Chen, Gotsman and Bunin 2008, which CEPS uses): the
/// first where the constant-curvature metric scales most (closed surfaces), each next one where
/// the level fit of the cones so far scales most, then four sweeps moving each cone to where
/// the others' fit scales most. Curvatures: the level fit's (no bounds: `within_bounds` is true,
/// `max_log_scale` empty). A candidate for few cones on a closed surface of chi < 0, where the
/// bounded selection cannot meet its bounds and the linearised objective misjudges strong cones
/// (parameterize runs the flow on both and keeps the lower area distortion).
/// \throw InvalidInput when count < 1
ConeSelection select_level_cones(const ConeModel& model, int count);

/// The lowest curvature select_cones lets a cone at v take (drawable on the input's faces:
/// options.max_face_angle and max_corner_angle).
double cone_lower_bound(const ConeModel& model, const ConeSelectionOptions& options, int v);

/// The flow linearised at the model's metric, i.e. its first Newton step from there: the log
/// factors (#V, relative to the problem's initial u) whose linearised curvature is each cone's
/// at its vertex and 0 at every other vertex that is not held; held vertices (a boundary, and the
/// gauge vertex of a closed surface) stay at 0. A start for the flow to the flat metric with
/// these cones (FlowOptions::start_u, after adding the initial u) that saves the factorisation
/// of that step: the model has it.
/// \throw InvalidInput when a cone's vertex is out of range
Eigen::VectorXd linearised_log_factors(const ConeModel& model, const std::vector<Cone>& cones);

/// The linearised flow's inverse applied to r (#V): the model's Laplacian, its held vertices
/// pinned by a penalty, solved with its factorisation; held entries of the result are 0. Near
/// the flat metric's Hessian away from strong cones, so it preconditions the flow's first Newton
/// steps (FlowOptions::start_preconditioner) in place of a factorisation of their own.
/// approximately: to about single precision (SparseCholesky::solve_approximately), which is all
/// a preconditioner needs, and faster on large meshes.
/// \throw InvalidInput when r does not have #V entries
Eigen::VectorXd linearised_inverse(const ConeModel& model, const Eigen::VectorXd& r,
                                   bool approximately = false);

/// The same on a mesh: builds its problem (options.structure) and model, then selects.
/// \pre the mesh is a single connected component that passed validate_mesh
/// \throw InvalidInput when options are out of range
ConeSelection select_cones(const Mesh& mesh, const ConeSelectionOptions& options = {});

/// max |u - mean u| (area-weighted mean) of log scale factors u of the mesh's vertices, leaving
/// out the cones and up to 3 rings around each (at most 2 % of the area per cone, where
/// select_cones leaves out 3 whole rings): the measure `max_log_scale` bounds, for a nonlinear
/// flow's u.
/// \param u #V log scale factors; cones: vertex indices
double log_scale_spread(const Mesh& mesh, const Topology& topology, const Eigen::VectorXd& u,
                        const std::vector<int>& cones);
/// The same with the areas of a cone model (its problem's mesh and topology).
double log_scale_spread(const ConeModel& model, const Eigen::VectorXd& u,
                        const std::vector<int>& cones);

/// Area distortion E (eq. 9) of log scale factors u with a cone model's areas, each face's
/// share scaled by e^{2 u_f} (u_f its corners' mean): the measure ConeSelection::area_energy
/// reports for the model's own u, here for a nonlinear flow's.
/// \throw InvalidInput when u does not have #V entries
double area_distortion_of(const ConeModel& model, const Eigen::VectorXd& u);

/// Rounds cone curvatures to multiples of pi/2 keeping their sum (which must itself be a
/// multiple of pi/2, as 2 pi chi minus a boundary total is for the flat targets): the cones with
/// the largest rounding remainders are rounded the other way until the sum matches. Cones whose
/// curvature rounds to 0 are dropped.
std::vector<Cone> quantize_cones(const std::vector<Cone>& cones, double total);

}  // namespace ricci
