#include "ricci/param/parameterize.hpp"

#include "../flow/mesh_flow_internal.hpp"
#include "../mesh/parallel.hpp"
#include "layout_support.hpp"
#include "parameterize_component.hpp"
#include "ricci/metric/intrinsic_triangulation.hpp"

#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <numbers>
#include <utility>

#include "ricci/errors.hpp"
#include "ricci/mesh/split.hpp"

namespace ricci {

namespace {

/// A fixed cone count too small for the curvature: about twice as many, or the automatic count.
std::vector<OptionFix> more_cones_fixes(std::size_t count) {
  return {OptionFix{"cones", std::to_string(2 * count + 2)}, OptionFix{"cones", "auto"}};
}

using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
/// Automatic cones are chosen again, with more of them, while the flat metric's log scale
/// spread exceeds the selection's bound by this factor ...
constexpr double kNonlinearSlack = 1.25;
/// ... at most this many times.
constexpr int kConeRounds = 3;

/// Valence a cone of curvature k needs for the single-vertex bound with room to spare: packings
/// with Phi up to pi/2 give each face at least pi/2, so valence > (2 pi - k) / (pi/2); the other
/// schemes give each face up to pi, so valence > (2 pi - k) / pi.
int required_valence(double k, Scheme scheme) {
  const bool packing = scheme == Scheme::Thurston || scheme == Scheme::Tangential;
  const double per_face = packing ? kPi / 2 : kPi;
  return static_cast<int>(std::floor((2 * kPi - k) / per_face)) + 1;
}

}  // namespace

ConeMode parse_cone_mode(const std::string& name) {
  if (name == "needed") return ConeMode::Needed;
  if (name == "none") return ConeMode::None;
  if (name == "user") return ConeMode::User;
  if (name == "auto") return ConeMode::Auto;
  if (name == "one") return ConeMode::OneCone;
  throw InvalidInput("parse_cone_mode: unknown cone mode '" + name +
                     "'; expected needed, none, user, auto or one");
}

const char* cone_mode_name(ConeMode mode) {
  switch (mode) {
    case ConeMode::Needed:
      return "needed";
    case ConeMode::None:
      return "none";
    case ConeMode::User:
      return "user";
    case ConeMode::Auto:
      return "auto";
    case ConeMode::OneCone:
      return "one";
  }
  return "unknown";
}

ParamResult parameterize_one_component(const Mesh& input, const ParamOptions& options) {
  return parameterize_one_component(input, options,
                                    build_topology(input.triangles, input.num_vertices()));
}

ParamResult parameterize_one_component(const Mesh& input, const ParamOptions& options,
                                       Topology t0) {
  const auto start = Clock::now();
  ParamResult result;
  // Wall time since the previous lap, added to a phase of result.timings.
  auto last = start;
  auto lap = [&last](double& phase) {
    const auto now = Clock::now();
    phase += std::chrono::duration<double>(now - last).count();
    last = now;
  };
  if (t0.components.size() != 1) {
    throw InvalidInput("parameterize: the mesh has " + std::to_string(t0.components.size()) +
                       " connected components");
  }
  // (Copied: t0 is rebuilt below when the Thurston scheme splits edges.)
  const int genus = t0.components[0].genus, boundary_loops = t0.components[0].num_boundary_loops;
  const bool closed = boundary_loops == 0;
  const int chi = t0.components[0].euler_characteristic;

  // 1. Singularities, in input vertex indices.
  auto select_auto = [&](int count) {
    ConeSelectionOptions selection = options.auto_cones;
    selection.count = count;
    selection.structure = options.structure;
    selection.boundary = options.boundary;
    selection.quantize = options.quantize;
    result.cone_selection = select_cones(input, selection);
    std::vector<Cone> chosen;
    for (std::size_t i = 0; i < result.cone_selection.vertices.size(); ++i) {
      chosen.push_back(
          {result.cone_selection.vertices[i], result.cone_selection.linear_curvature[i]});
    }
    return chosen;
  };
  auto quantize = [&](std::vector<Cone>& chosen) {
    if (!options.quantize || chosen.empty()) return;
    double total = 0;
    for (const Cone& c : chosen) total += c.curvature;
    // Closed surfaces must keep 2 pi chi; with a boundary the nearest multiple of pi/2 will do.
    total = closed ? 2 * kPi * chi : std::round(total / (kPi / 2)) * (kPi / 2);
    chosen = quantize_cones(chosen, total);
  };
  std::vector<Cone> cones;
  ConeMode mode = options.cone_mode;
  if (mode == ConeMode::Needed) mode = closed && chi != 0 ? ConeMode::Auto : ConeMode::None;
  switch (mode) {
    case ConeMode::Needed:
      break;
    case ConeMode::None:
      if (closed && chi != 0) {
        throw InvalidInput("parameterize: a closed surface of genus " + std::to_string(genus) +
                               " has no flat metric without cones (chi = " + std::to_string(chi) +
                               "); use automatic cones or one cone",
                           genus >= 2 ? fixes_of({{"cones", "auto"}, {"cones", "one"}})
                                      : fixes_of({{"cones", "auto"}}));
      }
      break;
    case ConeMode::User:
      cones = options.cones;
      break;
    case ConeMode::OneCone: {
      if (!closed || genus < 2) {
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
      one.structure = options.structure;
      one.max_cones = 1;
      result.cone_selection = select_cones(input, one);
      cones.push_back({result.cone_selection.vertices.front(), 2 * kPi * chi});
      break;
    }
    case ConeMode::Auto:
      cones = select_auto(options.auto_cones.count);
      for (const Cone& c : cones) {
        // A fixed count too small for the curvature (two cones on a sphere): the least-squares
        // curvatures leave every bound behind. Say so instead of the flow's refusal of a vertex.
        if (!result.cone_selection.within_bounds && !(c.curvature < 2 * kPi)) {
          throw InvalidInput("parameterize: " + std::to_string(cones.size()) +
                                 " automatic cones cannot carry the curvature within their bounds "
                                 "(vertex " +
                                 std::to_string(c.vertex) + " would need " +
                                 std::to_string(c.curvature) +
                                 ", a cone angle below 0); ask for more cones, or let the count be "
                                 "chosen automatically",
                             more_cones_fixes(cones.size()));
        }
      }
      break;
  }
  lap(result.timings.cones);
  quantize(cones);

  // 2. Local connectivity modification: raise the valence of cones that need it.
  result.mesh = input;
  result.vertex_origin.resize(input.num_vertices());
  for (int v = 0; v < input.num_vertices(); ++v) result.vertex_origin[v] = v;
  // With flips every admissible target is reachable on the input's own triangulation, which is
  // kept. (A cone much stronger than its valence then shows as flipped uv triangles around it, as
  // every map drawn linearly on the input's faces does; the common refinement is exact.)
  const bool flips =
      options.flow.flips == EdgeFlips::Delaunay ||
      (options.flow.flips == EdgeFlips::Auto && options.structure.scheme == Scheme::VertexScaling);
  if (options.modify_connectivity && !flips) {
    for (const Cone& cone : cones) {
      if (cone.vertex < 0 || cone.vertex >= result.mesh.num_vertices()) continue;  // flat_target
      const Topology t = build_topology(result.mesh.triangles, result.mesh.num_vertices());
      const int needed = required_valence(cone.curvature, options.structure.scheme);
      if (t.vertex_degree[cone.vertex] >= needed) continue;
      ValenceResult raised = raise_valence(result.mesh, cone.vertex, needed);
      result.mesh = std::move(raised.mesh);
      result.edge_splits += raised.splits;
      for (const auto& parents : raised.new_vertex_parents) {
        result.added_vertex_parents.push_back(parents);
        result.vertex_origin.push_back(-1);
      }
    }
  }
  result.cones = cones;
  // The connectivity every later stage reads, built once (again only if edges were split).
  if (result.edge_splits > 0)
    t0 = build_topology(result.mesh.triangles, result.mesh.num_vertices());

  // 4 (ahead). The cut graph through the cones and the slicing need only the connectivity and
  // the 3D lengths: when the flow cannot change the connectivity (no subdivision possible) they
  // run beside it, on a core the flow's factorisation leaves idle.
  struct CutStage {
    Eigen::VectorXd lengths_3d;
    CutGraph cut;
    CutMesh cut_mesh;
    layout_support::Roots roots;  // of the layout (default options), chosen ahead
    double seconds = 0;
  };
  // (The cones are copied: the rounds of step 3b may choose others while this runs.)
  auto cut_stage = [&input = std::as_const(result.mesh)](const Topology& topology,
                                                         std::vector<Cone> through) {
    const auto t = Clock::now();
    CutStage stage;
    stage.lengths_3d = input_edge_lengths(input, topology);
    CutGraphOptions cut_options;
    for (const Cone& c : through) cut_options.cones.push_back(c.vertex);
    stage.cut = cut_graph(topology, stage.lengths_3d, cut_options);
    stage.cut_mesh = slice(topology, stage.cut);
    stage.roots.faces = layout_support::root_faces(stage.cut_mesh.topology,
                                                   LayoutOptions{}.root_face, stage.roots.first);
    stage.seconds = std::chrono::duration<double>(Clock::now() - t).count();
    return stage;
  };
  const bool may_subdivide = options.modify_connectivity && !flips && !cones.empty();
  std::future<CutStage> cut_ahead;
  if (!may_subdivide) cut_ahead = parallel::run_beside([&, cones] { return cut_stage(t0, cones); });

  // 3. Ricci flow to the flat metric with these cones.
  MeshFlowOptions flow_options;
  flow_options.structure = options.structure;
  flow_options.flow = options.flow;
  flow_options.target.kind = TargetKind::Flat;
  flow_options.target.cones = cones;
  flow_options.target.boundary = options.boundary;
  // The flows' results refer to t0 as their input triangulation: t0 is handed over to them at
  // the end, once the stages below are done with it (no copy of the topology).
  bool flow_kept_t0 = false;
  auto run_flow = [&](const MeshFlowOptions& o, bool& kept) {
    return mesh_flow_internal::flow_mesh_keeping_topology(result.mesh, t0, o, kept);
  };
  auto give_t0_to_flow = [&] {
    if (flow_kept_t0) {
      mesh_flow_internal::adopt_input_topology(result.flow,
                                               std::make_shared<const Topology>(std::move(t0)));
    }
  };
  try {
    result.flow = run_flow(flow_options, flow_kept_t0);
  } catch (const InvalidInput& e) {
    // The user's own cones refused (Gauss-Bonnet, a bound): automatic ones are the fix here,
    // not the flow's target options.
    if (options.cone_mode != ConeMode::User || e.fixes().empty()) throw;
    throw InvalidInput(e.what(), fixes_of({{"cones", "auto"}}));
  }
  result.converged = result.flow.converged;
  const FlowStatus status = result.flow.components.front().flow.status;
  if (!result.converged && options.modify_connectivity && !flips && !cones.empty() &&
      (status == FlowStatus::SolverFailed || status == FlowStatus::LineSearchFailed)) {
    // A degenerating metric means Thurston's conditions fail on vertex sets around a strong cone,
    // not on the cone alone: its neighbours lack faces. One midpoint subdivision gives every
    // neighbourhood four times the faces (input vertices keep their indices; each new vertex is
    // an edge midpoint).
    const int before = result.mesh.num_vertices();
    result.mesh = subdivide_midpoint(result.mesh);
    for (int e = 0; e < t0.num_edges; ++e) {
      result.added_vertex_parents.push_back({t0.edge_vertices(e, 0), t0.edge_vertices(e, 1)});
      result.vertex_origin.push_back(-1);
    }
    result.edge_splits += result.mesh.num_vertices() - before;
    result.subdivided = true;
    t0 = build_topology(result.mesh.triangles, result.mesh.num_vertices());
    result.flow = run_flow(flow_options, flow_kept_t0);
    result.converged = result.flow.converged;
  }
  // 3b. The selection's model is the flow linearised at the input metric, which holds while u
  // stays small. Strong cones leave it: on a CAD cylinder three cones of 1.5 pi each met the
  // linear bound, but the flat metric scaled areas by e^4 (area distortion energy 4.5, angle
  // distortion 3.2; eight cones give 0.031 and 1.43). Where the flow's own u spreads well past
  // the bound, more cones are chosen and the flow run again, keeping the better of the two.
  if (mode == ConeMode::Auto && options.auto_cones.count == 0 && flips && result.converged) {
    std::vector<int> vertices;
    for (const Cone& c : cones) vertices.push_back(c.vertex);
    result.log_scale_spread = log_scale_spread(result.mesh, t0, result.flow.u, vertices);
    for (int round = 0; round < kConeRounds; ++round) {
      if (result.log_scale_spread <= kNonlinearSlack * options.auto_cones.max_log_scale) break;
      const int n = static_cast<int>(cones.size());
      ConeSelection previous = result.cone_selection;
      std::vector<Cone> more = select_auto(std::max(n + 2, (3 * n + 1) / 2));
      // Fewer: the cap on the number of cones, or no more candidates; out of bounds: no such
      // cone set is drawable. Either way the first one stays.
      if (static_cast<int>(more.size()) <= n || !result.cone_selection.within_bounds) {
        result.cone_selection = std::move(previous);
        break;
      }
      quantize(more);
      flow_options.target.cones = more;
      MeshFlowResult flow;
      bool kept = false;
      try {
        flow = run_flow(flow_options, kept);
      } catch (const InvalidInput&) {  // a target the flow refuses: keep the first cones
        result.cone_selection = std::move(previous);
        flow_options.target.cones = cones;
        break;
      }
      vertices.clear();
      for (const Cone& c : more) vertices.push_back(c.vertex);
      const double spread =
          flow.converged ? log_scale_spread(result.mesh, t0, flow.u, vertices) : kInf;
      ++result.cone_rounds;
      if (!(spread < result.log_scale_spread)) {
        result.cone_selection = std::move(previous);
        flow_options.target.cones = cones;
        break;
      }
      cones = std::move(more);
      // The cut made beside the first flow runs through the old cones: cut again.
      if (cut_ahead.valid()) cut_ahead.wait();
      cut_ahead = {};
      result.cones = cones;
      result.flow = std::move(flow);
      flow_kept_t0 = kept;
      result.log_scale_spread = spread;
    }
  }
  lap(result.timings.flow);
  if (!result.converged) {
    // The cut stage beside the flow reads result.mesh: wait for it (and drop it) first.
    if (cut_ahead.valid()) cut_ahead.wait();
    give_t0_to_flow();
    result.message = result.flow.components.front().flow.message;
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  }

  // 4. Cut graph through the cones, slicing, layout, atlas, distortion, all on the mesh's own
  // faces. After Delaunay flips the flat metric lives on the intrinsic triangulation; each input
  // face is developed in it (its corners at their exact images), so the cut runs along input
  // edges and the layout, the seams and the written faces are the user's.
  const Topology& topology = t0;
  CutStage cut = cut_ahead.valid() ? cut_ahead.get() : cut_stage(topology, cones);
  const Eigen::VectorXd& lengths_3d = cut.lengths_3d;
  result.cut = std::move(cut.cut);
  result.cut_mesh = std::move(cut.cut_mesh);
  // The stage's own time (run beside the flow it took no time of the pipeline's own).
  result.timings.cut += cut.seconds;
  last = Clock::now();
  const Development development = develop_input_faces(topology, result.flow);
  result.development_length_mismatch = development.max_length_mismatch;
  lap(result.timings.development);
  result.layout = layout_support::layout_flat_with_roots(
      topology, development.shapes, result.cut, result.cut_mesh, LayoutOptions{}, cut.roots);
  lap(result.timings.layout);
  if (options.polish.enabled) {
    result.polish =
        polish_angles(result.mesh, result.cut_mesh.triangles, result.layout.uv, options.polish);
    // The layout takes the polished positions; polish.uv keeps the flat metric's own.
    std::swap(result.layout.uv, result.polish.uv);
    lap(result.timings.polish);
  }
  result.atlas = affine_atlas(topology, result.cut, result.cut_mesh, result.layout);
  lap(result.timings.atlas);
  result.distortion = measure_distortion(result.mesh, result.cut_mesh.triangles, result.layout.uv);
  lap(result.timings.distortion);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (result.cut.is_cut_edge[e]) result.seam_length += lengths_3d[e];
  }
  give_t0_to_flow();  // (topology is t0: not read after this)

  // Texture coordinates in the unit square, aspect ratio kept.
  const Eigen::Vector2d lo = result.layout.uv.colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = result.layout.uv.colwise().maxCoeff().transpose();
  const double extent = (hi - lo).maxCoeff();
  result.uv_offset = lo;
  result.uv_scale = extent > 0 ? 1.0 / extent : 1.0;
  result.uv = (result.layout.uv.rowwise() - lo.transpose()) * result.uv_scale;
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace ricci
