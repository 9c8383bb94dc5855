#pragma once
/// \file
/// The input metric of a mesh flipped isometrically to its intrinsic Delaunay triangulation: the
/// starting point of the tests that follow the input's faces and edges through the flips.

#include <Eigen/Core>

#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci::testing {

struct Flipped {
  Topology input, flipped;
  Eigen::VectorXd input_lengths, lengths;  ///< #E lengths of `input` and of `flipped`
  DelaunayFlipResult flips;
};

/// Flips the mesh's own edge lengths (vertex scaling at its initial u, so no length changes) to
/// the intrinsic Delaunay triangulation.
inline Flipped flip_isometrically(const Mesh& mesh) {
  Flipped f;
  f.input = build_topology(mesh.triangles, mesh.num_vertices());
  f.flipped = f.input;
  f.input_lengths = input_edge_lengths(mesh, f.input);
  f.lengths = f.input_lengths;
  StructureOptions vertex_scaling;
  vertex_scaling.scheme = Scheme::VertexScaling;
  ConformalStructure s = make_conformal_structure(f.input, f.lengths, vertex_scaling).structure;
  DelaunayFlipOptions options;
  options.isometric = true;
  f.flips = flip_to_delaunay(f.flipped, s, s.initial_u, f.lengths, options);
  return f;
}

}  // namespace ricci::testing
