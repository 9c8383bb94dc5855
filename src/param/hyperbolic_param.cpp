#include "ricci/param/hyperbolic_param.hpp"

#include <chrono>

#include "ricci/errors.hpp"

namespace ricci {

HyperbolicParamResult parameterize_hyperbolic(const Mesh& mesh,
                                              const HyperbolicParamOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  HyperbolicParamResult result;
  const Topology t0 = build_topology(mesh.triangles, mesh.num_vertices());
  if (t0.components.size() != 1) {
    throw InvalidInput("parameterize_hyperbolic: the mesh has " +
                       std::to_string(t0.components.size()) +
                       " connected components; parameterize them one by one");
  }
  const Component& comp = t0.components[0];
  if (comp.euler_characteristic >= 0) {
    throw InvalidInput(
        "parameterize_hyperbolic: a surface with chi = " +
        std::to_string(comp.euler_characteristic) + " (genus " + std::to_string(comp.genus) + ", " +
        std::to_string(comp.num_boundary_loops) +
        " boundary loops) has no hyperbolic metric; it needs chi < 0 (genus >= 2, or boundaries)");
  }

  // 1. The uniformization metric: K = 0 everywhere, geodesic boundary.
  MeshFlowOptions flow_options;
  flow_options.structure = options.structure;
  flow_options.structure.geometry = Geometry::Hyperbolic;
  flow_options.flow = options.flow;
  flow_options.target.kind = TargetKind::Flat;
  flow_options.target.boundary = BoundaryMode::Geodesic;
  result.flow = flow_mesh(mesh, flow_options);
  result.converged = result.flow.converged;
  if (!result.converged) {
    result.message = result.flow.components.front().flow.message;
    result.seconds = seconds();
    return result;
  }

  // 2. Cut graph (no cones: 2 g loops, joined to the boundaries), slicing, disk layout.
  const Topology& topology = result.flow.topology;
  const Eigen::VectorXd lengths_3d = input_edge_lengths(mesh, topology);
  // Shortest paths in the hyperbolic metric: the loops are then short hyperbolic curves, the
  // fundamental domain compact, and the deck transformations short (a layout error grows like
  // sinh of the distance from the root, and the group relation multiplies the maps).
  result.cut = cut_graph(topology, result.flow.lengths);
  result.cut_mesh = slice(topology, result.cut);
  result.layout =
      layout_hyperbolic(topology, result.flow.lengths, result.cut, result.cut_mesh, options.layout);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (result.cut.is_cut_edge[e]) result.seam_length += lengths_3d[e];
  }

  // 3. The Fuchsian group of a closed surface.
  if (comp.num_boundary_loops == 0) {
    SegmentRelations relations;
    for (const SegmentIsometry& s : result.layout.segment_maps) {
      relations.segment_maps.push_back(s.map);
    }
    relations.node_words = result.layout.node_words;
    result.group = fuchsian_group(relations);
    result.has_group = true;
  }
  result.uv = result.layout.uv;
  result.distortion = measure_distortion(mesh, result.cut_mesh.triangles, result.uv);
  result.seconds = seconds();
  return result;
}

}  // namespace ricci
