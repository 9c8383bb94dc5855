#include "ricci/mesh/components.hpp"

namespace ricci {

std::vector<Submesh> split_components(const Mesh& mesh, const Topology& topology) {
  std::vector<Submesh> out;
  out.reserve(topology.components.size());
  // Local index of each vertex within its own component; every vertex is in at most one.
  std::vector<int> local(mesh.num_vertices(), -1);
  for (const Component& component : topology.components) {
    Submesh sub;
    sub.vertex_map = component.vertices;
    sub.face_map = component.faces;
    const auto nv = static_cast<Eigen::Index>(component.vertices.size());
    const auto nf = static_cast<Eigen::Index>(component.faces.size());
    sub.mesh.positions.resize(nv, 3);
    for (Eigen::Index i = 0; i < nv; ++i) {
      local[component.vertices[i]] = static_cast<int>(i);
      sub.mesh.positions.row(i) = mesh.positions.row(component.vertices[i]);
    }
    sub.mesh.triangles.resize(nf, 3);
    for (Eigen::Index i = 0; i < nf; ++i) {
      for (int k = 0; k < 3; ++k) {
        sub.mesh.triangles(i, k) = local[mesh.triangles(component.faces[i], k)];
      }
    }
    out.push_back(std::move(sub));
  }
  return out;
}

}  // namespace ricci
