#include "ricci/mesh/doubled_topology.hpp"

#include <algorithm>
#include <utility>

namespace ricci {
namespace {

/// The connectivity of the double (DoubledTopology::topology) from the input's own.
Topology connect_double(const Topology& t, const Triangles& triangles, int num_vertices) {
  const int nf = t.num_faces, ne = t.num_edges;
  auto mirrored = [nf](int h) { return 3 * (nf + h / 3) + kMirroredCorner[h % 3]; };
  Topology d;
  d.num_vertices = num_vertices;
  d.num_faces = 2 * nf;
  d.triangles = triangles;
  d.halfedge_twin.assign(6 * static_cast<std::size_t>(nf), -1);
  d.halfedge_edge.assign(6 * static_cast<std::size_t>(nf), -1);
  d.face_edges.resize(2 * nf, 3);
  int interior_edges = 0;
  for (int e = 0; e < ne; ++e) interior_edges += !t.is_boundary_edge[e];
  d.num_edges = ne + interior_edges;
  d.edge_vertices.resize(d.num_edges, 2);
  d.edge_halfedges.resize(d.num_edges, 2);
  std::vector<int> mirror_edge(ne, -1);
  int next = ne;
  for (int e = 0; e < ne; ++e) mirror_edge[e] = t.is_boundary_edge[e] ? e : next++;
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k, m = mirrored(h), e = t.halfedge_edge[h];
      const int twin = t.halfedge_twin[h];
      d.halfedge_twin[h] = twin >= 0 ? twin : m;
      d.halfedge_twin[m] = twin >= 0 ? mirrored(twin) : h;
      d.halfedge_edge[h] = e;
      d.halfedge_edge[m] = mirror_edge[e];
      d.face_edges(f, k) = e;
      d.face_edges(nf + f, kMirroredCorner[k]) = mirror_edge[e];
    }
  }
  auto tail = [&](int h) { return d.triangles(h / 3, (h % 3 + 1) % 3); };
  auto head = [&](int h) { return d.triangles(h / 3, (h % 3 + 2) % 3); };
  for (int e = 0; e < ne; ++e) {
    const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
    d.edge_halfedges(e, 0) = h0;
    d.edge_halfedges(e, 1) = h1 >= 0 ? h1 : mirrored(h0);
    if (mirror_edge[e] != e) {
      d.edge_halfedges(mirror_edge[e], 0) = mirrored(h0);
      d.edge_halfedges(mirror_edge[e], 1) = mirrored(h1);
    }
  }
  for (int e = 0; e < d.num_edges; ++e) {
    const int h = d.edge_halfedges(e, 0);
    d.edge_vertices(e, 0) = std::min(tail(h), head(h));
    d.edge_vertices(e, 1) = std::max(tail(h), head(h));
  }
  d.is_boundary_vertex.assign(num_vertices, 0);
  d.is_boundary_edge.assign(d.num_edges, 0);
  d.vertex_degree.assign(num_vertices, 0);
  for (int e = 0; e < d.num_edges; ++e) {
    ++d.vertex_degree[d.edge_vertices(e, 0)];
    ++d.vertex_degree[d.edge_vertices(e, 1)];
  }
  d.vertex_component.assign(num_vertices, 0);
  d.face_component.assign(d.num_faces, 0);
  Component c;
  c.vertices.resize(num_vertices);
  for (int v = 0; v < num_vertices; ++v) c.vertices[v] = v;
  c.faces.resize(d.num_faces);
  for (int f = 0; f < d.num_faces; ++f) c.faces[f] = f;
  c.num_edges = d.num_edges;
  c.num_boundary_loops = 0;
  c.euler_characteristic = num_vertices - d.num_edges + d.num_faces;
  c.genus = (2 - c.euler_characteristic) / 2;
  d.components.push_back(std::move(c));
  return d;
}

}  // namespace

DoubledTopology build_doubled_topology(const Topology& t) {
  DoubledTopology d;
  const int nv = t.num_vertices, nf = t.num_faces;
  std::vector<int> mirror(nv, -1);
  d.original.resize(nv);
  for (int v = 0; v < nv; ++v) d.original[v] = v;
  for (int v = 0; v < nv; ++v) {
    if (t.is_boundary_vertex[v]) {
      mirror[v] = v;
    } else {
      mirror[v] = static_cast<int>(d.original.size());
      d.original.push_back(v);
    }
  }
  d.triangles.resize(2 * nf, 3);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      d.triangles(f, k) = t.triangles(f, k);
      d.triangles(nf + f, k) = mirror[t.triangles(f, kMirroredCorner[k])];
    }
  }
  d.num_vertices = static_cast<int>(d.original.size());
  d.topology = connect_double(t, d.triangles, d.num_vertices);
  return d;
}

}  // namespace ricci
