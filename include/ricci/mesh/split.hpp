#pragma once
/// \file
/// Local connectivity modification (tutorial section 5.3): edge splits that raise the valence of
/// a vertex so that a strong cone there satisfies the single-vertex bound of THEORY.md section 6.

#include <array>
#include <vector>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {

/// What raise_valence returns.
struct ValenceResult {
  Mesh mesh;  ///< the refined mesh: the input's vertices first, new ones appended
  /// For each new vertex (index #V_in + i): the two input-or-earlier vertices it splits.
  std::vector<std::array<int, 2>> new_vertex_parents;
  int splits = 0;         ///< edges split
  int final_valence = 0;  ///< valence of the vertex afterwards
  /// The connectivity of `mesh`, built once after the last round of splits (the caller's when
  /// there were none): the next stage needs it, and building it again would repeat the work.
  Topology topology;
};

/// Splits the edges opposite `vertex` in its faces at their midpoints (each split adds one
/// neighbour) until its valence is at least min_valence. Faces keep their orientation.
/// \pre mesh is manifold and consistently oriented
/// \throw InvalidInput when the vertex is out of range or used by no face
ValenceResult raise_valence(const Mesh& mesh, int vertex, int min_valence);

/// The same on a mesh whose connectivity the caller already holds (build_topology of mesh): no
/// build before the first round. Each round of splits builds the connectivity once, and the last
/// such build is ValenceResult::topology.
ValenceResult raise_valence(const Mesh& mesh, const Topology& topology, int vertex,
                            int min_valence);

}  // namespace ricci

namespace ricci {

/// One step of 1-to-4 midpoint subdivision: every edge gets its midpoint, every face becomes four.
/// Original vertices keep their valence and index; new vertices follow, one per edge in the order
/// of the input's edges (build_topology).
Mesh subdivide_midpoint(const Mesh& mesh);

}  // namespace ricci
