#include "ricci/param/parameterize.hpp"

#include "flow/detail/mesh_flow_internal.hpp"
#include "numerics/detail/parallel.hpp"
#include "param/detail/one_component.hpp"
#include "param/layout/detail/layout_support.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <utility>

#include "ricci/errors.hpp"
#include "ricci/flow/flow_problem.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/mesh/split.hpp"
#include "ricci/numerics/timer.hpp"
#include "ricci/param/cones/refine_curvatures.hpp"
#include "ricci/param/layout/polygon_fans.hpp"

namespace ricci {

namespace {

/// A fixed cone count too small for the curvature: about twice as many, or the automatic count.
std::vector<OptionFix> more_cones_fixes(std::size_t count) {
  return {OptionFix{"cones", std::to_string(2 * count + 2)}, OptionFix{"cones", "auto"}};
}

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Automatic cones are chosen again, with more of them, while the flat metric's log scale
/// spread exceeds the selection's bound by this factor ...
constexpr double kNonlinearSlack = 1.25;
/// ... or, on a closed surface of genus 0, while its area distortion E (area_distortion_of)
/// exceeds this: the spread is measured away from the cones, where a cone's own log scale
/// diverges, and a round sphere meets its bound with three cones while the areas around them
/// swell (E 4.1 on an icosphere and on the corpus's unit sphere, 6.8 on two of its balls; five
/// cones give 0.30, eight 0.07). (Not on higher genus: a genus-10 CAD part then got an exact map
/// of E 0.92 where the charts that stood in for its first one had 0.078) ...
constexpr double kAutoConesMaxEnergy = 0.5;
/// ... at most this many times.
constexpr int kConeRounds = 3;

/// Valence a cone of curvature k needs for the single-vertex bound with room to spare: each face
/// gives the cone at least the scheme's guaranteed angle (packings with Phi up to pi/2: pi/2; the
/// other schemes: pi), so valence > (2 pi - k) / guaranteed angle.
int required_valence(double k, Scheme scheme) {
  const double per_face = scheme_traits(scheme).guaranteed_face_angle;
  return static_cast<int>(std::floor((2 * std::numbers::pi - k) / per_face)) + 1;
}

}  // namespace

ConeMode parse_cone_mode(const std::string& name) {
  return parse_enum<ConeMode>(name, "parse_cone_mode");
}

const char* cone_mode_name(ConeMode mode) {
  return enum_name(mode);
}

SeamMode parse_seam_mode(const std::string& name) {
  return parse_enum<SeamMode>(name, "parse_seam_mode");
}

const char* seam_mode_name(SeamMode mode) {
  return enum_name(mode);
}

namespace {

/// One run of the single-component pipeline: the problem (connectivity, input lengths,
/// structure) built once for the mesh the flow runs on, the cone model built once from it, and
/// what the stages hand on to each other. A stage that changes the mesh (valence raising,
/// subdivision) makes the problem of the new mesh; nothing else builds one.
struct ParamRun {
  ParamRun(const Mesh& mesh, const ParamOptions& o, ParamResult& r, Topology topology)
      : input(mesh), options(o), result(r), input_topology(std::move(topology)) {}
  const Mesh& input;
  const ParamOptions& options;
  ParamResult& result;
  /// The input's connectivity until the problem takes it.
  Topology input_topology;
  std::optional<FlowProblem> problem;   ///< of result.mesh (of the input until it changes)
  std::optional<ConeModel> cone_model;  ///< of *problem, at the first automatic selection
  bool closed = false;
  int chi = 0;
  /// Edge flips: every admissible target is reachable on the mesh's own triangulation.
  bool flips = false;
  ConeMode mode = ConeMode::Needed;  ///< options.cone_mode with Needed resolved
  std::vector<Cone> cones;
  /// The flat metric with `cones` when a stage has flowed to it already (refine_few_cones):
  /// the flow starts there.
  Eigen::VectorXd start_u;

  /// The problem of the mesh the flow will run on, built at the first call.
  FlowProblem& the_problem(const Mesh& mesh) {
    if (!problem) problem = make_flow_problem(mesh, std::move(input_topology), options.structure);
    return *problem;
  }
  /// A new problem for a changed mesh (the cone model belonged to the old one).
  void remake_problem(const Mesh& mesh) {
    cone_model.reset();
    problem.reset();
    input_topology = build_topology(mesh.triangles, mesh.num_vertices());
    the_problem(mesh);
  }
  const ConeModel& the_cone_model() {
    if (!cone_model) cone_model = build_cone_model(the_problem(input));
    return *cone_model;
  }
};

/// Wall time since the previous lap, added to a phase of result.timings.
class Laps {
 public:
  void operator()(double& phase) {
    const auto now = Clock::now();
    phase += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }
  void restart() { last_ = Clock::now(); }

 private:
  Clock::time_point last_ = Clock::now();
};

/// Automatic cones from the run's model (ConeSelection in result.cone_selection).
std::vector<Cone> select_automatic(ParamRun& run, int count) {
  ConeSelectionOptions selection = run.options.auto_cones;
  selection.count = count;
  selection.boundary = run.options.boundary;
  selection.quantize = run.options.quantize;
  run.result.cone_selection = select_cones(run.the_cone_model(), selection);
  std::vector<Cone> chosen;
  const ConeSelection& s = run.result.cone_selection;
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    chosen.push_back({s.vertices[i], s.linear_curvature[i]});
  }
  return chosen;
}

/// Quarter-turn cone curvatures (ParamOptions::quantize).
void quantize(const ParamRun& run, std::vector<Cone>& chosen) {
  if (!run.options.quantize || chosen.empty()) return;
  double total = 0;
  for (const Cone& c : chosen) total += c.curvature;
  // Closed surfaces must keep 2 pi chi; with a boundary the nearest multiple of pi/2 will do.
  total = run.closed ? 2 * std::numbers::pi * run.chi
                     : std::round(total / (std::numbers::pi / 2)) * (std::numbers::pi / 2);
  chosen = quantize_cones(chosen, total);
}

/// Starts a flow to the flat metric with `cones` where the cone model's linearised flow puts
/// them (or at `flat`, that metric when a stage has flowed to it already), its first Newton
/// steps preconditioned by the model's factorisation (which must outlive the flow): that first
/// step and its factorisation are saved.
void start_at_model(const ConeModel& model, const FlowProblem& problem,
                    const std::vector<Cone>& cones, FlowOptions& flow,
                    const Eigen::VectorXd* flat = nullptr) {
  flow.start_u = flat ? *flat
                      : Eigen::VectorXd(problem.structure.structure.initial_u +
                                        linearised_log_factors(model, cones));
  flow.start_preconditioner = [model = &model](const Eigen::VectorXd& r) {
    return linearised_inverse(*model, r, /*approximately=*/true);
  };
}

/// Steps of the few-cone refinement at most: most of the gain comes in the first few (eight 3,
/// 3holes 7, fertility 5; fertility with 8 cones took 16 steps, 1 s, from 0.72 to 0.50).
constexpr int kRefinementSteps = 8;
/// The refinement's drawable bound on a cone: corners up to this on average (the selection's
/// 0.6 pi is what few cones on chi < 0 cannot meet) and this at most.
constexpr double kRefinedFaceAngle = 0.9 * std::numbers::pi;
constexpr double kRefinedCornerAngle = 0.95 * std::numbers::pi;

/// Few cones on a closed surface of chi < 0, too few for the selection's bounds (eight with 4,
/// 3holes with 5): the linearised model misjudges such strong cones (eight, 4 cones: E 0.385
/// where cones spread more evenly give 0.29). Two candidates are measured by one flow each:
/// the selection's cones, and cones placed where the scale is extreme at one level
/// (select_level_cones); the lower area distortion is kept, its curvatures refined on the flow
/// itself (refine_cone_curvatures), and its flat metric starts the pipeline's flow.
void refine_few_cones(ParamRun& run) {
  const ParamOptions& options = run.options;
  if (!run.closed || run.chi >= 0 || options.auto_cones.count <= 0 || options.quantize ||
      !run.flips || run.cones.empty() || run.result.cone_selection.within_bounds) {
    return;
  }
  const FlowProblem& problem = run.the_problem(run.input);
  ConeSelection level = select_level_cones(run.the_cone_model(), options.auto_cones.count);
  std::vector<Cone> level_cones;
  for (std::size_t i = 0; i < level.vertices.size(); ++i) {
    level_cones.push_back({level.vertices[i], level.linear_curvature[i]});
  }
  // Each candidate's flat metric first; only the less distorting one is refined. The two flows
  // are independent: the level cones' runs beside (these meshes are small, so each flow keeps to
  // one thread), unless the caller's flow options hold a preconditioner, which may not be called
  // from two threads at once.
  CurvatureRefinementOptions measure_only;
  measure_only.max_steps = 0;
  // Each flow starts where the cone model's linearised flow puts its cones, preconditioned by
  // the model's factorisation (as the pipeline's flow, start_where_linearised), unless the
  // caller's options bring their own.
  const ConeModel& model = run.the_cone_model();
  const auto flow_from_model = [&](const std::vector<Cone>& cones) {
    FlowOptions flow = options.flow;
    if (!flow.start_preconditioner && flow.start_u.size() == 0) {
      start_at_model(model, problem, cones, flow);
    }
    return flow;
  };
  const FlowOptions level_flow = flow_from_model(level_cones);
  const FlowOptions selected_flow = flow_from_model(run.cones);
  const auto measure_level = [&] {
    return refine_cone_curvatures(problem, level_cones, level_flow, measure_only);
  };
  parallel::Task<CurvatureRefinement> placed_beside;
  if (!options.flow.start_preconditioner) placed_beside = parallel::run_beside(measure_level);
  const CurvatureRefinement selected =
      refine_cone_curvatures(problem, run.cones, selected_flow, measure_only);
  const CurvatureRefinement placed = placed_beside.valid() ? placed_beside.get() : measure_level();
  const bool take_level =
      placed.converged && (!selected.converged || placed.area_energy < selected.area_energy);
  ConeRefinementReport& report = run.result.cone_refinement;
  report.ran = true;
  report.level_cones = take_level;
  report.selected_energy = selected.converged ? selected.area_energy : kInf;
  report.level_energy = placed.converged ? placed.area_energy : kInf;
  if (!take_level && !selected.converged) return;
  FlowOptions flow = options.flow;
  flow.start_u = take_level ? placed.u : selected.u;
  const std::vector<Cone>& start = take_level ? level_cones : run.cones;
  // No cone pushed past what its faces can draw (or past where it starts): stronger ones fold
  // the exact map (fertility, 6 cones: E 0.53 in the flat metric, but faces flipped).
  CurvatureRefinementOptions bounded;
  bounded.max_steps = kRefinementSteps;
  ConeSelectionOptions drawable = options.auto_cones;
  drawable.max_face_angle = kRefinedFaceAngle;
  drawable.max_corner_angle = kRefinedCornerAngle;
  for (const Cone& c : start) {
    bounded.lower_bounds.push_back(cone_lower_bound(run.the_cone_model(), drawable, c.vertex));
  }
  CurvatureRefinement best = refine_cone_curvatures(problem, start, flow, bounded);
  report.refined_energy = best.area_energy;
  report.steps = best.steps;
  report.flows = best.flows + 2;  // (and the two candidates' flows)
  if (!best.converged) {          // (the selection's cones stay, as they were)
    report.level_cones = false;
    return;
  }
  if (take_level) run.result.cone_selection = std::move(level);
  run.cones = best.cones;
  for (std::size_t i = 0; i < best.cones.size(); ++i) {
    run.result.cone_selection.linear_curvature[i] = best.cones[i].curvature;
  }
  run.start_u = std::move(best.u);
}

/// Stage 1: the singularities, in input vertex indices.
void choose_cones(ParamRun& run) {
  const ParamOptions& options = run.options;
  const Component& component = run.input_topology.components[0];
  const int genus = component.genus, boundary_loops = component.num_boundary_loops;
  switch (run.mode) {
    case ConeMode::Needed:
      break;
    case ConeMode::None:
      if (run.closed && run.chi != 0) {
        throw InvalidInput("parameterize: a closed surface of genus " + std::to_string(genus) +
                               " has no flat metric without cones (chi = " +
                               std::to_string(run.chi) + "); use automatic cones or one cone",
                           genus >= 2 ? fixes_of({{"cones", "auto"}, {"cones", "one"}})
                                      : fixes_of({{"cones", "auto"}}));
      }
      break;
    case ConeMode::User:
      run.cones = options.cones;
      break;
    case ConeMode::OneCone: {
      if (!run.closed || genus < 2) {
        throw InvalidInput(
            "parameterize: one cone of 2 pi chi is for closed surfaces of genus >= "
            "2; this one has genus " +
                std::to_string(genus) + " and " + std::to_string(boundary_loops) +
                " boundary loops",
            fixes_of({{"cones", "needed"}, {"cones", "auto"}}));
      }
      ConeSelectionOptions one = options.auto_cones;
      one.count = 1;
      one.try_first_cone_candidates = 16;
      one.max_cones = 1;
      run.result.cone_selection = select_cones(run.the_cone_model(), one);
      run.cones.push_back(
          {run.result.cone_selection.vertices.front(), 2 * std::numbers::pi * run.chi});
      break;
    }
    case ConeMode::Auto:
      // Free seams choose their cones with the cut, once the flow's problem is made.
      if (options.seams == SeamMode::Free) break;
      run.cones = select_automatic(run, options.auto_cones.count);
      for (const Cone& c : run.cones) {
        // A fixed count too small for the curvature (two cones on a sphere): the least-squares
        // curvatures leave every bound behind. Say so instead of the flow's refusal of a vertex.
        if (!run.result.cone_selection.within_bounds && !(c.curvature < 2 * std::numbers::pi)) {
          throw InvalidInput("parameterize: " + std::to_string(run.cones.size()) +
                                 " automatic cones cannot carry the curvature within their bounds "
                                 "(vertex " +
                                 std::to_string(c.vertex) + " would need " +
                                 std::to_string(c.curvature) +
                                 ", a cone angle below 0); ask for more cones, or let the count be "
                                 "chosen automatically",
                             more_cones_fixes(run.cones.size()));
        }
      }
      refine_few_cones(run);
      break;
  }
}

/// Stage 2: local connectivity modification, raising the valence of cones that need it (without
/// flips only). The problem of the raised mesh is made when edges were split.
void raise_cone_valence(ParamRun& run) {
  ParamResult& result = run.result;
  result.mesh = run.input;
  result.vertex_origin.resize(run.input.num_vertices());
  for (int v = 0; v < run.input.num_vertices(); ++v) result.vertex_origin[v] = v;
  // With flips every admissible target is reachable on the input's own triangulation, which is
  // kept. (A cone much stronger than its valence then shows as flipped uv triangles around it, as
  // every map drawn linearly on the input's faces does; the common refinement is exact.)
  if (run.options.modify_connectivity && !run.flips) {
    // Degrees of the current mesh: the input's connectivity, rebuilt only after a split.
    std::optional<Topology> raised;
    for (const Cone& cone : run.cones) {
      if (cone.vertex < 0 || cone.vertex >= result.mesh.num_vertices()) continue;  // flat_target
      const Topology& t = raised        ? *raised
                          : run.problem ? run.problem->topology
                                        : run.input_topology;
      const int needed = required_valence(cone.curvature, run.options.structure.scheme);
      if (t.vertex_degree[cone.vertex] >= needed) continue;
      ValenceResult r = raise_valence(result.mesh, t, cone.vertex, needed);
      result.mesh = std::move(r.mesh);
      result.edge_splits += r.splits;
      for (const auto& parents : r.new_vertex_parents) {
        result.added_vertex_parents.push_back(parents);
        result.vertex_origin.push_back(-1);
      }
      raised = std::move(r.topology);
    }
    if (raised) {
      run.cone_model.reset();
      run.problem.reset();
      run.input_topology = std::move(*raised);
    }
  }
  result.cones = run.cones;
}

}  // namespace

ParamResult parameterize_one_component(const Mesh& input, const ParamOptions& options) {
  return parameterize_one_component(input, options,
                                    build_topology(input.triangles, input.num_vertices()));
}

namespace {

/// What the cut stage makes: the cut graph through the cones, the sliced mesh and the layout's
/// root faces. It needs only the connectivity and the 3D lengths, so it can run beside the flow.
struct CutStage {
  CutGraph cut;
  CutMesh cut_mesh;
  layout_support::Roots roots;  // of the layout (default options), chosen ahead
  double seconds = 0;
};

/// The polygons the run keeps whole: ParamOptions::polygons while the mesh has the input's faces
/// (no edge split); null otherwise.
const Polygons* kept_polygons(const ParamRun& run) {
  const bool same_faces = run.result.edge_splits == 0 && !run.result.subdivided;
  return same_faces && !run.options.polygons.empty() ? &run.options.polygons : nullptr;
}

/// A cut made elsewhere, sliced, with the layout's roots.
CutStage cut_stage_of(const FlowProblem& problem, CutGraph cut) {
  const auto t = Clock::now();
  CutStage stage;
  stage.cut = std::move(cut);
  stage.cut_mesh = slice(problem.topology, stage.cut);
  stage.roots.faces = layout_support::root_faces(stage.cut_mesh.topology, LayoutOptions{}.root_face,
                                                 stage.roots.first);
  stage.seconds = seconds_since(t);
  return stage;
}

/// Stage 4a: the cut through these cones on the problem's connectivity, never along the
/// diagonals of the polygons (when not null).
CutStage cut_through(const FlowProblem& problem, const std::vector<Cone>& cones,
                     const Polygons* polygons) {
  const auto t = Clock::now();
  CutGraphOptions cut_options;
  for (const Cone& c : cones) cut_options.cones.push_back(c.vertex);
  if (polygons != nullptr) cut_options.uncut_edges = polygon_diagonals(problem.topology, *polygons);
  CutStage stage =
      cut_stage_of(problem, cut_graph(problem.topology, problem.input_lengths, cut_options));
  stage.seconds = seconds_since(t);
  return stage;
}

/// The flow stage's state: the problem it runs on, its options, and the cut made beside it.
struct FlowStage {
  FlowProblem* problem = nullptr;
  MeshFlowOptions options;
  /// Whether the flow's result refers to the problem's triangulation as its input (handed over
  /// at the end of the pipeline).
  bool kept_topology = false;
  /// When the flow cannot change the connectivity (no subdivision possible) the cut runs beside
  /// it, on a core the flow's factorisation leaves idle.
  parallel::Task<CutStage> cut_ahead;

  MeshFlowResult run(bool& kept) const {
    return mesh_flow_internal::flow_mesh_keeping_topology(*problem, options, kept);
  }
  /// The cut beside the flow reads the problem: wait for it before the problem changes.
  void drop_cut_ahead() {
    if (cut_ahead.valid()) cut_ahead.wait();
    cut_ahead = {};
  }
};

bool same_cones(const std::vector<Cone>& a, const std::vector<Cone>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const Cone& x, const Cone& y) {
    return x.vertex == y.vertex && x.curvature == y.curvature;
  });
}

/// The flow to the flat metric with the stage's cones starts where the cone model's linearised
/// flow puts it: that first Newton step comes from the model's factorisation, and the flow saves
/// its own (kitten, 8 cones: 5 factorisations instead of 6). Only where the model is the flow's
/// linearisation: automatic cones on the problem the model was built on (no edge split since),
/// flat target with the boundary held (free) or no boundary.
void start_where_linearised(ParamRun& run, FlowStage& stage) {
  FlowOptions& flow = stage.options.flow;
  flow.start_u.resize(0);
  flow.start_preconditioner = nullptr;
  const TargetSpec& target = stage.options.target;
  if (!run.cone_model || !run.problem || stage.problem != &*run.problem ||
      target.kind != TargetKind::Flat || run.options.seams != SeamMode::Rigid ||
      (stage.problem->topology.num_boundary_loops() > 0 && target.boundary != BoundaryMode::Free)) {
    return;
  }
  const bool flowed = run.start_u.size() == stage.problem->topology.num_vertices &&
                      same_cones(target.cones, run.cones);
  // (run keeps the model through the flow.)
  start_at_model(*run.cone_model, *stage.problem, target.cones, flow,
                 flowed ? &run.start_u : nullptr);
}

/// Stage 3: the Ricci flow to the flat metric with the run's cones, with its fallbacks: one
/// midpoint subdivision when a packing degenerates, and rounds of more automatic cones while the
/// flat metric spreads past the selection's bound.
void flow_to_flat(ParamRun& run, FlowStage& stage) {
  const ParamOptions& options = run.options;
  ParamResult& result = run.result;
  std::vector<Cone>& cones = run.cones;
  try {
    result.flow = stage.run(stage.kept_topology);
  } catch (const InvalidInput& e) {
    // The user's own cones refused (Gauss-Bonnet, a bound): automatic ones are the fix here,
    // not the flow's target options.
    if (options.cone_mode != ConeMode::User || e.fixes().empty()) throw;
    throw InvalidInput(e.what(), fixes_of({{"cones", "auto"}}));
  }
  result.converged = result.flow.converged;
  // (Free seams chose their target on this mesh's cut: no subdivision under them.)
  const bool may_subdivide = options.modify_connectivity && !run.flips && !cones.empty() &&
                             options.seams == SeamMode::Rigid;
  const FlowStatus status = result.flow.status;
  if (!result.converged && may_subdivide &&
      (status == FlowStatus::SolverFailed || status == FlowStatus::LineSearchFailed)) {
    // A degenerating metric means Thurston's conditions fail on vertex sets around a strong cone,
    // not on the cone alone: its neighbours lack faces. One midpoint subdivision gives every
    // neighbourhood four times the faces (input vertices keep their indices; each new vertex is
    // an edge midpoint). The subdivided mesh has a problem of its own.
    stage.drop_cut_ahead();
    const int before = result.mesh.num_vertices();
    const Topology& t = stage.problem->topology;
    result.mesh = subdivide_midpoint(result.mesh);
    for (int e = 0; e < t.num_edges; ++e) {
      result.added_vertex_parents.push_back({t.edge_vertices(e, 0), t.edge_vertices(e, 1)});
      result.vertex_origin.push_back(-1);
    }
    result.edge_splits += result.mesh.num_vertices() - before;
    result.subdivided = true;
    run.remake_problem(result.mesh);
    stage.problem = &*run.problem;
    // The start and its preconditioner belonged to the old mesh's model (gone with it): cleared.
    start_where_linearised(run, stage);
    result.flow = stage.run(stage.kept_topology);
    result.converged = result.flow.converged;
  }
  // 3b. The selection's model is the flow linearised at the input metric, which holds while u
  // stays small. Strong cones leave it: on a CAD cylinder three cones of 1.5 pi each met the
  // linear bound, but the flat metric scaled areas by e^4 (area distortion energy 4.5, angle
  // distortion 3.2; eight cones give 0.031 and 1.43). Where the flow's own u spreads well past
  // the bound, more cones are chosen (from the same model) and the flow run again (on the same
  // problem), keeping the better of the two.
  // (Free seams: the cones only shape the cut, their curvature is the seams'.)
  if (run.mode != ConeMode::Auto || options.auto_cones.count != 0 || !run.flips ||
      !result.converged || options.seams == SeamMode::Free) {
    return;
  }
  std::vector<int> vertices;
  vertices.reserve(cones.size());
  for (const Cone& c : cones) vertices.push_back(c.vertex);
  result.log_scale_spread = log_scale_spread(run.the_cone_model(), result.flow.u, vertices);
  const bool sphere = run.closed && run.chi > 0;
  double energy = sphere ? area_distortion_of(run.the_cone_model(), result.flow.u) : 0.0;
  for (int round = 0; round < kConeRounds; ++round) {
    const bool by_spread =
        result.log_scale_spread > kNonlinearSlack * options.auto_cones.max_log_scale;
    const bool by_energy = energy > kAutoConesMaxEnergy;
    if (!by_spread && !by_energy) break;
    const int n = static_cast<int>(cones.size());
    ConeSelection previous = result.cone_selection;
    std::vector<Cone> more = select_automatic(run, std::max(n + 2, (3 * n + 1) / 2));
    // Fewer: the cap on the number of cones, or no more candidates; out of bounds: no such cone
    // set is drawable. Either way the first one stays.
    if (static_cast<int>(more.size()) <= n || !result.cone_selection.within_bounds) {
      result.cone_selection = std::move(previous);
      break;
    }
    quantize(run, more);
    stage.options.target.cones = more;
    start_where_linearised(run, stage);
    MeshFlowResult flow;
    bool kept = false;
    try {
      flow = stage.run(kept);
    } catch (const InvalidInput&) {  // a target the flow refuses: keep the first cones
      result.cone_selection = std::move(previous);
      stage.options.target.cones = cones;
      start_where_linearised(run, stage);
      break;
    }
    vertices.clear();
    for (const Cone& c : more) vertices.push_back(c.vertex);
    const double spread =
        flow.converged ? log_scale_spread(run.the_cone_model(), flow.u, vertices) : kInf;
    const double more_energy = !sphere          ? 0.0
                               : flow.converged ? area_distortion_of(run.the_cone_model(), flow.u)
                                                : kInf;
    ++result.cone_rounds;
    // Kept when it lowers what asked for it.
    if (!((by_spread && spread < result.log_scale_spread) || (by_energy && more_energy < energy))) {
      result.cone_selection = std::move(previous);
      stage.options.target.cones = cones;
      start_where_linearised(run, stage);
      break;
    }
    cones = std::move(more);
    // The cut made beside the first flow runs through the old cones: cut again.
    stage.drop_cut_ahead();
    result.cones = cones;
    result.flow = std::move(flow);
    stage.kept_topology = kept;
    result.log_scale_spread = spread;
    energy = more_energy;
  }
}

/// Faces of a layout with signed area <= 0.
int count_flipped(const Triangles& triangles, const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  int n = 0;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::Vector2d a = uv.row(triangles(f, 0)).transpose();
    const Eigen::Vector2d b = uv.row(triangles(f, 1)).transpose() - a;
    const Eigen::Vector2d c = uv.row(triangles(f, 2)).transpose() - a;
    n += !(b.x() * c.y() - b.y() * c.x() > 0);
  }
  return n;
}

/// Stage 4: cut graph through the cones, slicing, layout, angle polish, atlas and distortion,
/// all on the mesh's own faces. After Delaunay flips the flat metric lives on the intrinsic
/// triangulation; each input face is developed in it (its corners at their exact images), so the
/// cut runs along input edges and the layout, the seams and the written faces are the user's.
void cut_and_lay_out(ParamRun& run, FlowStage& stage, Laps& lap) {
  ParamResult& result = run.result;
  const FlowProblem& problem = *stage.problem;
  const Topology& topology = problem.topology;
  const Polygons* polygons = kept_polygons(run);
  CutStage cut =
      stage.cut_ahead.valid() ? stage.cut_ahead.get() : cut_through(problem, run.cones, polygons);
  result.cut = std::move(cut.cut);
  result.cut_mesh = std::move(cut.cut_mesh);
  // The stage's own time (run beside the flow it took no time of the pipeline's own).
  result.timings.cut += cut.seconds;
  lap.restart();
  const Development development = develop_input_faces(topology, result.flow);
  result.development_length_mismatch = development.max_length_mismatch;
  lap(result.timings.development);
  result.layout = layout_support::layout_flat_with_roots(
      topology, development.shapes, result.cut, result.cut_mesh, LayoutOptions{}, cut.roots);
  lap(result.timings.layout);
  if (run.options.polish.enabled) {
    result.polish =
        polish_angles(result.mesh, result.cut_mesh.triangles, result.layout.uv, run.options.polish);
    // The layout takes the polished positions; polish.uv keeps the flat metric's own.
    std::swap(result.layout.uv, result.polish.uv);
    lap(result.timings.polish);
  }
  if (run.options.fold_free.untangle && result.layout.uv.allFinite() &&
      result.layout.max_length_relative_error <= run.options.fold_free.max_length_error) {
    // (A layout that does not close up is no map to untangle: parameterize replaces it.)
    // Faces drawn flipped (needles whose vertices' exact images come out in clockwise order)
    // untangled: cones and the boundary stay, seam vertices move with all their copies.
    UntangleOptions untangle;
    // A free boundary's shape is the flat metric's but nothing asks for it; a disk's is.
    untangle.move_boundary = run.options.boundary == BoundaryMode::Free;
    // With the charts to fall back on, a layout that cannot come out fold-free is left as is.
    untangle.give_up_when_stuck = run.options.fold_free.charts;
    untangle.fixed.assign(result.mesh.num_vertices(), 0);
    untangle.angles.assign(result.mesh.num_vertices(), 2 * std::numbers::pi);
    // A cone whose angle its faces cannot hold, each below pi, leaves one of them flipped
    // whatever else moves: no untangling is tried then.
    if (run.options.seams == SeamMode::Free) {
      // Free seams: the copies of a seam vertex differ by no rigid motion, so none can move
      // with the others; the cut's vertices (and the boundary) stay where the metric put them.
      untangle.move_boundary = false;
      const std::vector<char> on_cut = cut_vertices(topology, result.cut);
      for (int v = 0; v < topology.num_vertices; ++v) {
        if (!on_cut[v]) continue;
        untangle.fixed[v] = 1;
        untangle.angles[v] = 2 * std::numbers::pi - result.flow.target_curvature[v];
      }
    }
    bool overloaded = false;
    for (const Cone& c : result.cones) {
      if (c.vertex < 0 || c.vertex >= result.mesh.num_vertices()) continue;
      untangle.fixed[c.vertex] = 1;
      untangle.angles[c.vertex] = 2 * std::numbers::pi - c.curvature;
      const int faces = topology.vertex_degree[c.vertex] - topology.is_boundary_vertex[c.vertex];
      overloaded = overloaded || 2 * std::numbers::pi - c.curvature >= faces * std::numbers::pi;
    }
    if (overloaded) {
      result.untangle = {};
      result.untangle.flipped_before = count_flipped(result.cut_mesh.triangles, result.layout.uv);
      result.untangle.flipped_after = result.untangle.stuck_faces = result.untangle.flipped_before;
    } else {
      result.untangle =
          untangle_layout(result.mesh, result.cut_mesh.triangles, result.layout.uv, untangle);
      if (result.untangle.moved_vertices > 0) result.layout.uv = std::move(result.untangle.uv);
      result.untangle.uv.resize(0, 2);
    }
    lap(result.timings.untangle);
  }
  result.atlas = affine_atlas(topology, result.cut, result.cut_mesh, result.layout);
  lap(result.timings.atlas);
  // The faces written: the triangles, or each polygon from a corner whose fan is sound.
  if (polygons != nullptr) {
    result.polygons =
        start_fans_where_valid(*polygons, result.mesh, result.cut_mesh.triangles, result.layout.uv);
  }
  result.distortion = measure_polygon_distortion(result.mesh, result.polygons,
                                                 result.cut_mesh.triangles, result.layout.uv);
  lap(result.timings.distortion);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (result.cut.is_cut_edge[e]) result.seam_length += problem.input_lengths[e];
  }
}

/// Stage 5: texture coordinates in the unit square, aspect ratio kept.
void to_unit_square(ParamResult& result) {
  const Eigen::Vector2d lo = result.layout.uv.colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = result.layout.uv.colwise().maxCoeff().transpose();
  const double extent = (hi - lo).maxCoeff();
  result.uv_offset = lo;
  result.uv_scale = extent > 0 ? 1.0 / extent : 1.0;
  result.uv = (result.layout.uv.rowwise() - lo.transpose()) * result.uv_scale;
}

/// Stage 3 with free seams: the flow's target is the chosen curvature at every vertex: flat off
/// the cut (a disk boundary as its mode asks), the cut's vertices, the cones among them, and a
/// free boundary at the curvature that distorts least (free_seams.hpp). `linear_u` gets the
/// linearised flow's solution for that target (the flow's start).
TargetSpec free_seams_spec(FreeSeamTarget chosen, ParamResult& result, Eigen::VectorXd& linear_u) {
  linear_u = std::move(chosen.linear_u);
  result.seam_curvature.free_seconds = chosen.seconds;
  result.seam_curvature.linear_area_energy = chosen.linear_area_energy;
  result.seam_curvature.capped_vertices = chosen.capped_vertices;
  TargetSpec spec;
  spec.kind = TargetKind::Values;
  spec.values = std::move(chosen.target.curvature);
  return spec;
}

/// The curvature the final metric leaves at the cut's vertices that are not cones.
void measure_seam_curvature(ParamResult& result, const Topology& topology) {
  std::vector<char> seam = cut_vertices(topology, result.cut);
  for (const Cone& c : result.cones) {
    if (c.vertex >= 0 && c.vertex < topology.num_vertices) seam[c.vertex] = 0;
  }
  SeamCurvature& s = result.seam_curvature;
  s.vertices = 0;
  s.total = s.max = 0;
  for (int v = 0; v < topology.num_vertices; ++v) {
    if (!seam[v] || topology.is_boundary_vertex[v]) continue;
    const double k = std::abs(result.flow.curvature[v]);
    ++s.vertices;
    s.total += k;
    s.max = std::max(s.max, k);
  }
}

/// Rigid seams on genus >= 1 with the cones asked for (a count or the user's): when the map
/// distorts area strongly, too few cones for an exact map of this genus; says so.
void check_cone_count(ParamRun& run) {
  const ParamOptions& options = run.options;
  const bool asked = options.cone_mode == ConeMode::User ||
                     (options.cone_mode == ConeMode::Auto && options.auto_cones.count > 0);
  const int genus = run.problem ? run.problem->topology.components.at(0).genus : 0;
  const double e = run.result.distortion.area_distortion_energy;
  const int folded = run.result.distortion.flipped_faces;
  if (options.seams != SeamMode::Rigid || !asked || genus < 1 ||
      !(e > kTooFewConesEnergy || folded > 0)) {
    return;
  }
  std::ostringstream message;
  message << std::setprecision(3) << run.cones.size()
          << " cones are too few for an exact map (rigid seams) of this genus-" << genus
          << " surface to be good: its area distortion E is " << e;
  if (folded > 0) message << " and " << folded << " faces fold around its strong cones";
  message << ". Seams that may bend (seams free) or more cones (cones auto) distort far less";
  run.result.too_few_cones = message.str();
}

/// The stages, in order, filling `result` (all but its total time).
void run_pipeline(const Mesh& input, const ParamOptions& options, Topology t0,
                  ParamResult& result) {
  if (t0.components.size() != 1) {
    throw InvalidInput("parameterize: the mesh has " + std::to_string(t0.components.size()) +
                       " connected components");
  }
  ParamRun run(input, options, result, std::move(t0));
  run.closed = run.input_topology.components[0].num_boundary_loops == 0;
  run.chi = run.input_topology.components[0].euler_characteristic;
  run.flips = options.flow.flips == EdgeFlips::Delaunay ||
              (options.flow.flips == EdgeFlips::Auto &&
               scheme_traits(options.structure.scheme).ptolemy_flips);
  run.mode = options.cone_mode;
  if (run.mode == ConeMode::Needed) {
    run.mode = run.closed && run.chi != 0 ? ConeMode::Auto : ConeMode::None;
  }
  Laps lap;

  // 1-2. Cones, and the valence they need.
  choose_cones(run);
  lap(result.timings.cones);
  quantize(run, run.cones);
  raise_cone_valence(run);

  // 3. The flow, on the problem every later stage reads, built once (for the raised mesh when
  // edges were split), with the cut (stage 4a) beside it when the connectivity cannot change.
  FlowStage stage;
  stage.problem = &run.the_problem(result.mesh);
  TargetSpec flat;
  flat.kind = TargetKind::Flat;
  flat.cones = run.cones;
  flat.boundary = options.boundary;
  const bool free_seams = options.seams == SeamMode::Free;
  std::optional<CutStage> cut_first;
  Eigen::VectorXd free_start;
  if (free_seams) {
    const Target prescribed =
        flat_target(stage.problem->topology, {}, options.boundary, stage.problem->input_lengths);
    if (run.mode == ConeMode::Auto) {
      // Automatic cones with free seams are the cut's ends, chosen for the seams
      // (select_free_seam_cones), together with the cut.
      CutGraphOptions cutting;
      if (const Polygons* polygons = kept_polygons(run)) {
        cutting.uncut_edges = polygon_diagonals(stage.problem->topology, *polygons);
      }
      FreeSeamCones chosen =
          select_free_seam_cones(*stage.problem, prescribed, options.auto_cones.count,
                                 options.auto_cones.max_log_scale, cutting, options.free_seams);
      run.cones.clear();
      for (int v : chosen.cones) run.cones.push_back({v, chosen.seams.target.curvature[v]});
      result.cones = run.cones;
      cut_first = cut_stage_of(*stage.problem, std::move(chosen.cut));
      flat = free_seams_spec(std::move(chosen.seams), result, free_start);
    } else {
      // The seams' curvature is chosen on the cut through the given cones.
      cut_first = cut_through(*stage.problem, run.cones, kept_polygons(run));
      flat = free_seams_spec(
          free_seam_target(*stage.problem, cut_first->cut, prescribed, options.free_seams), result,
          free_start);
    }
    lap(result.timings.cones);  // (the seams' cones and curvature: the cones' stage)
  }
  stage.options = mesh_flow_options(options.structure, options.flow, std::move(flat));
  start_where_linearised(run, stage);
  if (free_start.size() == stage.problem->topology.num_vertices) {
    // Free seams: the seams' choice solved the flow linearised at the initial metric for this
    // very target, so the flow starts at its solution and saves that first Newton step (bob, 4
    // cones: 5 -> 4 steps, 22 -> 16 ms). (ricci_flow drops a start that is no better.)
    stage.options.flow.start_u = stage.problem->structure.structure.initial_u + free_start;
  }
  const bool may_subdivide = options.modify_connectivity && !run.flips && !run.cones.empty();
  if (cut_first) {
    stage.cut_ahead = parallel::Task<CutStage>::ready(std::move(*cut_first));
  } else if (!may_subdivide) {
    // (The cones are copied: the rounds of stage 3b may choose others while this runs.)
    stage.cut_ahead = parallel::run_beside(
        [problem = stage.problem, cones = run.cones, polygons = kept_polygons(run)] {
          return cut_through(*problem, cones, polygons);
        });
  }
  flow_to_flat(run, stage);
  lap(result.timings.flow);
  if (result.converged) {
    cut_and_lay_out(run, stage, lap);
    measure_seam_curvature(result, stage.problem->topology);
    check_cone_count(run);
    to_unit_square(result);
  } else {
    stage.drop_cut_ahead();
    result.message = result.flow.message;
  }
  // The flows' results refer to the problem's triangulation as their input: it is handed over to
  // them now that the stages are done with it (no copy).
  if (stage.kept_topology) {
    mesh_flow_internal::adopt_input_topology(
        result.flow, std::make_shared<const Topology>(std::move(stage.problem->topology)));
  }
}

}  // namespace

ParamResult parameterize_one_component(const Mesh& input, const ParamOptions& options,
                                       Topology topology) {
  const auto start = Clock::now();
  ParamResult result;
  run_pipeline(input, options, std::move(topology), result);
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace ricci
