#include "ricci/hyperbolic/hyperbolic_param.hpp"

#include <chrono>
#include <limits>
#include <sstream>
#include <string>

#include "ricci/errors.hpp"
#include "ricci/param/layout/polygon_fans.hpp"

namespace ricci {

namespace {

/// One cut, its layout and its group.
struct Attempt {
  CutGraph cut;
  CutMesh cut_mesh;
  HyperbolicLayout layout;
  FuchsianGroup group;
  std::string group_failure;  // why the group could not be computed (empty: it was)
};

/// The default root (-1: cut_graph's own choice), then vertices spread over the surface by
/// farthest-point sampling in steps across edges (breadth-first from all roots so far).
std::vector<int> candidate_roots(const Topology& t, int count) {
  std::vector<int> roots = {-1};
  std::vector<int> picked;
  int first = -1;
  for (int v = 0; v < t.num_vertices && first < 0; ++v) {
    if (t.vertex_component[v] >= 0) first = v;
  }
  if (first < 0) return roots;
  // Adjacency through the edges.
  std::vector<std::vector<int>> neighbours(t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    neighbours[t.edge_vertices(e, 0)].push_back(t.edge_vertices(e, 1));
    neighbours[t.edge_vertices(e, 1)].push_back(t.edge_vertices(e, 0));
  }
  std::vector<int> distance(t.num_vertices, -1);
  std::vector<int> queue;
  int next = first;
  while (static_cast<int>(roots.size()) < count) {
    picked.push_back(next);
    roots.push_back(next);
    std::fill(distance.begin(), distance.end(), -1);
    queue.assign(picked.begin(), picked.end());
    for (int p : picked) distance[p] = 0;
    int farthest = next;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int v = queue[head];
      if (distance[v] > distance[farthest]) farthest = v;
      for (int w : neighbours[v]) {
        if (distance[w] < 0) {
          distance[w] = distance[v] + 1;
          queue.push_back(w);
        }
      }
    }
    if (distance[farthest] <= 0) break;
    next = farthest;
  }
  return roots;
}

}  // namespace

HyperbolicParamResult parameterize_hyperbolic(const Mesh& mesh,
                                              const HyperbolicParamOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  HyperbolicParamResult result;
  check_polygons(options.polygons, mesh.triangles, "parameterize_hyperbolic");
  Topology t0 = build_topology(mesh.triangles, mesh.num_vertices());
  if (t0.components.size() != 1) {
    throw InvalidInput("parameterize_hyperbolic: the mesh has " +
                       std::to_string(t0.components.size()) +
                       " connected components; parameterize them one by one");
  }
  const Component& comp = t0.components[0];
  if (comp.euler_characteristic >= 0) {
    throw InvalidInput("parameterize_hyperbolic: a surface with chi = " +
                           std::to_string(comp.euler_characteristic) + " (genus " +
                           std::to_string(comp.genus) + ", " +
                           std::to_string(comp.num_boundary_loops) +
                           " boundary loops) has no hyperbolic metric; it needs chi < 0 (genus >= "
                           "2, or boundaries); "
                           "the Euclidean geometry gives a flat metric with cones",
                       fixes_of({{"geometry", "euclidean"}}));
  }

  // 1. The uniformization metric: K = 0 everywhere, geodesic boundary. The problem (topology,
  // 3D lengths, hyperbolic structure) is built once; the cut below reads it too.
  StructureOptions structure = options.structure;
  structure.geometry = Geometry::Hyperbolic;
  TargetSpec flat;
  flat.kind = TargetKind::Flat;
  flat.boundary = BoundaryMode::Geodesic;
  MeshFlowOptions flow_options = mesh_flow_options(structure, options.flow, flat);
  const FlowProblem problem = make_flow_problem(mesh, std::move(t0), flow_options.structure);
  result.flow = flow_mesh(problem, flow_options);
  result.converged = result.flow.converged;
  if (!result.converged) {
    result.message = result.flow.message;
    result.seconds = seconds();
    return result;
  }

  // 2. The metric refined in long double: the group relation multiplies every misclosure of the
  // layout by the squared norms of long words. With flips the metric lives on the intrinsic
  // Delaunay triangulation (possibly a Delta-complex), with the constants its flips set.
  const IntrinsicTriangulation& intrinsic = result.flow.intrinsic;
  result.refinement = refine_hyperbolic_metric(intrinsic.topology(), intrinsic.structure(),
                                               result.flow.target, result.flow.u);

  // The input's own faces in that metric: without flips their lengths; with flips each face
  // developed into the disk by undoing the flips (long double), so that the cut runs along input
  // edges and the layout, the seams and the written faces are the user's.
  const Topology& topology = problem.topology;
  const bool flipped = intrinsic.flips() > 0;
  HyperbolicDevelopment development;
  Eigen::VectorXd path_lengths = result.flow.lengths;  // hyperbolic lengths of the input edges
  if (flipped) {
    development = intrinsic.develop_input_faces_hyperbolic(result.refinement.lengths);
    result.development_length_mismatch = development.max_length_mismatch;
    path_lengths = development.lengths.cast<double>();
  }
  const Eigen::VectorXd& lengths_3d = problem.input_lengths;

  // 3. Cut graph (no cones: 2 g loops, joined to the boundaries), slicing, disk layout and, on a
  // closed surface, the Fuchsian group. Shortest paths follow the hyperbolic metric, so that
  // the loops are short hyperbolic curves. How well conditioned the canonical generators come
  // out depends on where the tree-cotree grows from (on a generated genus-4 surface the relation
  // residual ranged from 1e-11 to 6e-6 over root vertices), so roots spread over the
  // surface are tried and the best-conditioned group is kept.
  const bool closed = topology.components[0].num_boundary_loops == 0;
  const std::vector<int> roots =
      closed ? candidate_roots(topology, std::max(1, options.cut_candidates))
             : std::vector<int>{-1};
  bool have_layout = false;
  std::string layout_failure;
  const std::vector<char> uncut_edges = polygon_diagonals(topology, options.polygons);
  for (int root : roots) {
    Attempt a;
    CutGraphOptions cut_options;
    cut_options.root_vertex = root;
    cut_options.uncut_edges = uncut_edges;
    a.cut = cut_graph(topology, path_lengths, cut_options);
    a.cut_mesh = slice(topology, a.cut);
    try {
      a.layout = flipped ? layout_hyperbolic(topology, development.shapes, a.cut, a.cut_mesh,
                                             options.layout)
                         : layout_hyperbolic(topology, result.refinement.lengths, a.cut, a.cut_mesh,
                                             options.layout);
    } catch (const InvalidInput& e) {
      // Another root may give a domain that stays within reach of the arithmetic.
      layout_failure = e.what();
      ++result.cut_candidates_tried;
      continue;
    }
    if (closed) {
      SegmentRelations relations;
      for (const SegmentIsometry& s : a.layout.segment_maps) {
        relations.segment_maps.push_back(s.map);
        relations.wide_segment_maps.push_back(s.wide_map);
      }
      relations.node_words = a.layout.node_words;
      try {
        a.group = fuchsian_group(relations);
      } catch (const InvalidInput& e) {
        // Far out in the disk (high genus) the segment maps' entries grow past what double
        // rounds faithfully; keep the layout, try the next cut, and say why if none works.
        a.group = FuchsianGroup{};
        a.group.relation_residual = std::numeric_limits<double>::infinity();
        a.group_failure = e.what();
      }
    }
    ++result.cut_candidates_tried;
    const bool better = !have_layout || a.group.relation_residual < result.group.relation_residual;
    have_layout = true;
    if (better) {
      result.cut = std::move(a.cut);
      result.cut_mesh = std::move(a.cut_mesh);
      result.layout = std::move(a.layout);
      result.group = std::move(a.group);
      result.group_failure = std::move(a.group_failure);
      result.cut_root = root;
    }
    if (!closed || result.group.relation_residual <= options.good_relation_residual) break;
  }
  if (!have_layout)
    throw InvalidInput(layout_failure + " (tried " + std::to_string(roots.size()) + " cuts)");
  if (closed && result.group_failure.empty() &&
      !(result.group.relation_residual <= options.usable_relation_residual)) {
    std::ostringstream why;
    why << "the best of " << result.cut_candidates_tried
        << " cuts gives generators whose relation misses the identity by "
        << result.group.relation_residual
        << ": far out in the disk the segment maps exceed what the arithmetic resolves";
    result.group_failure = why.str();
  }
  result.has_group = closed && result.group_failure.empty();
  for (int e = 0; e < topology.num_edges; ++e) {
    if (result.cut.is_cut_edge[e]) result.seam_length += lengths_3d[e];
  }
  result.uv = result.layout.uv;
  result.polygons =
      start_fans_where_valid(options.polygons, mesh, result.cut_mesh.triangles, result.uv);
  result.distortion =
      measure_polygon_distortion(mesh, result.polygons, result.cut_mesh.triangles, result.uv);
  result.seconds = seconds();
  return result;
}

}  // namespace ricci
