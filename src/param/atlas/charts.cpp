#include "param/atlas/detail/charts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "param/detail/one_component.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/components.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/disjoint_sets.hpp"
#include "ricci/param/atlas/chart_packing.hpp"
#include "ricci/param/layout/polygon_fans.hpp"
#include "ricci/param/layout/untangle.hpp"

namespace ricci::param_detail {
namespace {

/// Flattenings of the remaining faces at most: each takes the faces still flipped out of the
/// chart; the last takes out every chart that still has one.
constexpr int kRounds = 4;
/// A chart's boundary edge whose layout length differs from its 3D length by more than this
/// (relative) would leave an inexact seam: the layout itself is exact to about 1e-12.
constexpr double kSeamTolerance = 5e-10;

/// The vertex farthest from `from` along the edges (Dijkstra over the given lengths).
int farthest_vertex(const Topology& t, const Eigen::VectorXd& lengths, int from) {
  std::vector<std::vector<std::pair<int, double>>> adjacent(t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    const int a = t.edge_vertices(e, 0), b = t.edge_vertices(e, 1);
    adjacent[a].emplace_back(b, lengths[e]);
    adjacent[b].emplace_back(a, lengths[e]);
  }
  std::vector<double> distance(t.num_vertices, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  distance[from] = 0;
  queue.emplace(0.0, from);
  int far = from;
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    if (d > distance[far]) far = v;
    for (const auto& [w, l] : adjacent[v]) {
      if (d + l < distance[w]) distance[w] = d + l, queue.emplace(d + l, w);
    }
  }
  return far;
}

/// Faces of a mesh as a mesh of their own, with a vertex per fan: corners glued across the edges
/// the faces share, never through a bare vertex, so that the result is a manifold (two faces of a
/// manifold that meet only at a vertex get a copy of it each). `source`: per vertex of the
/// result, the vertex of `mesh` it copies.
Mesh faces_as_mesh(const Mesh& mesh, const std::vector<int>& faces, std::vector<int>& source) {
  const auto n = static_cast<int>(faces.size());
  // An edge's two faces meet in the sorted list of (smaller end, larger end, face).
  std::vector<std::array<int, 3>> keys;
  keys.reserve(3 * faces.size());
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(faces[i], (k + 1) % 3),
                b = mesh.triangles(faces[i], (k + 2) % 3);
      keys.push_back({std::min(a, b), std::max(a, b), i});
    }
  }
  std::sort(keys.begin(), keys.end());
  DisjointSets corners(3 * n);
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    if (keys[i][0] != keys[i + 1][0] || keys[i][1] != keys[i + 1][1]) continue;
    const int f = keys[i][2], g = keys[i + 1][2];
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) {
        const int v = mesh.triangles(faces[f], k);
        if (v != mesh.triangles(faces[g], j) || (v != keys[i][0] && v != keys[i][1])) continue;
        corners.unite(3 * f + k, 3 * g + j);
      }
    }
  }
  Mesh out;
  out.triangles.resize(n, 3);
  std::vector<int> id(3 * faces.size(), -1);
  source.clear();
  for (int c = 0; c < 3 * n; ++c) {
    int& v = id[corners.find(c)];
    if (v < 0)
      v = static_cast<int>(source.size()), source.push_back(mesh.triangles(faces[c / 3], c % 3));
    out.triangles(c / 3, c % 3) = v;
  }
  out.positions.resize(static_cast<Eigen::Index>(source.size()), 3);
  for (std::size_t v = 0; v < source.size(); ++v) {
    out.positions.row(static_cast<Eigen::Index>(v)) = mesh.positions.row(source[v]);
  }
  return out;
}

/// A flattened chart: a connected piece of the remaining faces with the pipeline's result.
struct Flat {
  std::vector<int> faces;     ///< per face of the piece: its face in the component
  std::vector<int> vertices;  ///< per vertex of the piece: its vertex in the disk
  ParamResult param;
};

/// The pipeline's layout passes its own checks: converged, closes up, finite.
bool usable(const ParamResult& p, const ParamOptions& options) {
  return p.converged && p.layout.uv.allFinite() &&
         p.layout.max_length_relative_error <= options.fold_free.max_length_error;
}

/// Faces of a flattened piece that cannot stay in it: flipped ones, and those with a boundary
/// edge that did not keep its 3D length (a flow that had to be doubled along the boundary flips
/// boundary edges, and the input's edge there comes out at another length), which would leave a
/// seam of different lengths on its two sides.
std::vector<int> faces_to_take_out(const ParamResult& p) {
  const Triangles& corners = p.cut_mesh.triangles;
  const Points& uv = p.layout.uv;
  std::vector<int> out;
  const Topology t = build_topology(p.mesh.triangles, p.mesh.num_vertices());
  for (int f = 0; f < corners.rows(); ++f) {
    const Eigen::Vector2d a = uv.row(corners(f, 0)).transpose();
    const Eigen::Vector2d b = Eigen::Vector2d(uv.row(corners(f, 1))) - a;
    const Eigen::Vector2d c = Eigen::Vector2d(uv.row(corners(f, 2))) - a;
    bool take = !(b.x() * c.y() - b.y() * c.x() > 0);
    for (int k = 0; k < 3 && !take; ++k) {
      if (t.halfedge_twin[3 * f + k] >= 0) continue;
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const double length3 = (p.mesh.positions.row(p.mesh.triangles(f, i)) -
                              p.mesh.positions.row(p.mesh.triangles(f, j)))
                                 .norm();
      const double length2 = (uv.row(corners(f, i)) - uv.row(corners(f, j))).norm();
      take = !(std::abs(length2 - length3) <= kSeamTolerance * length3);
    }
    if (take) out.push_back(f);
  }
  return out;
}

/// The component cut open into a disk along a cut graph through `cut_through` (a sphere with
/// fewer: along a path between two vertices far apart), never along a polygon's diagonal.
/// `cut_vertices`: the vertices the cut went through.
CutMesh cut_open(const Topology& t, const Eigen::VectorXd& lengths, const Polygons& polygons,
                 const std::vector<int>& cut_through, std::vector<int>& cut_vertices) {
  CutGraphOptions cut_options;
  cut_options.cones = cut_through;
  cut_options.uncut_edges = polygon_diagonals(t, polygons);
  const Component& component = t.components.front();
  if (component.num_boundary_loops == 0 && component.genus == 0 && cut_through.size() < 2) {
    const int a = farthest_vertex(t, lengths, component.vertices.front());
    cut_options.cones = {a, farthest_vertex(t, lengths, a)};
  }
  cut_vertices = cut_options.cones;
  return slice(t, cut_graph(t, lengths, cut_options));
}

/// The pipeline's options for one piece of the disk: free boundary (u = 0 there), no cones, no
/// quantization, and no untangling (done here with the boundary fixed: the pipeline's own
/// untangling moves a free boundary, which would take the seams off their 3D lengths).
ParamOptions piece_options(const ParamOptions& options) {
  ParamOptions inner = options;
  inner.cone_mode = ConeMode::None;
  inner.cones.clear();
  inner.quantize = false;
  inner.boundary = BoundaryMode::Free;
  inner.fold_free.untangle = false;
  return inner;
}

/// Flattens one piece (the pipeline, then untangling with the boundary fixed) into flat.param;
/// false when the pipeline failed or its layout is not usable. `flipped`: the piece's faces
/// (indices into flat.faces) that cannot stay (faces_to_take_out). The untangling's figures are
/// added to out.untangle.
bool flatten_piece(const Mesh& piece, const ParamOptions& options, ParamOptions& inner, Flat& flat,
                   std::vector<int>& flipped, ChartsLayout& out) {
  bool ok = false;
  inner.polygons = polygons_of_faces(options.polygons, flat.faces);
  try {
    flat.param = parameterize_one_component(piece, inner);
    ok = usable(flat.param, options);
  } catch (const Error&) {
    ok = false;
  }
  if (!ok) return false;
  const UntangleOptions untangle;  // the boundary (u = 0, the seams) stays
  UntangleResult u = untangle_layout(flat.param.mesh, flat.param.cut_mesh.triangles,
                                     flat.param.layout.uv, untangle);
  flat.param.layout.uv = std::move(u.uv);
  u.uv.resize(0, 2);
  out.untangle.flipped_before += u.flipped_before;
  out.untangle.moved_vertices += u.moved_vertices;
  out.untangle.region_faces += u.region_faces;
  out.untangle.rounds += u.rounds;
  out.untangle.newton_iterations += u.newton_iterations;
  out.untangle.seconds += u.seconds;
  flipped = faces_to_take_out(flat.param);
  return true;
}

/// Marks the flipped faces of a flat unfolded, with the rest of each polygon they belong to.
void take_out(const Flat& flat, const std::vector<int>& flipped, const Polygons& polygons,
              std::vector<char>& unfolded) {
  for (int f : flipped) unfolded[flat.faces[f]] = 1;
  for (std::size_t i = 0; i < flat.faces.size() && !polygons.empty(); ++i) {
    for (int f : flipped) {
      if (polygons.triangle_polygon[flat.faces[i]] == polygons.triangle_polygon[flat.faces[f]]) {
        unfolded[flat.faces[i]] = 1;
      }
    }
  }
}

/// The disk flattened in rounds (at most kRounds): each round flattens every connected piece of
/// the faces not yet taken out, except those unchanged since the last round, which keep their
/// flattening. Returns the flats of the last round; `unfolded` marks the faces taken out (the
/// flats' flipped faces, pieces that failed or still fold in the last round, and faces no flat
/// holds at the end).
std::vector<Flat> flatten_in_rounds(const Mesh& disk, const ParamOptions& options,
                                    std::vector<char>& unfolded, ChartsLayout& out) {
  const int nf = disk.num_faces();
  ParamOptions inner = piece_options(options);
  unfolded.assign(nf, 0);
  std::vector<Flat> flats;
  // The flat that holds each face (-1: none yet, or taken out), so that a piece whose faces did
  // not change keeps its flattening.
  std::vector<int> owner(nf, -1);
  for (int round = 0; round < kRounds; ++round) {
    std::vector<int> remaining;
    for (int f = 0; f < nf; ++f) {
      if (!unfolded[f]) remaining.push_back(f);
    }
    if (remaining.empty()) break;
    // The remaining faces as a mesh of their own.
    std::vector<int> disk_vertex;
    const Mesh rest = faces_as_mesh(disk, remaining, disk_vertex);
    const Topology rest_topology = build_topology(rest.triangles, rest.num_vertices());
    const std::vector<Submesh> pieces = split_components(rest, rest_topology);
    std::vector<Flat> next;
    std::vector<int> next_owner(nf, -1);
    bool changed = false;
    for (const Submesh& piece : pieces) {
      Flat flat;
      for (int f : piece.face_map) flat.faces.push_back(remaining[f]);
      for (int v : piece.vertex_map) flat.vertices.push_back(disk_vertex[v]);
      // Unchanged since the last round: kept as it is.
      const int before = owner[flat.faces.front()];
      if (before >= 0 && flats[before].faces.size() == flat.faces.size() &&
          std::all_of(flat.faces.begin(), flat.faces.end(),
                      [&](int f) { return owner[f] == before; })) {
        for (int f : flat.faces) next_owner[f] = static_cast<int>(next.size());
        next.push_back(std::move(flats[before]));
        continue;
      }
      ++out.rounds;
      std::vector<int> flipped;
      const bool ok = flatten_piece(piece.mesh, options, inner, flat, flipped, out);
      // A piece that failed, or that still folds in the last round, is laid out in its own
      // shape; otherwise its folded faces are, and it is flattened again next round.
      if (!ok || (!flipped.empty() && round == kRounds - 1)) {
        for (int f : flat.faces) unfolded[f] = 1;
        changed = true;
        continue;
      }
      if (!flipped.empty()) {
        take_out(flat, flipped, options.polygons, unfolded);
        changed = true;
        continue;
      }
      for (int f : flat.faces) next_owner[f] = static_cast<int>(next.size());
      next.push_back(std::move(flat));
    }
    flats = std::move(next);
    owner = std::move(next_owner);
    if (!changed) break;
  }
  // Faces never placed by a flat (the last round's taken-out pieces) are unfolded too.
  for (int f = 0; f < nf; ++f) {
    if (owner[f] < 0) unfolded[f] = 1;
  }
  return flats;
}

/// Every chart's layout vertices in one array, with the disk vertex each copies, and per face of
/// the disk its corners' indices into the array.
struct ChartVertices {
  std::vector<Eigen::RowVector2d> positions;
  std::vector<int> disk_vertex;
  Triangles corners;
};

/// Adds the flats' layouts to `vertices` as charts from `charts` on (a flat that overlaps itself
/// split into pieces that do not), writing out.face_chart of their faces. Returns the next chart.
int add_flat_charts(const std::vector<Flat>& flats, const Polygons& polygons, int charts,
                    ChartVertices& vertices, ChartsLayout& out) {
  for (const Flat& flat : flats) {
    const ParamResult& p = flat.param;
    const int offset = static_cast<int>(vertices.positions.size());
    for (Eigen::Index v = 0; v < p.layout.uv.rows(); ++v) {
      vertices.positions.emplace_back(p.layout.uv.row(v));
      vertices.disk_vertex.push_back(flat.vertices[p.cut_mesh.to_original[v]]);
    }
    int count = 1;
    std::vector<int> piece_of(flat.faces.size(), 0);
    if (find_uv_overlaps(p.layout.uv, p.cut_mesh.triangles, {}, 0).count > 0) {
      piece_of = embedded_pieces(p.layout.uv, p.cut_mesh.triangles, count,
                                 polygons_of_faces(polygons, flat.faces).triangle_polygon);
    }
    for (std::size_t i = 0; i < flat.faces.size(); ++i) {
      const int f = flat.faces[i];
      out.face_chart[f] = charts + piece_of[i];
      for (int k = 0; k < 3; ++k)
        vertices.corners(f, k) = offset + p.cut_mesh.triangles(static_cast<Eigen::Index>(i), k);
    }
    charts += count;
  }
  return charts;
}

/// Adds the faces taken out (unfolded), laid out in patches of their own 3D shape, to `vertices`
/// as charts from `charts` on, writing out.face_chart and out.unfolded_faces. Returns the next
/// chart.
int add_unfolded_charts(const Mesh& disk, const std::vector<char>& unfolded,
                        const Polygons& polygons, int charts, ChartVertices& vertices,
                        ChartsLayout& out) {
  std::vector<int> taken;
  for (int f = 0; f < disk.num_faces(); ++f) {
    if (unfolded[f]) taken.push_back(f);
  }
  out.unfolded_faces = static_cast<int>(taken.size());
  if (taken.empty()) return charts;
  std::vector<int> loose_disk_vertex;
  const Mesh loose = faces_as_mesh(disk, taken, loose_disk_vertex);
  const PatchLayout patches = develop_patches(loose, polygons_of_faces(polygons, taken));
  const int offset = static_cast<int>(vertices.positions.size());
  for (Eigen::Index v = 0; v < patches.layout.rows(); ++v) {
    vertices.positions.emplace_back(patches.layout.row(v));
    vertices.disk_vertex.push_back(loose_disk_vertex[patches.vertex[v]]);
  }
  for (std::size_t i = 0; i < taken.size(); ++i) {
    out.face_chart[taken[i]] = charts + patches.face_patch[i];
    for (int k = 0; k < 3; ++k)
      vertices.corners(taken[i], k) = offset + patches.triangles(static_cast<Eigen::Index>(i), k);
  }
  return charts + patches.num_patches;
}

}  // namespace

ChartsLayout lay_out_charts(const Mesh& mesh, const ParamOptions& options,
                            const std::vector<int>& cut_through) {
  ChartsLayout out;
  const int nf = mesh.num_faces();
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd lengths = input_edge_lengths(mesh, t);
  // A polygon mesh's polygons stay whole: no cut along a diagonal, and a polygon leaves a chart
  // or joins a piece or a patch with all its triangles.
  const Polygons& polygons = options.polygons;
  const CutMesh sliced = cut_open(t, lengths, polygons, cut_through, out.cut_vertices);
  Mesh disk;
  disk.triangles = sliced.triangles;
  disk.positions.resize(static_cast<Eigen::Index>(sliced.to_original.size()), 3);
  for (std::size_t v = 0; v < sliced.to_original.size(); ++v) {
    disk.positions.row(static_cast<Eigen::Index>(v)) = mesh.positions.row(sliced.to_original[v]);
  }
  std::vector<char> unfolded;
  const std::vector<Flat> flats = flatten_in_rounds(disk, options, unfolded, out);

  // Every chart's layout vertices in one array: the flats' (split where a flat overlaps itself)
  // and the unfolded faces' patches (edge-connected groups laid out in their 3D shape).
  ChartVertices vertices;
  vertices.corners.resize(nf, 3);
  out.face_chart.assign(nf, -1);
  out.flow_charts = add_flat_charts(flats, polygons, 0, vertices, out);
  out.num_charts = add_unfolded_charts(disk, unfolded, polygons, out.flow_charts, vertices, out);
  // One vertex per fan of each chart.
  const std::vector<int> source = split_at_charts(
      vertices.corners, static_cast<int>(vertices.positions.size()), out.face_chart);
  out.triangles = std::move(vertices.corners);
  out.vertex.resize(source.size());
  out.layout.resize(static_cast<Eigen::Index>(source.size()), 2);
  for (std::size_t v = 0; v < source.size(); ++v) {
    out.vertex[v] = sliced.to_original[vertices.disk_vertex[source[v]]];
    out.layout.row(static_cast<Eigen::Index>(v)) = vertices.positions[source[v]];
  }
  out.message = std::to_string(out.num_charts) + " charts (" + std::to_string(out.flow_charts) +
                " flattened with free boundary, " + std::to_string(out.unfolded_faces) +
                " faces in their own shape)";
  return out;
}

ParamResult charts_result(const Mesh& mesh, const ChartsLayout& charts, const Polygons& polygons) {
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  ParamResult r = own_layout_result(mesh, t, input_edge_lengths(mesh, t), charts.triangles,
                                    charts.vertex, charts.layout, polygons);
  r.untangle = charts.untangle;
  return r;
}

}  // namespace ricci::param_detail
