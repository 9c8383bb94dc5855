#pragma once
/// \file
/// Conformal structures and their curvature at given log radii, for tests that probe K(u)
/// directly.

#include <random>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/metric/scheme.hpp"
#include "support/test_meshes.hpp"

namespace ricci::testing {

/// Every scheme, for the properties that must hold whichever one a caller picks.
inline constexpr Scheme kAllSchemes[] = {Scheme::Tangential, Scheme::Thurston,
                                         Scheme::InversiveDistance, Scheme::VertexScaling,
                                         Scheme::VirtualRadius};

/// The conformal structure of `scheme` (and `geometry`) fitted to the edge lengths `lbar`.
inline ConformalStructure structure_of(const Topology& t, const Eigen::VectorXd& lbar,
                                       Scheme scheme, Geometry geometry = Geometry::Euclidean) {
  StructureOptions options;
  options.scheme = scheme;
  options.geometry = geometry;
  return make_conformal_structure(t, lbar, options).structure;
}

/// The conformal structure of `scheme` (and `geometry`) fitted to the mesh's own edge lengths.
inline ConformalStructure structure_of(const Mesh& mesh, const Topology& t, Scheme scheme,
                                       Geometry geometry = Geometry::Euclidean) {
  return structure_of(t, input_edge_lengths(mesh, t), scheme, geometry);
}

/// Calls `check(name, t, s, scheme)` for every mesh of `meshes` under every scheme, with `s`
/// fitted to the mesh's own edge lengths and `t` its topology: the loop of the properties that
/// must hold on any mesh whichever scheme a caller picks.
template <class Check>
void for_every_mesh_and_scheme(const std::vector<NamedMesh>& meshes, Check check) {
  for (const auto& [name, mesh] : meshes) {
    const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
    const Eigen::VectorXd lbar = input_edge_lengths(mesh, t);
    for (Scheme scheme : kAllSchemes) check(name, t, structure_of(t, lbar, scheme), scheme);
  }
}

/// Random changes of u that keep `scheme`'s triangles valid: packings with Phi in [0, pi/2]
/// (Thurston, tangential) accept any radii, so they draw from [-wide, wide]; the others only
/// small changes, from [-narrow, narrow].
inline std::uniform_real_distribution<double> u_noise(Scheme scheme, double wide, double narrow) {
  const bool any_radii = scheme == Scheme::Thurston || scheme == Scheme::Tangential;
  return std::uniform_real_distribution<double>(any_radii ? -wide : -narrow,
                                                any_radii ? wide : narrow);
}

/// K(u) for a conformal structure; an empty vector when u breaks a length or a triangle
/// inequality.
inline Eigen::VectorXd curvature_at(const Topology& t, const ConformalStructure& s,
                                    const Eigen::VectorXd& u) {
  Eigen::VectorXd l;
  CornerAngles a;
  if (!edge_lengths(t, s, u, l).ok() || !corner_angles(t, l, a).ok()) return {};
  return vertex_curvature(t, a);
}

}  // namespace ricci::testing
