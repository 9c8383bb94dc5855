#include "ricci/mesh/info.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {
namespace {

/// Defects that leave the connectivity undefined; non-finite coordinates and zero-area faces
/// do not.
bool blocks_topology(DefectKind kind) {
  switch (kind) {
    case DefectKind::IndexOutOfRange:
    case DefectKind::RepeatedVertex:
    case DefectKind::DuplicateFace:
    case DefectKind::NonManifoldEdge:
    case DefectKind::NonManifoldVertex:
    case DefectKind::InconsistentOrientation:
    case DefectKind::NonOrientable:
      return true;
    default:
      return false;
  }
}

}  // namespace

MeshInfo mesh_info(const Mesh& mesh) {
  MeshInfo info;
  const int nv = mesh.num_vertices();
  const int nf = mesh.num_faces();
  info.faces = nf;
  info.validation = find_defects(mesh);

  std::vector<char> referenced(nv, 0);
  std::vector<char> valid_face(nf, 1);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k);
      if (v >= 0 && v < nv) {
        referenced[v] = 1;
      } else {
        valid_face[f] = 0;
      }
    }
  }
  for (int v = 0; v < nv; ++v) (referenced[v] ? info.vertices : info.unreferenced_vertices) += 1;

  // Corner angles as atan2(|a x b|, a . b): accurate for needles, where acos of a normalised dot
  // product loses all digits near 0 and 180 degrees.
  double min_angle = std::numeric_limits<double>::infinity();
  double max_angle = -std::numeric_limits<double>::infinity();
  for (int f = 0; f < nf; ++f) {
    if (!valid_face[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = mesh.positions.row(mesh.triangles(f, k)).transpose();
      const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, (k + 1) % 3)).transpose() - p;
      const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, (k + 2) % 3)).transpose() - p;
      const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
      if (!std::isfinite(angle)) continue;
      min_angle = std::min(min_angle, angle);
      max_angle = std::max(max_angle, angle);
    }
  }
  if (min_angle <= max_angle) {
    info.min_angle_degrees = min_angle * 180.0 / std::numbers::pi;
    info.max_angle_degrees = max_angle * 180.0 / std::numbers::pi;
  }

  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d p = mesh.positions.row(v).transpose();
    if (!referenced[v] || !p.allFinite()) continue;
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  if ((low.array() <= high.array()).all()) info.bounding_box_diagonal = (high - low).norm();

  const bool topology_defined =
      std::none_of(info.validation.counts.begin(), info.validation.counts.end(),
                   [](const auto& count) { return blocks_topology(count.first); });
  if (!topology_defined) return info;
  try {
    const Topology topology = build_topology(mesh.triangles, nv);
    info.edges = topology.num_edges;
    info.components = static_cast<int>(topology.components.size());
    info.boundary_loops = topology.num_boundary_loops();
    info.euler_characteristic = topology.euler_characteristic();
    info.genus = 0;
    for (const Component& c : topology.components) {
      ComponentInfo component;
      component.vertices = static_cast<int>(c.vertices.size());
      component.edges = c.num_edges;
      component.faces = static_cast<int>(c.faces.size());
      component.boundary_loops = c.num_boundary_loops;
      component.euler_characteristic = c.euler_characteristic;
      component.genus = c.genus;
      info.genus += c.genus;
      info.component_info.push_back(component);
    }
  } catch (const Error&) {
    // find_defects and build_topology agree on what breaks connectivity; should they ever
    // disagree, the summary keeps its -1 fields rather than failing `ricci info`.
  }
  return info;
}

}  // namespace ricci
