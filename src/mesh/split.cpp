#include "ricci/mesh/split.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {

ValenceResult raise_valence(const Mesh& mesh, int vertex, int min_valence) {
  // (The vertex is checked by the overload; build_topology does not read it.)
  return raise_valence(mesh, build_topology(mesh.triangles, mesh.num_vertices()), vertex,
                       min_valence);
}

ValenceResult raise_valence(const Mesh& mesh, const Topology& topology, int vertex,
                            int min_valence) {
  if (vertex < 0 || vertex >= mesh.num_vertices()) {
    throw InvalidInput("raise_valence: vertex " + std::to_string(vertex) + " is out of range [0, " +
                       std::to_string(mesh.num_vertices()) + ")");
  }
  if (topology.num_vertices != mesh.num_vertices() || topology.num_faces != mesh.num_faces()) {
    throw InvalidInput("raise_valence: the topology has " + std::to_string(topology.num_vertices) +
                       " vertices and " + std::to_string(topology.num_faces) + " faces, the mesh " +
                       std::to_string(mesh.num_vertices()) + " and " +
                       std::to_string(mesh.num_faces()) + " (build_topology of another mesh)");
  }
  ValenceResult result;
  std::vector<Eigen::Vector3d> positions(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) positions[v] = mesh.positions.row(v);
  std::vector<std::array<int, 3>> faces(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    faces[f] = {mesh.triangles(f, 0), mesh.triangles(f, 1), mesh.triangles(f, 2)};
  }
  auto to_mesh = [&]() {
    Mesh out;
    out.positions.resize(static_cast<Eigen::Index>(positions.size()), 3);
    for (std::size_t v = 0; v < positions.size(); ++v) out.positions.row(v) = positions[v];
    out.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      for (int k = 0; k < 3; ++k) out.triangles(f, k) = faces[f][k];
    }
    return out;
  };

  // The connectivity of the current faces: the caller's before the first split, then built after
  // each round (the last build is the result's).
  std::optional<Topology> built;
  for (;;) {
    const Topology& t = built ? *built : topology;
    result.final_valence = t.vertex_degree[vertex];
    if (t.vertex_component[vertex] < 0) {
      throw InvalidInput("raise_valence: vertex " + std::to_string(vertex) + " is in no face");
    }
    if (result.final_valence >= min_valence) break;
    // One round: split every link edge whose faces no earlier split of this round touched.
    std::vector<char> touched(faces.size(), 0);
    const std::size_t face_count = faces.size();
    int round_splits = 0;
    for (std::size_t f = 0; f < face_count; ++f) {
      int k = 0;
      while (k < 3 && faces[f][k] != vertex) ++k;
      if (k == 3 || touched[f]) continue;
      const int h = static_cast<int>(3 * f) + k;  // halfedge opposite the vertex
      const int twin = t.halfedge_twin[h];
      if (twin >= 0 && touched[twin / 3]) continue;
      const int a = t.tail(h), b = t.head(h);
      const int m = static_cast<int>(positions.size());
      // Evaluated before the push: the sum reads elements a reallocation may move.
      const Eigen::Vector3d midpoint = 0.5 * (positions[a] + positions[b]);
      positions.push_back(midpoint);
      result.new_vertex_parents.push_back(std::array<int, 2>{a, b});
      // (vertex, a, b) -> (vertex, a, m) + (vertex, m, b)
      touched[f] = 1;
      faces[f] = {vertex, a, m};
      faces.push_back({vertex, m, b});
      touched.push_back(1);
      if (twin >= 0) {
        const int g = twin / 3, j = twin % 3;
        const int d = faces[g][j];  // the corner opposite edge (b, a) in the other face
        touched[g] = 1;
        faces[g] = {d, b, m};
        faces.push_back({d, m, a});
        touched.push_back(1);
      }
      ++result.splits;
      ++round_splits;
      if (t.vertex_degree[vertex] + round_splits >= min_valence) break;
    }
    if (round_splits == 0) break;  // cannot happen on a valid mesh; guards an endless loop
    result.mesh = to_mesh();
    built = build_topology(result.mesh.triangles, result.mesh.num_vertices());
  }
  if (built) {
    result.topology = std::move(*built);
  } else {
    result.mesh = mesh;
    result.topology = topology;
  }
  return result;
}

}  // namespace ricci

namespace ricci {

Mesh subdivide_midpoint(const Mesh& mesh) {
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const int nv = mesh.num_vertices();
  Mesh out;
  out.positions.resize(nv + t.num_edges, 3);
  out.positions.topRows(nv) = mesh.positions;
  for (int e = 0; e < t.num_edges; ++e) {
    out.positions.row(nv + e) = 0.5 * (mesh.positions.row(t.edge_vertices(e, 0)) +
                                       mesh.positions.row(t.edge_vertices(e, 1)));
  }
  out.triangles.resize(4 * t.num_faces, 3);
  for (int f = 0; f < t.num_faces; ++f) {
    // m[k] is the midpoint of the edge opposite corner k.
    const int v[3] = {t.triangles(f, 0), t.triangles(f, 1), t.triangles(f, 2)};
    const int m[3] = {nv + t.face_edges(f, 0), nv + t.face_edges(f, 1), nv + t.face_edges(f, 2)};
    out.triangles.row(4 * f + 0) << v[0], m[2], m[1];
    out.triangles.row(4 * f + 1) << v[1], m[0], m[2];
    out.triangles.row(4 * f + 2) << v[2], m[1], m[0];
    out.triangles.row(4 * f + 3) << m[0], m[1], m[2];
  }
  return out;
}

}  // namespace ricci
