#pragma once
/// \file
/// Connectivity of a manifold, consistently oriented triangle mesh as flat arrays: halfedges,
/// edges, boundary loops, connected components and their Euler characteristic and genus.
/// Built once per mesh; every kernel of ricci reads these arrays instead of a halfedge structure.

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// One connected component of a mesh.
struct Component {
  std::vector<int> vertices;     ///< vertex indices of the component, ascending
  std::vector<int> faces;        ///< face indices of the component, ascending
  int num_edges = 0;             ///< edges of the component
  int num_boundary_loops = 0;    ///< boundary loops of the component
  int euler_characteristic = 0;  ///< V - E + F of the component
  int genus = 0;                 ///< (2 - chi - b) / 2
};

/// Halfedge h = 3 f + k lies in face f opposite its corner k: it runs from vertex
/// triangles(f, (k+1)%3) to triangles(f, (k+2)%3). Corner c = 3 f + k is the corner of face f at
/// vertex triangles(f, k); corner and opposite halfedge share an index.
struct Topology {
  int num_vertices = 0;
  int num_edges = 0;
  int num_faces = 0;

  Triangles triangles;                                  ///< #F by 3, copied from the mesh
  Eigen::Matrix<int, Eigen::Dynamic, 2> edge_vertices;  ///< #E by 2, smaller index first
  Triangles face_edges;            ///< #F by 3: edge opposite corner k of face f
  std::vector<int> halfedge_twin;  ///< 3#F: opposite halfedge, -1 on the boundary
  std::vector<int> halfedge_edge;  ///< 3#F: edge of each halfedge
  Eigen::Matrix<int, Eigen::Dynamic, 2> edge_halfedges;  ///< #E by 2: its halfedges, -1 if none
  std::vector<char> is_boundary_vertex;                  ///< #V: 1 on a boundary loop
  std::vector<char> is_boundary_edge;                    ///< #E: 1 when the edge has one face
  std::vector<int> vertex_degree;                        ///< #V: number of incident edges
  std::vector<std::vector<int>> boundary_loops;  ///< vertices of each loop, surface on the left
  std::vector<int> vertex_component;  ///< #V: component index, -1 for unreferenced vertices
  std::vector<int> face_component;    ///< #F: component index
  std::vector<Component> components;  ///< in order of their smallest face index

  /// Halfedge helpers (see the struct comment for the numbering).
  static int face_of(int h) { return h / 3; }
  static int next(int h) { return h % 3 == 2 ? h - 2 : h + 1; }
  static int prev(int h) { return h % 3 == 0 ? h + 2 : h - 1; }
  int tail(int h) const { return triangles(h / 3, (h % 3 + 1) % 3); }
  int head(int h) const { return triangles(h / 3, (h % 3 + 2) % 3); }

  /// V - E + F over the whole mesh (unreferenced vertices not counted).
  int euler_characteristic() const;
  /// Number of boundary loops over the whole mesh.
  int num_boundary_loops() const { return static_cast<int>(boundary_loops.size()); }
  /// Number of vertices that belong to some face.
  int num_referenced_vertices() const;
};

/// Builds the connectivity of a triangle mesh.
/// \param triangles #F by 3 counter-clockwise vertex indices into [0, num_vertices)
/// \pre every face has three distinct vertices in range
/// \throw TopologyError naming the edge or vertex when an edge has more than two faces, two faces
///        traverse an edge in the same direction (inconsistent orientation), or a vertex joins
///        several fans of faces (non-manifold vertex)
/// \throw InvalidInput when an index is out of range or a face repeats a vertex
Topology build_topology(const Triangles& triangles, int num_vertices);

/// build_topology with a given first halfedge per interior edge: edge_halfedges(e, 0) is the
/// halfedge of e whose first_halfedge entry is 1 (a boundary edge keeps its only halfedge first).
/// A part of a mesh rebuilt on its own (a component) keeps the whole mesh's choice this way:
/// flip_edge orients its new faces by the first halfedge, so flips replayed on the whole mesh give
/// the same faces.
/// \param first_halfedge 3#F: 1 for the halfedge that comes first on its edge; of the two
///        halfedges of an interior edge, the one flagged 1 comes first (the builder's own choice
///        when both or neither are)
/// \throw as build_topology; InvalidInput when first_halfedge does not have 3#F entries
Topology build_topology(const Triangles& triangles, int num_vertices,
                        const std::vector<char>& first_halfedge);

}  // namespace ricci
