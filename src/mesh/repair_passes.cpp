/// \file
/// The repair passes of mesh/detail/repair_passes.hpp: the weld, duplicate faces, the pairing of
/// faces around an edge, and the split and orientation of a non-manifold soup into a manifold.
/// repair_mesh (repair.cpp) runs them in order.
#include "mesh/detail/repair_passes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "mesh/detail/corner_fans.hpp"
#include "mesh/detail/edge_name.hpp"
#include "mesh/detail/face_keys.hpp"
#include "mesh/detail/orientation.hpp"
#include "mesh/detail/slivers.hpp"
#include "ricci/errors.hpp"
#include "ricci/numerics/disjoint_sets.hpp"

namespace ricci {
namespace {

// The module's shared helpers (edge names, corner fans, the orientation search, face keys).
using namespace mesh_detail;

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

/// Union-find that also keeps each element's parity (flipped or not) relative to its root: the
/// faces joined so far, and which of them must be reversed relative to each other.
class ParitySets {
 public:
  explicit ParitySets(int n) : parent_(n), parity_(n, 0) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  /// Root of x and the parity of x relative to it.
  std::pair<int, int> find(int x) {
    int root = x, parity = 0;
    while (parent_[root] != root) {
      parity ^= parity_[root];
      root = parent_[root];
    }
    for (int at = x, at_parity = parity; parent_[at] != root && at != root;) {
      const int next = parent_[at], next_parity = at_parity ^ parity_[at];
      parent_[at] = root;
      parity_[at] = static_cast<char>(at_parity);
      at = next;
      at_parity = next_parity;
    }
    return {root, parity};
  }
  /// Records that the parities of a and b differ by `relation` (1: one of them is reversed);
  /// false, recording nothing, when that contradicts what is known.
  bool unite(int a, int b, int relation) {
    auto [root_a, parity_a] = find(a);
    auto [root_b, parity_b] = find(b);
    if (root_a == root_b) return (parity_a ^ parity_b) == relation;
    if (root_a > root_b) std::swap(root_a, root_b);
    parent_[root_b] = root_a;
    parity_[root_b] = static_cast<char>(parity_a ^ parity_b ^ relation);
    return true;
  }

 private:
  std::vector<int> parent_;
  std::vector<char> parity_;
};

/// Halfedges sorted by an undirected edge key: pairs (key, halfedge).
using KeyedHalfedges = std::vector<std::pair<std::uint64_t, int>>;

/// Calls run(i, j) for each run [i, j) of equal keys in `keyed` (the halfedges of one edge).
template <typename Run>
void for_each_edge(const KeyedHalfedges& keyed, const Run& run) {
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i + 1;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    run(i, j);
    i = j;
  }
}

/// The kept faces of the welded triangles seen as corners and halfedges: corner c = 3 i + k is
/// corner k of face kept[i] of T, halfedge h = 3 i + k lies opposite it.
struct KeptFaces {
  const Triangles& T;
  const std::vector<int>& kept;

  int num_faces() const { return static_cast<int>(kept.size()); }
  int corner_vertex(int c) const { return T(kept[c / 3], c % 3); }
  int tail(int h) const { return T(kept[h / 3], (h % 3 + 1) % 3); }
  int head(int h) const { return T(kept[h / 3], (h % 3 + 2) % 3); }
};

/// Two kept faces joined across an edge, by their halfedges there.
struct Glue {
  int h, g;
  int group;  // index of the edge among the non-manifold ones, -1 for a two-faced edge
};

/// Which faces stay joined across each edge, and the non-manifold edges (by vertex, ascending).
struct Gluing {
  std::vector<Glue> glue;
  std::vector<std::array<int, 2>> non_manifold_edges;
};

/// (3) Which faces stay joined across each edge: both faces of a two-faced edge; around an edge
/// with more faces, the pairs that bound one wedge of space (or all of them, when splitting is
/// off, which leaves the edge as it was).
Gluing glue_across_edges(const Positions& P, const KeptFaces& faces, bool split_non_manifold) {
  const int nh = 3 * faces.num_faces();
  KeyedHalfedges keyed;
  keyed.reserve(nh);
  for (int h = 0; h < nh; ++h) keyed.emplace_back(edge_key(faces.tail(h), faces.head(h)), h);
  std::sort(keyed.begin(), keyed.end());
  Gluing out;
  out.glue.reserve(nh / 2);
  for_each_edge(keyed, [&](std::size_t i, std::size_t j) {
    if (j - i == 2) {
      out.glue.push_back({keyed[i].second, keyed[i + 1].second, -1});
    } else if (j - i > 2) {
      const int a = static_cast<int>(keyed[i].first >> 32);
      const int b = static_cast<int>(keyed[i].first & 0xffffffffu);
      const int group = static_cast<int>(out.non_manifold_edges.size());
      out.non_manifold_edges.push_back({a, b});
      std::vector<int> halfedges;
      for (std::size_t m = i; m < j; ++m) halfedges.push_back(keyed[m].second);
      if (split_non_manifold) {
        for (const auto& [h, g] : pair_around_edge(P, faces.T, faces.kept, halfedges, a, b)) {
          out.glue.push_back({h, g, group});
        }
      } else {
        for (std::size_t m = 1; m < halfedges.size(); ++m) {
          out.glue.push_back({halfedges[0], halfedges[m], group});
        }
      }
    }
  });
  return out;
}

/// The output vertices: corner_output[c] for each corner, vertex_map[o] the (welded) input
/// vertex that output vertex o copies.
struct VertexCopies {
  std::vector<int> corner_output;
  std::vector<int> vertex_map;
};

/// Vertex copies: the corners at a vertex joined across the active glue form its fans (without
/// splitting, all corners at a vertex form one); each fan becomes one output vertex. Primary
/// copies (the fan of a vertex's first corner) keep the input order, extra copies follow, so
/// that a mesh without defects keeps its numbering.
VertexCopies make_vertex_copies(const KeptFaces& faces, const Gluing& gluing,
                                const std::vector<char>& glue_active, int nv,
                                bool split_non_manifold) {
  const int nh = 3 * faces.num_faces();
  auto tail = [&](int h) { return faces.tail(h); };
  auto head = [&](int h) { return faces.head(h); };
  DisjointSets fans(nh);
  if (split_non_manifold) {
    for (std::size_t i = 0; i < gluing.glue.size(); ++i) {
      if (!glue_active[i]) continue;
      unite_fans_across(fans, gluing.glue[i].h, gluing.glue[i].g, tail, head);
    }
  } else {
    std::vector<int> first_corner(nv, -1);
    for (int c = 0; c < nh; ++c) {
      int& first = first_corner[faces.corner_vertex(c)];
      if (first < 0) {
        first = c;
      } else {
        fans.unite(first, c);
      }
    }
  }
  std::vector<int> root_output(nh, -1);
  std::vector<char> has_primary(nv, 0);
  std::vector<int> extra_roots;  // roots of extra copies, in order of their first corner
  std::vector<int> primary_roots(nv, -1);
  for (int c = 0; c < nh; ++c) {
    const int root = fans.find(c);
    if (root != c) continue;  // roots are the smallest corner of their fan
    const int v = faces.corner_vertex(c);
    if (!has_primary[v]) {
      has_primary[v] = 1;
      primary_roots[v] = root;
    } else {
      extra_roots.push_back(root);
    }
  }
  VertexCopies out;
  for (int v = 0; v < nv; ++v) {
    if (!has_primary[v]) continue;
    root_output[primary_roots[v]] = static_cast<int>(out.vertex_map.size());
    out.vertex_map.push_back(v);
  }
  std::stable_sort(extra_roots.begin(), extra_roots.end(),
                   [&](int x, int y) { return faces.corner_vertex(x) < faces.corner_vertex(y); });
  for (int root : extra_roots) {
    root_output[root] = static_cast<int>(out.vertex_map.size());
    out.vertex_map.push_back(faces.corner_vertex(root));
  }
  out.corner_output.resize(nh);
  for (int c = 0; c < nh; ++c) out.corner_output[c] = root_output[fans.find(c)];
  return out;
}

/// The halfedges keyed by the output vertices at their ends, sorted.
KeyedHalfedges output_edge_keys(const std::vector<int>& corner_output) {
  const int nh = static_cast<int>(corner_output.size());
  KeyedHalfedges keyed;
  keyed.reserve(nh);
  for (int h = 0; h < nh; ++h) {
    keyed.emplace_back(edge_key(corner_output[next_corner(h)], corner_output[prev_corner(h)]), h);
  }
  std::sort(keyed.begin(), keyed.end());
  return keyed;
}

/// What detach_crowded_edges did.
enum class Crowding {
  None,      ///< no copy of an edge has more than two faces
  Detached,  ///< some had: their faces are now detached there
  Stuck,     ///< some had, and nothing was left to detach (cannot happen; never loop for ever)
};

/// A pairing can still leave three faces on the copies of an edge (when fans around its ends
/// close up through other edges); the faces of such an edge are then all detached there, which
/// leaves each of its copies the two ends of a fan at most, and the copies are made again.
Crowding detach_crowded_edges(const KeptFaces& faces, const KeyedHalfedges& output_keyed,
                              const Gluing& gluing, std::vector<char>& glue_active) {
  std::vector<std::uint64_t> crowded;  // input edges whose copies still have > 2 faces
  for_each_edge(output_keyed, [&](std::size_t i, std::size_t j) {
    if (j - i > 2) {
      const int h = output_keyed[i].second;
      crowded.push_back(edge_key(faces.tail(h), faces.head(h)));
    }
  });
  if (crowded.empty()) return Crowding::None;
  std::sort(crowded.begin(), crowded.end());
  bool detached = false;
  for (std::size_t i = 0; i < gluing.glue.size(); ++i) {
    const int h = gluing.glue[i].h;
    if (glue_active[i] && gluing.glue[i].group >= 0 &&
        std::binary_search(crowded.begin(), crowded.end(),
                           edge_key(faces.tail(h), faces.head(h)))) {
      glue_active[i] = 0;
      detached = true;
    }
  }
  return detached ? Crowding::Detached : Crowding::Stuck;
}

/// Pairs made at non-manifold edges, and the edges that fans closing up made between faces
/// detached there, must not make the orientation contradict itself where the two-faced edges of
/// the input do not: such a surface would be non-orientable by the repair's own choice. The
/// faces' relative orientations are fixed across the input's two-faced edges first; a pair that
/// contradicts them is detached, and a closed-up edge that does detaches the pairs at its ends.
/// \param glue_of #H: the glue entry of each halfedge (one at most when splitting), or -1
/// \return whether any pair was detached
bool detach_contradicting_pairs(const KeptFaces& faces, const KeyedHalfedges& output_keyed,
                                const std::vector<int>& corner_output, const Gluing& gluing,
                                const std::vector<int>& glue_of, std::vector<char>& glue_active,
                                int nv) {
  const std::vector<Glue>& glue = gluing.glue;
  auto out_tail = [&](int h) { return corner_output[next_corner(h)]; };
  ParitySets sides(faces.num_faces());
  std::vector<std::pair<int, int>> paired, closed_up;  // (h, g)
  for_each_edge(output_keyed, [&](std::size_t i, std::size_t j) {
    if (j - i != 2) return;
    const int h = output_keyed[i].second, g = output_keyed[i + 1].second;
    const int entry = glue_of[h];
    if (entry >= 0 && glue_of[g] == entry && glue_active[entry]) {
      if (glue[entry].group < 0) {
        sides.unite(h / 3, g / 3, out_tail(h) == out_tail(g) ? 1 : 0);
      } else {
        paired.emplace_back(h, g);
      }
    } else {
      closed_up.emplace_back(h, g);
    }
  });
  bool detached = false;
  for (const auto& [h, g] : paired) {
    if (!sides.unite(h / 3, g / 3, out_tail(h) == out_tail(g) ? 1 : 0)) {
      glue_active[glue_of[h]] = 0;
      detached = true;
    }
  }
  std::vector<char> end_of_contradiction(nv, 0);
  bool contradiction = false;
  for (const auto& [h, g] : closed_up) {
    if (!sides.unite(h / 3, g / 3, out_tail(h) == out_tail(g) ? 1 : 0)) {
      end_of_contradiction[faces.tail(h)] = end_of_contradiction[faces.head(h)] = 1;
      contradiction = true;
    }
  }
  if (contradiction) {
    for (std::size_t i = 0; i < glue.size(); ++i) {
      if (glue_active[i] && glue[i].group >= 0 &&
          (end_of_contradiction[faces.tail(glue[i].h)] ||
           end_of_contradiction[faces.head(glue[i].h)])) {
        glue_active[i] = 0;
        detached = true;
      }
    }
  }
  return detached;
}

/// (4) Orientation: breadth-first search across the output's two-faced edges gives each face a
/// flip bit such that neighbours traverse their edge in opposite directions; in each component
/// the side with fewer faces is reversed. A contradiction means no orientation exists: the
/// component is left as it was and its seed appended to non_orientable.
std::vector<signed char> orient_faces(const KeyedHalfedges& output_keyed,
                                      const std::vector<int>& corner_output,
                                      std::vector<int>& non_orientable) {
  const int nh = static_cast<int>(corner_output.size());
  auto out_tail = [&](int h) { return corner_output[next_corner(h)]; };
  std::vector<signed char> flip(nh / 3, 0);
  std::vector<int> twin(nh, -1);
  for_each_edge(output_keyed, [&](std::size_t i, std::size_t j) {
    if (j - i == 2) {
      twin[output_keyed[i].second] = output_keyed[i + 1].second;
      twin[output_keyed[i + 1].second] = output_keyed[i].second;
    }
  });
  const OrientationSearch search = search_orientation(twin, out_tail, [](int) { return true; });
  for (const OrientationComponent& component : search.components) {
    if (component.conflict >= 0) {
      non_orientable.push_back(component.seed);
      continue;
    }
    for (int i = component.begin; i < component.end; ++i) {
      const int f = search.order[i];
      flip[f] = static_cast<signed char>(search.side[f] == component.minority());
    }
  }
  return flip;
}

}  // namespace

namespace mesh_detail {

std::vector<int> weld(const Positions& P, const std::vector<char>& referenced, double tolerance) {
  const int nv = static_cast<int>(P.rows());
  std::vector<int> representative(nv);
  std::iota(representative.begin(), representative.end(), 0);
  std::vector<int> candidates;
  candidates.reserve(nv);
  for (int v = 0; v < nv; ++v) {
    if (referenced[v] && P.row(v).allFinite()) candidates.push_back(v);
  }
  if (candidates.empty()) return representative;

  Eigen::RowVector3d lo = P.row(candidates[0]), hi = lo;
  for (int v : candidates) {
    lo = lo.cwiseMin(P.row(v));
    hi = hi.cwiseMax(P.row(v));
  }
  const double radius = tolerance * (hi - lo).norm();
  if (radius == 0) {
    // Exact: equal positions are neighbours in lexicographic order; the smallest index of a run
    // comes first, so it becomes the representative.
    auto less = [&](int a, int b) {
      for (int k = 0; k < 3; ++k) {
        if (P(a, k) != P(b, k)) return P(a, k) < P(b, k);
      }
      return a < b;
    };
    std::sort(candidates.begin(), candidates.end(), less);
    for (std::size_t i = 1, first = 0; i < candidates.size(); ++i) {
      if (P.row(candidates[i]) == P.row(candidates[first])) {
        representative[candidates[i]] = candidates[first];
      } else {
        first = i;
      }
    }
    return representative;
  }

  // Within a radius: a grid of cells one radius wide, each vertex compared with the vertices of
  // the 27 cells around it; union-find makes the welding transitive. Cell coordinates stay below
  // 1 / weld_tolerance (at most 1e15: repair_mesh rejects tolerances below kMinWeldTolerance),
  // so they fit in 64 bits.
  auto cell_of = [&](int v) {
    std::array<std::int64_t, 3> cell;
    for (int k = 0; k < 3; ++k) {
      cell[k] = static_cast<std::int64_t>(std::floor((P(v, k) - lo[k]) / radius));
    }
    return cell;
  };
  struct CellHash {
    std::size_t operator()(const std::array<std::int64_t, 3>& c) const {
      std::uint64_t h = 1469598103934665603ull;
      for (std::int64_t x : c) h = (h ^ static_cast<std::uint64_t>(x)) * 1099511628211ull;
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<int>, CellHash> cells;
  cells.reserve(candidates.size());
  for (int v : candidates) cells[cell_of(v)].push_back(v);
  DisjointSets sets(nv);
  const double radius_squared = radius * radius;
  for (int v : candidates) {
    const auto cell = cell_of(v);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto found = cells.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
          if (found == cells.end()) continue;
          for (int w : found->second) {
            if (w < v && (P.row(v) - P.row(w)).squaredNorm() <= radius_squared) sets.unite(v, w);
          }
        }
      }
    }
  }
  for (int v : candidates) representative[v] = sets.find(v);  // the smallest index is the root
  return representative;
}

/// Pairs the faces around a non-manifold edge that bound the same wedge of space. The faces are
/// sorted by the angle of their third vertex around the edge a -> b; a face that runs a -> b has
/// its normal towards increasing angle, so the wedge below it is inside the solid it bounds, and
/// it pairs with the face just below when that one runs b -> a. Faces left without a partner are
/// detached at this edge. Positions that give no angle (a zero-length edge, non-finite
/// coordinates) leave the faces in halfedge order; the caller checks the outcome anyway.
std::vector<std::pair<int, int>> pair_around_edge(const Positions& P, const Triangles& T,
                                                  const std::vector<int>& kept,
                                                  const std::vector<int>& halfedges, int a, int b) {
  struct Sheet {
    double angle;
    int h;
    bool forward;  // runs a -> b
  };
  const int k = static_cast<int>(halfedges.size());
  std::vector<Sheet> sheets(k);
  const Eigen::Vector3d pa = P.row(a).transpose(), pb = P.row(b).transpose();
  const Eigen::Vector3d axis = (pb - pa).normalized();
  Eigen::Vector3d u = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  for (int i = 0; i < k; ++i) {
    const int h = halfedges[i], f = kept[h / 3];
    const Eigen::Vector3d w = P.row(T(f, h % 3)).transpose() - pa;
    if (i == 0) {
      u = (w - axis * axis.dot(w)).normalized();
      v = axis.cross(u);
    }
    double angle = std::atan2(w.dot(v), w.dot(u));
    if (!std::isfinite(angle)) angle = 0;
    sheets[i] = {angle, h, T(f, (h % 3 + 1) % 3) == a};
  }
  std::sort(sheets.begin(), sheets.end(), [](const Sheet& x, const Sheet& y) {
    return x.angle != y.angle ? x.angle < y.angle : x.h < y.h;
  });
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < k; ++i) {
    const Sheet& below = sheets[(i + k - 1) % k];
    // A backward face is the face below exactly one face, so no face is paired twice.
    if (sheets[i].forward && !below.forward) pairs.emplace_back(below.h, sheets[i].h);
  }
  return pairs;
}

std::vector<int> find_duplicate_faces(const Triangles& T, const std::vector<char>& included) {
  std::vector<int> duplicate_of(T.rows(), -1);
  const std::vector<std::array<int, 4>> keyed =
      sorted_face_keys(T, [&](int f) { return included[f] != 0; });
  for (std::size_t i = 1, first = 0; i < keyed.size(); ++i) {
    if (std::equal(keyed[i].begin(), keyed[i].begin() + 3, keyed[first].begin())) {
      duplicate_of[keyed[i][3]] = keyed[first][3];
    } else {
      first = i;
    }
  }
  return duplicate_of;
}

Split split_and_orient(const Positions& P, const Triangles& T, const std::vector<int>& kept, int nv,
                       const RepairOptions& options) {
  const KeptFaces faces{T, kept};
  const int nh = 3 * faces.num_faces();
  Gluing gluing = glue_across_edges(P, faces, options.split_non_manifold);
  std::vector<char> glue_active(gluing.glue.size(), 1);
  std::vector<int> glue_of(nh, -1);  // the glue entry of each halfedge (one at most when split)
  for (std::size_t i = 0; i < gluing.glue.size(); ++i) {
    glue_of[gluing.glue[i].h] = glue_of[gluing.glue[i].g] = static_cast<int>(i);
  }
  // The copies are made again after every change to the glue, until none is needed.
  VertexCopies copies;
  KeyedHalfedges output_keyed;
  while (true) {
    copies = make_vertex_copies(faces, gluing, glue_active, nv, options.split_non_manifold);
    output_keyed = output_edge_keys(copies.corner_output);
    if (!options.split_non_manifold) break;
    const Crowding crowding = detach_crowded_edges(faces, output_keyed, gluing, glue_active);
    if (crowding == Crowding::Detached) continue;
    if (crowding == Crowding::Stuck) break;
    if (!options.orient || gluing.non_manifold_edges.empty()) break;
    if (!detach_contradicting_pairs(faces, output_keyed, copies.corner_output, gluing, glue_of,
                                    glue_active, nv)) {
      break;
    }
  }
  Split out;
  out.flip.assign(faces.num_faces(), 0);
  if (options.orient) {
    out.flip = orient_faces(output_keyed, copies.corner_output, out.non_orientable);
  }
  out.corner_output = std::move(copies.corner_output);
  out.vertex_map = std::move(copies.vertex_map);
  out.non_manifold_edges = std::move(gluing.non_manifold_edges);
  return out;
}

}  // namespace mesh_detail

}  // namespace ricci
