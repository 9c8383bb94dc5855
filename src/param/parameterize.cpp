#include "ricci/param/parameterize.hpp"

#include "parameterize_component.hpp"
#include "ricci/metric/intrinsic_triangulation.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "ricci/errors.hpp"
#include "ricci/mesh/split.hpp"

namespace ricci {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;

bool is_packing(Scheme s) {
  return s == Scheme::Thurston || s == Scheme::Tangential;
}

/// Valence a cone of curvature k needs for the single-vertex bound with room to spare: packings
/// with Phi up to pi/2 give each face at least pi/2, so valence > (2 pi - k) / (pi/2); the other
/// schemes give each face up to pi, so valence > (2 pi - k) / pi.
int required_valence(double k, Scheme scheme) {
  const double per_face = is_packing(scheme) ? kPi / 2 : kPi;
  return static_cast<int>(std::floor((2 * kPi - k) / per_face)) + 1;
}

/// Cone curvatures the surface takes when u is held at the cone vertices (and on the boundary)
/// and every other vertex is flattened.
std::vector<Cone> settle_cones(const Mesh& mesh, const std::vector<int>& vertices,
                               const ParamOptions& options, ParamResult& result) {
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const StructureResult s =
      make_conformal_structure(t, input_edge_lengths(mesh, t), options.structure);
  Target target;
  target.curvature = Eigen::VectorXd::Zero(t.num_vertices);
  target.fixed.assign(t.num_vertices, 0);
  for (int v = 0; v < t.num_vertices; ++v) target.fixed[v] = t.is_boundary_vertex[v];
  for (int v : vertices) target.fixed[v] = 1;
  target.description = "flat, u held at the chosen cones";
  const FlowResult flow = ricci_flow(t, s.structure, target, options.flow);
  if (!flow.converged) {
    result.message = "settling the automatic cones: " + flow.message;
    return {};
  }
  std::vector<Cone> cones;
  for (int v : vertices) cones.push_back({v, flow.curvature[v]});
  return cones;
}

}  // namespace

ConeMode parse_cone_mode(const std::string& name) {
  if (name == "none") return ConeMode::None;
  if (name == "user") return ConeMode::User;
  if (name == "auto") return ConeMode::Auto;
  if (name == "one") return ConeMode::OneCone;
  throw InvalidInput("parse_cone_mode: unknown cone mode '" + name +
                     "'; expected none, user, auto or one");
}

const char* cone_mode_name(ConeMode mode) {
  switch (mode) {
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
  const auto start = Clock::now();
  ParamResult result;
  const Topology t0 = build_topology(input.triangles, input.num_vertices());
  if (t0.components.size() != 1) {
    throw InvalidInput("parameterize: the mesh has " + std::to_string(t0.components.size()) +
                       " connected components");
  }
  const Component& comp = t0.components[0];
  const bool closed = comp.num_boundary_loops == 0;
  const int chi = comp.euler_characteristic;

  // 1. Singularities, in input vertex indices.
  std::vector<Cone> cones;
  switch (options.cone_mode) {
    case ConeMode::None:
      if (closed && chi != 0) {
        throw InvalidInput("parameterize: a closed surface of genus " + std::to_string(comp.genus) +
                           " has no flat metric without cones (chi = " + std::to_string(chi) +
                           "); use automatic cones or one cone");
      }
      break;
    case ConeMode::User:
      cones = options.cones;
      break;
    case ConeMode::OneCone: {
      if (!closed || comp.genus < 2) {
        throw InvalidInput(
            "parameterize: one cone of 2 pi chi is for closed surfaces of genus >= "
            "2; this one has genus " +
            std::to_string(comp.genus) + " and " + std::to_string(comp.num_boundary_loops) +
            " boundary loops");
      }
      ConeSelectionOptions one = options.auto_cones;
      one.count = 1;
      one.try_first_cone_candidates = 16;
      one.structure = options.structure;
      result.cone_selection = select_cones(input, one);
      cones.push_back({result.cone_selection.vertices.front(), 2 * kPi * chi});
      break;
    }
    case ConeMode::Auto: {
      ConeSelectionOptions selection = options.auto_cones;
      selection.structure = options.structure;
      selection.boundary = options.boundary;
      result.cone_selection = select_cones(input, selection);
      cones = settle_cones(input, result.cone_selection.vertices, options, result);
      if (!result.message.empty()) {
        result.mesh = input;
        result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        return result;
      }
      break;
    }
  }
  if (options.quantize && !cones.empty()) {
    double total = 0;
    for (const Cone& c : cones) total += c.curvature;
    // Closed surfaces must keep 2 pi chi; with a boundary the nearest multiple of pi/2 will do.
    total = closed ? 2 * kPi * chi : std::round(total / (kPi / 2)) * (kPi / 2);
    cones = quantize_cones(cones, total);
  }

  // 2. Local connectivity modification: raise the valence of cones that need it.
  result.mesh = input;
  result.vertex_origin.resize(input.num_vertices());
  for (int v = 0; v < input.num_vertices(); ++v) result.vertex_origin[v] = v;
  if (options.modify_connectivity) {
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

  // 3. Ricci flow to the flat metric with these cones.
  MeshFlowOptions flow_options;
  flow_options.structure = options.structure;
  flow_options.flow = options.flow;
  flow_options.target.kind = TargetKind::Flat;
  flow_options.target.cones = cones;
  flow_options.target.boundary = options.boundary;
  result.flow = flow_mesh(result.mesh, flow_options);
  result.converged = result.flow.converged;
  const FlowStatus status = result.flow.components.front().flow.status;
  if (!result.converged && options.modify_connectivity && !cones.empty() &&
      (status == FlowStatus::SolverFailed || status == FlowStatus::LineSearchFailed)) {
    // A degenerating metric means Thurston's conditions fail on vertex sets around a strong cone,
    // not on the cone alone: its neighbours lack faces. One midpoint subdivision gives every
    // neighbourhood four times the faces (input vertices keep their indices; each new vertex is
    // an edge midpoint).
    const Topology t = build_topology(result.mesh.triangles, result.mesh.num_vertices());
    const int before = result.mesh.num_vertices();
    result.mesh = subdivide_midpoint(result.mesh);
    for (int e = 0; e < t.num_edges; ++e) {
      result.added_vertex_parents.push_back({t.edge_vertices(e, 0), t.edge_vertices(e, 1)});
      result.vertex_origin.push_back(-1);
    }
    result.edge_splits += result.mesh.num_vertices() - before;
    result.subdivided = true;
    result.flow = flow_mesh(result.mesh, flow_options);
    result.converged = result.flow.converged;
  }
  if (!result.converged) {
    result.message = result.flow.components.front().flow.message;
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  }

  // 4. Cut graph through the cones, slicing, layout, atlas, distortion, all on the mesh's own
  // faces. After Delaunay flips the flat metric lives on the intrinsic triangulation; each input
  // face is developed in it (its corners at their exact images), so the cut runs along input
  // edges and the layout, the seams and the written faces are the user's.
  const Topology input_topology = build_topology(result.mesh.triangles, result.mesh.num_vertices());
  const Topology& topology = input_topology;
  const Eigen::VectorXd lengths_3d = input_edge_lengths(result.mesh, topology);
  CutGraphOptions cut_options;
  for (const Cone& c : cones) cut_options.cones.push_back(c.vertex);
  result.cut = cut_graph(topology, lengths_3d, cut_options);
  result.cut_mesh = slice(topology, result.cut);
  if (result.flow.flips > 0) {
    Development development =
        develop_input_faces(topology, result.flow.flipped_edges, result.flow.lengths);
    result.development_length_mismatch = development.max_length_mismatch;
    result.layout = layout_flat(topology, development.shapes, result.cut, result.cut_mesh);
  } else {
    result.layout = layout_flat(topology, result.flow.lengths, result.cut, result.cut_mesh);
  }
  result.atlas = affine_atlas(topology, result.cut, result.cut_mesh, result.layout);
  result.distortion = measure_distortion(result.mesh, result.cut_mesh.triangles, result.layout.uv);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (result.cut.is_cut_edge[e]) result.seam_length += lengths_3d[e];
  }

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
