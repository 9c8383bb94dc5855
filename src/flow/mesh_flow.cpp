#include "ricci/flow/mesh_flow.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <optional>
#include <utility>

#include "mesh_flow_internal.hpp"
#include "ricci/errors.hpp"

namespace ricci {
namespace {

using Clock = std::chrono::steady_clock;

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
  view.topology = build_topology(triangles, static_cast<int>(comp.vertices.size()));
  // Faces keep their corner order, so halfedge 3 f + k of the component is halfedge
  // 3 faces[f] + k of the whole mesh.
  view.edge_map.resize(view.topology.num_edges);
  auto whole_halfedge = [&](int h) { return 3 * comp.faces[h / 3] + h % 3; };
  for (int e = 0; e < view.topology.num_edges; ++e) {
    const int h = view.topology.edge_halfedges(e, 0);
    const int ew = whole.halfedge_edge[whole_halfedge(h)];
    view.edge_map[e] = ew;
    // The same first halfedge as the whole mesh's edge: flip_edge orients its new faces by it,
    // so flips replayed on the whole mesh (MeshFlowResult::flipped_edges) give the same faces.
    if (whole.edge_halfedges(ew, 0) != whole_halfedge(h)) {
      std::swap(view.topology.edge_halfedges(e, 0), view.topology.edge_halfedges(e, 1));
    }
  }
  return view;
}

/// Writes a component's flipped connectivity into the whole mesh's arrays. Flips reuse face and
/// edge indices, so face f and edge e of the component stay face comp.faces[f] and edge
/// view.edge_map[e] of the whole mesh; only what they join changes.
void transplant(const Topology& local, const Component& comp, const ComponentView& view,
                Topology& whole) {
  auto halfedge = [&](int h) { return h < 0 ? -1 : 3 * comp.faces[h / 3] + h % 3; };
  for (int f = 0; f < local.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k, hw = halfedge(h), fw = comp.faces[f];
      whole.triangles(fw, k) = view.vertex_map[local.triangles(f, k)];
      whole.face_edges(fw, k) = view.edge_map[local.face_edges(f, k)];
      whole.halfedge_edge[hw] = view.edge_map[local.halfedge_edge[h]];
      whole.halfedge_twin[hw] = halfedge(local.halfedge_twin[h]);
    }
  }
  for (int e = 0; e < local.num_edges; ++e) {
    const int ew = view.edge_map[e];
    // vertex_map is ascending, so the smaller end stays first.
    whole.edge_vertices(ew, 0) = view.vertex_map[local.edge_vertices(e, 0)];
    whole.edge_vertices(ew, 1) = view.vertex_map[local.edge_vertices(e, 1)];
    whole.edge_halfedges(ew, 0) = halfedge(local.edge_halfedges(e, 0));
    whole.edge_halfedges(ew, 1) = halfedge(local.edge_halfedges(e, 1));
  }
  for (int i = 0; i < local.num_vertices; ++i) {
    whole.vertex_degree[view.vertex_map[i]] = local.vertex_degree[i];
  }
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
/// which interior flips reach every edge (a boundary edge becomes an interior one). Interior
/// vertices get a mirror copy, boundary vertices are shared; mirrored faces have the reverse
/// orientation. The doubled target asks the same curvature of both copies of an interior vertex
/// and twice the boundary curvature of a boundary vertex (both halves' angles meet there).
struct Doubled {
  Topology topology;
  Triangles triangles;
  std::vector<int> original;  // doubled vertex -> local vertex
  ConformalStructure structure;
  Target target;
};

// Mirrored corner k of face f copies corner kMirror[k]: (a, b, c) becomes (a', c', b').
constexpr int kMirror[3] = {0, 2, 1};

/// The connectivity of the double, built from the component's own: build_topology cannot, since
/// an interior edge joining two boundary vertices and its mirror image join the same two
/// (shared) vertices, a double edge. Original halfedge 3 f + k keeps its index; its mirror image
/// is halfedge 3 (F + f) + kMirror[k], running the other way. A boundary halfedge becomes the
/// twin of its own mirror image.
Topology doubled_topology(const Topology& t, const Triangles& triangles, int num_vertices) {
  const int nf = t.num_faces, ne = t.num_edges;
  auto mirrored = [nf](int h) { return 3 * (nf + h / 3) + kMirror[h % 3]; };
  Topology d;
  d.num_vertices = num_vertices;
  d.num_faces = 2 * nf;
  d.triangles = triangles;
  d.halfedge_twin.assign(6 * static_cast<std::size_t>(nf), -1);
  d.halfedge_edge.assign(6 * static_cast<std::size_t>(nf), -1);
  d.face_edges.resize(2 * nf, 3);
  int interior_edges = 0;
  for (int e = 0; e < ne; ++e) interior_edges += !t.is_boundary_edge[e];
  d.num_edges = ne + interior_edges;
  d.edge_vertices.resize(d.num_edges, 2);
  d.edge_halfedges.resize(d.num_edges, 2);
  std::vector<int> mirror_edge(ne, -1);
  int next = ne;
  for (int e = 0; e < ne; ++e) mirror_edge[e] = t.is_boundary_edge[e] ? e : next++;
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k, m = mirrored(h), e = t.halfedge_edge[h];
      const int twin = t.halfedge_twin[h];
      d.halfedge_twin[h] = twin >= 0 ? twin : m;
      d.halfedge_twin[m] = twin >= 0 ? mirrored(twin) : h;
      d.halfedge_edge[h] = e;
      d.halfedge_edge[m] = mirror_edge[e];
      d.face_edges(f, k) = e;
      d.face_edges(nf + f, kMirror[k]) = mirror_edge[e];
    }
  }
  auto tail = [&](int h) { return d.triangles(h / 3, (h % 3 + 1) % 3); };
  auto head = [&](int h) { return d.triangles(h / 3, (h % 3 + 2) % 3); };
  for (int e = 0; e < ne; ++e) {
    const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
    d.edge_halfedges(e, 0) = h0;
    d.edge_halfedges(e, 1) = h1 >= 0 ? h1 : mirrored(h0);
    if (mirror_edge[e] != e) {
      d.edge_halfedges(mirror_edge[e], 0) = mirrored(h0);
      d.edge_halfedges(mirror_edge[e], 1) = mirrored(h1);
    }
  }
  for (int e = 0; e < d.num_edges; ++e) {
    const int h = d.edge_halfedges(e, 0);
    d.edge_vertices(e, 0) = std::min(tail(h), head(h));
    d.edge_vertices(e, 1) = std::max(tail(h), head(h));
  }
  d.is_boundary_vertex.assign(num_vertices, 0);
  d.is_boundary_edge.assign(d.num_edges, 0);
  d.vertex_degree.assign(num_vertices, 0);
  for (int e = 0; e < d.num_edges; ++e) {
    ++d.vertex_degree[d.edge_vertices(e, 0)];
    ++d.vertex_degree[d.edge_vertices(e, 1)];
  }
  d.vertex_component.assign(num_vertices, 0);
  d.face_component.assign(d.num_faces, 0);
  Component c;
  c.vertices.resize(num_vertices);
  for (int v = 0; v < num_vertices; ++v) c.vertices[v] = v;
  c.faces.resize(d.num_faces);
  for (int f = 0; f < d.num_faces; ++f) c.faces[f] = f;
  c.num_edges = d.num_edges;
  c.num_boundary_loops = 0;
  c.euler_characteristic = num_vertices - d.num_edges + d.num_faces;
  c.genus = (2 - c.euler_characteristic) / 2;
  d.components.push_back(std::move(c));
  return d;
}

Doubled double_component(const Topology& t, const ConformalStructure& s, const Target& target) {
  Doubled d;
  const int nv = t.num_vertices, nf = t.num_faces;
  std::vector<int> mirror(nv, -1);
  d.original.resize(nv);
  for (int v = 0; v < nv; ++v) d.original[v] = v;
  for (int v = 0; v < nv; ++v) {
    if (t.is_boundary_vertex[v]) {
      mirror[v] = v;
    } else {
      mirror[v] = static_cast<int>(d.original.size());
      d.original.push_back(v);
    }
  }
  d.triangles.resize(2 * nf, 3);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      d.triangles(f, k) = t.triangles(f, k);
      d.triangles(nf + f, k) = mirror[t.triangles(f, kMirror[k])];
    }
  }
  const int n2 = static_cast<int>(d.original.size());
  d.topology = doubled_topology(t, d.triangles, n2);
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
  d.structure.eta.resize(d.topology.num_edges);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const double eta = s.eta[t.halfedge_edge[3 * f + k]];
      d.structure.eta[d.topology.halfedge_edge[3 * f + k]] = eta;
      // Mirrored halfedge k lies opposite the copy of corner kMirror[k].
      d.structure.eta[d.topology.halfedge_edge[3 * (nf + f) + k]] =
          s.eta[t.halfedge_edge[3 * f + kMirror[k]]];
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
  FlowResult flow = ricci_flow(d.topology, d.structure, d.target, options);
  if (!flow.converged) return;
  const Development development = develop_input_faces(d.topology, flow.flipped_edges, flow.lengths);
  out.doubled = true;
  out.first_attempt_message = out.flow.message;
  out.flow = std::move(flow);
  out.doubled_triangles = std::move(d.triangles);
  out.doubled_topology = std::make_shared<const Topology>(std::move(d.topology));
  out.doubled_vertex_original = std::move(d.original);
  out.doubled_shapes.assign(development.shapes.begin(), development.shapes.begin() + t.num_faces);
}

/// Writes a doubled component's u, curvature and the lengths of its own edges (in the final
/// metric, from the developed faces) into the whole-mesh arrays; the maps are local -> whole
/// (empty: the component is the whole mesh).
void gather_doubled(const ComponentFlow& out, const Topology& t, const std::vector<int>& vertex_map,
                    const std::vector<int>& edge_map, MeshFlowResult& result) {
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
      result.eta[whole_edge(e)] = 0.5 * l * l * std::exp(-(ui + uj));
    }
  }
}

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
  Development d =
      develop_input_faces(input, flow.flipped_edges, with_doubled ? doubled_lengths : flow.lengths);
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
      if (std::abs(area) <= 1e-14 * scale) {
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
  if (kept_input_topology) result.topology = topology;
  return result;
}

MeshFlowResult flow_mesh(const FlowProblem& problem, const MeshFlowOptions& options) {
  bool kept_input_topology = false;
  MeshFlowResult result =
      mesh_flow_internal::flow_mesh_keeping_topology(problem, options, kept_input_topology);
  if (kept_input_topology) result.topology = problem.topology;
  return result;
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
  // result.topology is set at the end when flips changed the triangulation.
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
  result.setup_seconds = std::chrono::duration<double>(Clock::now() - start).count();

  // Starting values, which the components' flows overwrite (a mesh of one component: every
  // one of them, so no copy is made).
  auto start_values = [&] {
    result.u = structure.initial_u;
    result.curvature = Eigen::VectorXd::Zero(whole.num_vertices);
    result.target_curvature = result.target.curvature;
    result.lengths = lbar;
    result.eta = structure.eta;
  };
  if (whole.components.size() != 1) start_values();
  result.input_lengths = lbar;
  result.converged = true;

  // After flips, the whole mesh's intrinsic triangulation (made from the components' own).
  std::optional<Topology> flipped;
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
        gather_doubled(out, whole, std::vector<int>(), std::vector<int>(), result);
      } else {
        result.u = out.flow.u;
        result.curvature = out.flow.curvature;
        result.target_curvature = out.flow.target_curvature;
        result.lengths = out.flow.lengths;
        result.eta = out.flow.eta;
      }
    } else {
      const ComponentView view = restrict_to(whole, comp);
      const int nv = view.topology.num_vertices, ne = view.topology.num_edges;
      ConformalStructure local;
      local.scheme = structure.scheme;
      local.geometry = structure.geometry;
      local.length_scale = structure.length_scale;
      local.epsilon.resize(nv);
      local.initial_u.resize(nv);
      local.eta.resize(ne);
      Target target;
      target.curvature.resize(nv);
      target.fixed.resize(nv);
      target.description = result.target.description;
      for (int i = 0; i < nv; ++i) {
        const int v = view.vertex_map[i];
        local.epsilon[i] = structure.epsilon[v];
        local.initial_u[i] = structure.initial_u[v];
        target.curvature[i] = result.target.curvature[v];
        target.fixed[i] = result.target.fixed[v];
      }
      for (int e = 0; e < ne; ++e) local.eta[e] = structure.eta[view.edge_map[e]];
      out.flow = ricci_flow(view.topology, local, target, options.flow);
      if (worth_doubling(view.topology, local, options.flow, out.flow)) {
        flow_doubled(view.topology, local, target, options.flow, out);
      }
      if (out.doubled) {
        gather_doubled(out, view.topology, view.vertex_map, view.edge_map, result);
      } else {
        for (int i = 0; i < nv; ++i) {
          const int v = view.vertex_map[i];
          result.u[v] = out.flow.u[i];
          result.curvature[v] = out.flow.curvature[i];
          result.target_curvature[v] = out.flow.target_curvature[i];
        }
        for (int e = 0; e < ne; ++e) {
          result.lengths[view.edge_map[e]] = out.flow.lengths[e];
          result.eta[view.edge_map[e]] = out.flow.eta[e];
        }
        if (out.flow.flips > 0) {
          if (!flipped) flipped = whole;
          transplant(*out.flow.intrinsic_topology, comp, view, *flipped);
          for (int e : out.flow.flipped_edges) result.flipped_edges.push_back(view.edge_map[e]);
          result.flip_is_isometric.insert(result.flip_is_isometric.end(),
                                          out.flow.flipped_edges.size(), 0);
          std::fill_n(result.flip_is_isometric.end() - out.flow.flipped_edges.size(),
                      out.flow.isometric_flips, 1);
        }
      }
    }
    if (whole.components.size() == 1 && out.flow.flips > 0 && !out.doubled) {
      flipped = *out.flow.intrinsic_topology;
      result.flipped_edges = out.flow.flipped_edges;
      result.flip_is_isometric.assign(out.flow.flipped_edges.size(), 0);
      std::fill_n(result.flip_is_isometric.begin(), out.flow.isometric_flips, 1);
    }
    result.flips += out.flow.flips;
    result.blocked_flips += out.flow.blocked_flips;
    result.converged = result.converged && out.flow.converged;
    result.max_error = std::max(result.max_error, out.flow.max_error);
    result.components.push_back(std::move(out));
  }
  // Converged when every component converged, else the first failed component's status; the
  // message says why each component stopped, prefixed by its index when there are several.
  result.status = FlowStatus::Converged;
  for (std::size_t c = 0; c < result.components.size(); ++c) {
    const FlowResult& flow = result.components[c].flow;
    if (!flow.converged && result.status == FlowStatus::Converged) result.status = flow.status;
    if (result.components.size() == 1) {
      result.message = flow.message;
    } else {
      result.message +=
          (c ? "; " : "") + std::string("component ") + std::to_string(c) + ": " + flow.message;
    }
  }
  // Without flips the caller holds the topology (a copy here would cost tens of milliseconds on
  // a million faces).
  kept_input_topology = !flipped;
  if (flipped) result.topology = std::move(*flipped);
  result.total_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace ricci
