#include "ricci/metric/background.hpp"

#include "ricci/errors.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci {

const GeometryTraits& geometry_traits(Geometry geometry) {
  for (const GeometryTraits& row : kGeometryTraits) {
    if (row.geometry == geometry) return row;
  }
  throw InvalidInput("geometry_traits: no geometry " + std::to_string(static_cast<int>(geometry)));
}

const char* geometry_name(Geometry geometry) {
  return enum_name(geometry);
}

Geometry parse_geometry(const std::string& name) {
  return parse_enum<Geometry>(name, "parse_geometry");
}

LengthsCheck edge_lengths(const Topology& topology, const ConformalStructure& structure,
                          const Eigen::VectorXd& u, Eigen::VectorXd& lengths) {
  switch (structure.geometry) {
    case Geometry::Euclidean:
      return euclidean_edge_lengths(topology, structure, u, lengths);
    case Geometry::Hyperbolic:
      return hyperbolic_edge_lengths(topology, structure, u, lengths);
  }
  throw InvalidInput("edge_lengths: unknown geometry");
}

AnglesCheck corner_angles(const Topology& topology, const Eigen::VectorXd& lengths,
                          CornerAngles& angles, Geometry geometry) {
  switch (geometry) {
    case Geometry::Euclidean:
      return corner_angles(topology, lengths, angles);
    case Geometry::Hyperbolic:
      return hyperbolic_corner_angles(topology, lengths, angles);
  }
  throw InvalidInput("corner_angles: unknown geometry");
}

void hessian_terms(const Topology& topology, const ConformalStructure& structure,
                   const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                   const CornerAngles& angles, Eigen::VectorXd& halfedge_w,
                   Eigen::VectorXd& corner_diagonal, Eigen::VectorXd& vertex_diagonal) {
  switch (structure.geometry) {
    case Geometry::Euclidean:
      halfedge_weights(topology, structure, u, lengths, angles, halfedge_w);
      corner_diagonal.resize(0);
      vertex_diagonal.resize(0);
      return;
    case Geometry::Hyperbolic:
      hyperbolic_hessian_terms(topology, structure, u, lengths, angles, halfedge_w,
                               corner_diagonal);
      vertex_diagonal.setZero(topology.num_vertices);
      for (int f = 0; f < topology.num_faces; ++f) {
        for (int k = 0; k < 3; ++k)
          vertex_diagonal[topology.triangles(f, k)] += corner_diagonal[3 * f + k];
      }
      return;
  }
  throw InvalidInput("hessian_terms: unknown geometry");
}

double gauss_bonnet_area(Geometry geometry, const CornerAngles& angles) {
  switch (geometry) {
    case Geometry::Euclidean:
      return 0.0;
    case Geometry::Hyperbolic:
      return hyperbolic_total_area(angles);
  }
  throw InvalidInput("gauss_bonnet_area: unknown geometry");
}

double gauss_bonnet_relative_error(Geometry geometry, const Topology& topology,
                                   const Eigen::VectorXd& curvature, double area) {
  switch (geometry) {
    case Geometry::Euclidean:
      return gauss_bonnet_relative_error(topology, curvature);
    case Geometry::Hyperbolic:
      return hyperbolic_gauss_bonnet_relative_error(topology, curvature, area);
  }
  throw InvalidInput("gauss_bonnet_relative_error: unknown geometry");
}

}  // namespace ricci
