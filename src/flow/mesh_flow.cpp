#include "ricci/flow/mesh_flow.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <utility>

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
    case TargetKind::Flat:
      return flat_target(topology, spec.cones, spec.boundary, input_lengths, vertex_labels);
    case TargetKind::Uniform:
      return uniform_target(topology);
    case TargetKind::Values:
      return values_target(topology, spec.values);
  }
  throw InvalidInput("build_target: unknown target kind");
}

MeshFlowResult flow_mesh(const Mesh& mesh, const MeshFlowOptions& options) {
  const auto start = Clock::now();
  MeshFlowResult result;
  result.topology = build_topology(mesh.triangles, mesh.num_vertices());
  const Topology& whole = result.topology;
  const Eigen::VectorXd lbar = input_edge_lengths(mesh, whole);
  result.structure = make_conformal_structure(whole, lbar, options.structure);
  const ConformalStructure& structure = result.structure.structure;
  result.target = build_target(whole, lbar, options.target, options.vertex_labels);
  // Checked on the whole mesh so that messages name whole-mesh vertices.
  AdmissibilityOptions admissibility;
  admissibility.vertex_labels = options.vertex_labels;
  admissibility.edge_flips = uses_edge_flips(structure, options.flow);
  check_admissible(whole, structure, result.target, admissibility);
  result.setup_seconds = std::chrono::duration<double>(Clock::now() - start).count();

  result.u = structure.initial_u;
  result.curvature = Eigen::VectorXd::Zero(whole.num_vertices);
  result.target_curvature = result.target.curvature;
  result.lengths = lbar;
  result.eta = structure.eta;
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
      result.u = out.flow.u;
      result.curvature = out.flow.curvature;
      result.target_curvature = out.flow.target_curvature;
      result.lengths = out.flow.lengths;
      result.eta = out.flow.eta;
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
    if (whole.components.size() == 1 && out.flow.flips > 0) {
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
  if (flipped) result.topology = std::move(*flipped);
  result.total_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace ricci
