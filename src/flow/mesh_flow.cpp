#include "ricci/flow/mesh_flow.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <memory>
#include <optional>
#include <utility>

#include "flow/detail/mesh_flow_internal.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/doubled_topology.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {
namespace {

/// A component as a topology of its own, with the maps back to the whole mesh.
struct ComponentView {
  Topology topology;
  std::vector<int> vertex_map;  // local -> whole
  std::vector<int> edge_map;    // local -> whole
};

ComponentView restrict_to(const Topology& whole, const Component& comp) {
  ComponentView view;
  view.vertex_map = comp.vertices;
  std::vector<int> local(whole.num_vertices, -1);
  for (std::size_t i = 0; i < comp.vertices.size(); ++i) {
    local[comp.vertices[i]] = static_cast<int>(i);
  }
  Triangles triangles(static_cast<Eigen::Index>(comp.faces.size()), 3);
  for (std::size_t f = 0; f < comp.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      triangles(static_cast<Eigen::Index>(f), k) = local[whole.triangles(comp.faces[f], k)];
    }
  }
  // Faces keep their corner order, so halfedge 3 f + k of the component is halfedge
  // 3 faces[f] + k of the whole mesh.
  auto whole_halfedge = [&](int h) { return 3 * comp.faces[h / 3] + h % 3; };
  // The same first halfedge as the whole mesh's edge: flip_edge orients its new faces by it,
  // so flips replayed on the whole mesh (MeshFlowResult::intrinsic) give the same faces.
  std::vector<char> first_halfedge(3 * comp.faces.size());
  for (std::size_t h = 0; h < first_halfedge.size(); ++h) {
    const int wh = whole_halfedge(static_cast<int>(h));
    first_halfedge[h] = whole.edge_halfedges(whole.halfedge_edge[wh], 0) == wh;
  }
  view.topology = build_topology(triangles, static_cast<int>(comp.vertices.size()), first_halfedge);
  view.edge_map.resize(view.topology.num_edges);
  for (int e = 0; e < view.topology.num_edges; ++e) {
    view.edge_map[e] = whole.halfedge_edge[whole_halfedge(view.topology.edge_halfedges(e, 0))];
  }
  return view;
}

}  // namespace

Target build_target(const Topology& topology, const Eigen::VectorXd& input_lengths,
                    const TargetSpec& spec, const std::vector<int>& vertex_labels) {
  switch (spec.kind) {
    case TargetKind::Natural: {
      if (!spec.cones.empty()) {
        return flat_target(topology, spec.cones, spec.boundary, input_lengths, vertex_labels);
      }
      Target target = flat_target(topology, {}, spec.boundary, input_lengths, vertex_labels);
      const Target uniform = uniform_target(topology);
      bool any_flat = false, any_uniform = false;
      for (const Component& comp : topology.components) {
        if (comp.num_boundary_loops > 0 || comp.euler_characteristic == 0) {
          any_flat = true;
          continue;
        }
        any_uniform = true;
        for (int v : comp.vertices) {
          target.curvature[v] = uniform.curvature[v];
          target.fixed[v] = 0;
        }
      }
      if (any_uniform) {
        target.description =
            any_flat ? target.description +
                           "; uniform curvature 2 pi chi / n on closed components "
                           "of genus other than 1"
                     : uniform.description +
                           " (closed, genus other than 1: no flat metric without cones)";
      }
      return target;
    }
    case TargetKind::Flat:
      return flat_target(topology, spec.cones, spec.boundary, input_lengths, vertex_labels);
    case TargetKind::Uniform:
      return uniform_target(topology);
    case TargetKind::Values:
      return values_target(topology, spec.values);
  }
  throw InvalidInput("build_target: unknown target kind");
}

namespace {

/// A component with boundary and its mirror image glued along the boundary: a closed surface on
/// which interior flips reach every edge (a boundary edge becomes an interior one), see
/// ricci/mesh/doubled_topology.hpp. The doubled target asks the same curvature of both copies
/// of an interior vertex and twice the boundary curvature of a boundary vertex (both halves'
/// angles meet there).
struct Doubled {
  std::shared_ptr<const Topology> topology;
  Triangles triangles;
  std::vector<int> original;  // doubled vertex -> local vertex
  ConformalStructure structure;
  Target target;
};

Doubled double_component(const Topology& t, const ConformalStructure& s, const Target& target) {
  DoubledTopology connectivity = build_doubled_topology(t);
  Doubled d;
  d.triangles = std::move(connectivity.triangles);
  d.original = std::move(connectivity.original);
  d.topology = std::make_shared<const Topology>(std::move(connectivity.topology));
  const int nf = t.num_faces;
  const int n2 = static_cast<int>(d.original.size());
  d.structure.scheme = s.scheme;
  d.structure.geometry = s.geometry;
  d.structure.length_scale = s.length_scale;
  d.structure.epsilon.resize(n2);
  d.structure.initial_u.resize(n2);
  d.target.curvature.resize(n2);
  d.target.fixed.resize(n2);
  d.target.description = target.description + " (doubled along the boundary)";
  for (int v = 0; v < n2; ++v) {
    const int o = d.original[v];
    d.structure.epsilon[v] = s.epsilon[o];
    d.structure.initial_u[v] = s.initial_u[o];
    d.target.curvature[v] = t.is_boundary_vertex[o] ? 2 * target.curvature[o] : target.curvature[o];
    d.target.fixed[v] = target.fixed[o];
  }
  const Topology& dt = *d.topology;
  d.structure.eta.resize(dt.num_edges);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const double eta = s.eta[t.halfedge_edge[3 * f + k]];
      d.structure.eta[dt.halfedge_edge[3 * f + k]] = eta;
      // Mirrored halfedge k lies opposite the copy of corner kMirroredCorner[k].
      d.structure.eta[dt.halfedge_edge[3 * (nf + f) + k]] =
          s.eta[t.halfedge_edge[3 * f + kMirroredCorner[k]]];
    }
  }
  return d;
}

/// Whether a failed flow on a component with boundary should be tried again on its double:
/// boundary edges cannot flip, so a triangle along the boundary can break where the doubled
/// surface simply flips the edge (CAD fans, the disk of the sphere map).
bool worth_doubling(const Topology& t, const ConformalStructure& s, const FlowOptions& options,
                    const FlowResult& flow) {
  if (flow.converged || t.num_boundary_loops() == 0) return false;
  if (flow.status == FlowStatus::Cancelled) return false;
  if (s.geometry != Geometry::Euclidean || !uses_edge_flips(s, options)) return false;
  return true;
}

/// Runs the flow on the double of a component; on success `out` holds it (its flow in the
/// doubled surface's indices) and the developed shapes of the component's own faces.
void flow_doubled(const Topology& t, const ConformalStructure& s, const Target& target,
                  const FlowOptions& options, ComponentFlow& out) {
  Doubled d = double_component(t, s, target);
  FlowOptions doubled_options = options;
  doubled_options.start_u.resize(0);  // (a start for the component, not for its double)
  doubled_options.start_preconditioner = nullptr;
  FlowResult flow = ricci_flow(*d.topology, d.structure, d.target, doubled_options);
  if (!flow.converged) return;
  flow.intrinsic.adopt_input(d.topology);  // the result owns the doubled connectivity
  const Development development = flow.intrinsic.develop_input_faces(flow.lengths);
  out.doubled = true;
  out.first_attempt_message = out.flow.message;
  out.flow = std::move(flow);
  out.doubled_triangles = std::move(d.triangles);
  out.doubled_vertex_original = std::move(d.original);
  out.doubled_shapes.assign(development.shapes.begin(), development.shapes.begin() + t.num_faces);
}

/// Writes a doubled component's u, curvature and the lengths of its own edges (in the final
/// metric, from the developed faces) into the whole-mesh arrays; the maps are local -> whole
/// (empty: the component is the whole mesh).
void gather_doubled(const ComponentFlow& out, const Topology& t, const std::vector<int>& vertex_map,
                    const std::vector<int>& edge_map, MeshFlowResult& result,
                    Eigen::VectorXd& eta) {
  auto whole_vertex = [&](int v) { return vertex_map.empty() ? v : vertex_map[v]; };
  auto whole_edge = [&](int e) { return edge_map.empty() ? e : edge_map[e]; };
  for (int v = 0; v < t.num_vertices; ++v) {
    const double half = t.is_boundary_vertex[v] ? 0.5 : 1.0;
    result.u[whole_vertex(v)] = out.flow.u[v];
    result.curvature[whole_vertex(v)] = half * out.flow.curvature[v];
    result.target_curvature[whole_vertex(v)] = half * out.flow.target_curvature[v];
  }
  for (int f = 0; f < t.num_faces; ++f) {
    const auto& p = out.doubled_shapes[f];
    for (int k = 0; k < 3; ++k) {
      const int e = t.face_edges(f, k);
      const double l = std::abs(p[(k + 2) % 3] - p[(k + 1) % 3]);
      result.lengths[whole_edge(e)] = l;
      const double ui = out.flow.u[t.edge_vertices(e, 0)], uj = out.flow.u[t.edge_vertices(e, 1)];
      eta[whole_edge(e)] = 0.5 * l * l * std::exp(-(ui + uj));
    }
  }
}

/// The component's conformal structure and target (copies of the whole mesh's values).
struct LocalProblem {
  ConformalStructure structure;
  Target target;
};

LocalProblem restrict_problem(const ComponentView& view, const ConformalStructure& structure,
                              const Target& whole_target) {
  const int nv = view.topology.num_vertices, ne = view.topology.num_edges;
  LocalProblem p;
  ConformalStructure& local = p.structure;
  local.scheme = structure.scheme;
  local.geometry = structure.geometry;
  local.length_scale = structure.length_scale;
  local.epsilon.resize(nv);
  local.initial_u.resize(nv);
  local.eta.resize(ne);
  Target& target = p.target;
  target.curvature.resize(nv);
  target.fixed.resize(nv);
  target.description = whole_target.description;
  for (int i = 0; i < nv; ++i) {
    const int v = view.vertex_map[i];
    local.epsilon[i] = structure.epsilon[v];
    local.initial_u[i] = structure.initial_u[v];
    target.curvature[i] = whole_target.curvature[v];
    target.fixed[i] = whole_target.fixed[v];
  }
  for (int e = 0; e < ne; ++e) local.eta[e] = structure.eta[view.edge_map[e]];
  return p;
}

/// The whole mesh's status, fixes and message from its components' flows: converged when every
/// component converged, else the first failed component's status; the message says why each
/// component stopped, prefixed by its index when there are several.
void summarise_components(MeshFlowResult& result) {
  result.status = FlowStatus::Converged;
  for (std::size_t c = 0; c < result.components.size(); ++c) {
    const FlowResult& flow = result.components[c].flow;
    if (!flow.converged && result.status == FlowStatus::Converged) result.status = flow.status;
    for (const OptionFix& fix : flow.fixes) {
      if (std::find(result.fixes.begin(), result.fixes.end(), fix) == result.fixes.end()) {
        result.fixes.push_back(fix);
      }
    }
    if (result.components.size() == 1) {
      result.message = flow.message;
    } else {
      result.message +=
          (c ? "; " : "") + std::string("component ") + std::to_string(c) + ": " + flow.message;
    }
  }
}

/// A developed face whose doubled area is at most this times its longest squared side counts
/// as degenerate rather than flipped: the rounding of the developed corners (a few eps of the
/// squared sides) stays below it, so its sign says nothing.
constexpr double degenerate_area_ratio = 1e-14;

}  // namespace

Development develop_input_faces(const Mesh& mesh, const MeshFlowResult& flow) {
  return develop_input_faces(build_topology(mesh.triangles, mesh.num_vertices()), flow);
}

Development develop_input_faces(const Topology& input, const MeshFlowResult& flow) {
  // Doubled components' faces are developed already (their lengths are those of developed
  // corners, which may be collinear): give them their input lengths here, always a valid
  // triangle, and their developed shapes below.
  const bool with_doubled = std::any_of(flow.components.begin(), flow.components.end(),
                                        [](const ComponentFlow& c) { return c.doubled; });
  Eigen::VectorXd doubled_lengths;
  if (with_doubled) {
    doubled_lengths = flow.lengths;
    for (std::size_t c = 0; c < flow.components.size(); ++c) {
      if (!flow.components[c].doubled) continue;
      for (int f : input.components[c].faces) {
        for (int k = 0; k < 3; ++k)
          doubled_lengths[input.face_edges(f, k)] = flow.input_lengths[input.face_edges(f, k)];
      }
    }
  }
  Development d = develop_input_faces(input, flow.intrinsic.flipped_edges(),
                                      with_doubled ? doubled_lengths : flow.lengths);
  bool any_doubled = false;
  for (std::size_t c = 0; c < flow.components.size(); ++c) {
    const ComponentFlow& comp = flow.components[c];
    if (!comp.doubled) continue;
    any_doubled = true;
    const std::vector<int>& faces = input.components[c].faces;
    for (std::size_t f = 0; f < faces.size(); ++f) d.shapes[faces[f]] = comp.doubled_shapes[f];
  }
  if (any_doubled) {
    d = Development{d.shapes, d.lengths, 0, 0, 0};
    for (int e = 0; e < input.num_edges; ++e) {
      auto side = [&](int h) {
        const auto& p = d.shapes[h / 3];
        return std::abs(p[(h % 3 + 2) % 3] - p[(h % 3 + 1) % 3]);
      };
      const double la = side(input.edge_halfedges(e, 0));
      d.lengths[e] = la;
      if (input.edge_halfedges(e, 1) >= 0) {
        const double lb = side(input.edge_halfedges(e, 1));
        d.max_length_mismatch =
            std::max(d.max_length_mismatch, std::abs(la - lb) / std::max(la, lb));
      }
    }
    for (const auto& p : d.shapes) {
      const std::complex<double> a = p[1] - p[0], b = p[2] - p[0];
      const double area = a.real() * b.imag() - a.imag() * b.real();
      const double scale = std::max({std::norm(a), std::norm(b), std::norm(p[2] - p[1])});
      if (std::abs(area) <= degenerate_area_ratio * scale) {
        ++d.degenerate_faces;
      } else if (area < 0) {
        ++d.flipped_faces;
      }
    }
  }
  return d;
}

MeshFlowResult flow_mesh(const Mesh& mesh, const MeshFlowOptions& options) {
  return flow_mesh(mesh, build_topology(mesh.triangles, mesh.num_vertices()), options);
}

MeshFlowResult flow_mesh(const Mesh& mesh, const Topology& topology,
                         const MeshFlowOptions& options) {
  const auto start = Clock::now();
  const Eigen::VectorXd lbar = input_edge_lengths(mesh, topology);
  bool kept_input_topology = false;
  MeshFlowResult result = mesh_flow_internal::flow_mesh_keeping_topology(
      topology, lbar, make_conformal_structure(topology, lbar, options.structure), options,
      kept_input_topology, start);
  mesh_flow_internal::adopt_input_topology(result, std::make_shared<const Topology>(topology));
  return result;
}

MeshFlowResult flow_mesh(const FlowProblem& problem, const MeshFlowOptions& options) {
  bool kept_input_topology = false;
  MeshFlowResult result =
      mesh_flow_internal::flow_mesh_keeping_topology(problem, options, kept_input_topology);
  mesh_flow_internal::adopt_input_topology(result,
                                           std::make_shared<const Topology>(problem.topology));
  return result;
}

void mesh_flow_internal::adopt_input_topology(MeshFlowResult& result,
                                              std::shared_ptr<const Topology> topology) {
  // The one-component flow that was not doubled refers to the same input.
  for (ComponentFlow& c : result.components) {
    if (!c.flow.intrinsic.empty() &&
        c.flow.intrinsic.shared_input().get() == result.intrinsic.shared_input().get()) {
      c.flow.intrinsic.adopt_input(topology);
    }
  }
  result.intrinsic.adopt_input(std::move(topology));
}

MeshFlowResult mesh_flow_internal::flow_mesh_keeping_topology(const FlowProblem& problem,
                                                              const MeshFlowOptions& options,
                                                              bool& kept_input_topology) {
  return flow_mesh_keeping_topology(problem.topology, problem.input_lengths, problem.structure,
                                    options, kept_input_topology, Clock::now());
}

MeshFlowResult mesh_flow_internal::flow_mesh_keeping_topology(
    const Topology& topology, const Eigen::VectorXd& lbar, StructureResult structure_result,
    const MeshFlowOptions& options, bool& kept_input_topology,
    std::chrono::steady_clock::time_point start) {
  MeshFlowResult result;
  const Topology& whole = topology;
  result.structure = std::move(structure_result);
  const ConformalStructure& structure = result.structure.structure;
  TargetSpec spec = options.target;
  // Zero curvature is the hyperbolic background's natural target (the uniformization metric).
  if (spec.kind == TargetKind::Natural && structure.geometry == Geometry::Hyperbolic) {
    spec.kind = TargetKind::Flat;
  }
  result.target = build_target(whole, lbar, spec, options.vertex_labels);
  // Checked on the whole mesh so that messages name whole-mesh vertices.
  AdmissibilityOptions admissibility;
  admissibility.vertex_labels = options.vertex_labels;
  admissibility.edge_flips = uses_edge_flips(structure, options.flow);
  check_admissible(whole, structure, result.target, admissibility);
  result.setup_seconds = seconds_since(start);

  // Starting values, which the components' flows overwrite (a mesh of one component: every
  // one of them, so no copy is made). `eta` becomes the whole triangulation's at the end.
  Eigen::VectorXd eta;
  auto start_values = [&] {
    result.u = structure.initial_u;
    result.curvature = Eigen::VectorXd::Zero(whole.num_vertices);
    result.target_curvature = result.target.curvature;
    result.lengths = lbar;
    eta = structure.eta;
  };
  if (whole.components.size() != 1) start_values();
  result.input_lengths = lbar;
  result.converged = true;

  // The whole mesh's intrinsic triangulation, gathered from the components' own (a mesh of one
  // component whose flow was not doubled: that flow's, shared).
  IntrinsicTriangulation gathered(whole, structure);
  bool whole_is_flow = false;
  for (const Component& comp : whole.components) {
    ComponentFlow out;
    out.vertices = comp.vertices;
    out.euler_characteristic = comp.euler_characteristic;
    out.genus = comp.genus;
    out.boundary_loops = comp.num_boundary_loops;
    if (whole.components.size() == 1) {
      out.flow = ricci_flow(whole, structure, result.target, options.flow);
      if (worth_doubling(whole, structure, options.flow, out.flow)) {
        flow_doubled(whole, structure, result.target, options.flow, out);
      }
      if (out.doubled) {
        start_values();
        gather_doubled(out, whole, std::vector<int>(), std::vector<int>(), result, eta);
        gathered.add_flip_counts(out.flow.intrinsic);
      } else {
        result.u = out.flow.u;
        result.curvature = out.flow.curvature;
        result.target_curvature = out.flow.target_curvature;
        result.lengths = out.flow.lengths;
        result.intrinsic = out.flow.intrinsic;
        whole_is_flow = true;
      }
    } else {
      // The component's connectivity stays with its flow's result (its input).
      ComponentView view = restrict_to(whole, comp);
      const auto component_topology = std::make_shared<const Topology>(std::move(view.topology));
      const Topology& t = *component_topology;
      const int nv = t.num_vertices, ne = t.num_edges;
      const auto [local, target] = restrict_problem(view, structure, result.target);
      FlowOptions component_options = options.flow;
      component_options.start_preconditioner = nullptr;  // (the whole mesh's vertices)
      if (options.flow.start_u.size() == whole.num_vertices) {
        component_options.start_u.resize(nv);
        for (int i = 0; i < nv; ++i)
          component_options.start_u[i] = options.flow.start_u[view.vertex_map[i]];
      }
      out.flow = ricci_flow(t, local, target, component_options);
      out.flow.intrinsic.adopt_input(component_topology);
      if (worth_doubling(t, local, options.flow, out.flow)) {
        flow_doubled(t, local, target, component_options, out);
      }
      if (out.doubled) {
        gather_doubled(out, t, view.vertex_map, view.edge_map, result, eta);
        gathered.add_flip_counts(out.flow.intrinsic);
      } else {
        for (int i = 0; i < nv; ++i) {
          const int v = view.vertex_map[i];
          result.u[v] = out.flow.u[i];
          result.curvature[v] = out.flow.curvature[i];
          result.target_curvature[v] = out.flow.target_curvature[i];
        }
        const Eigen::VectorXd& component_eta = out.flow.intrinsic.eta();
        for (int e = 0; e < ne; ++e) {
          result.lengths[view.edge_map[e]] = out.flow.lengths[e];
          eta[view.edge_map[e]] = component_eta[e];
        }
        gathered.gather_component(out.flow.intrinsic, comp.faces, view.vertex_map, view.edge_map);
      }
    }
    result.converged = result.converged && out.flow.converged;
    result.max_error = std::max(result.max_error, out.flow.max_error);
    result.components.push_back(std::move(out));
  }
  summarise_components(result);
  if (!whole_is_flow) {
    gathered.set_eta(std::move(eta));
    result.intrinsic = std::move(gathered);
  }
  // The result refers to the caller's topology as its input (a copy here would cost tens of
  // milliseconds on a million faces): the caller hands it over (adopt_input_topology).
  kept_input_topology = true;
  result.total_seconds = seconds_since(start);
  return result;
}

}  // namespace ricci
