#include "ricci/mesh/repair.hpp"

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
#include "mesh/detail/repair_passes.hpp"
#include "mesh/detail/slivers.hpp"
#include "ricci/errors.hpp"
#include "ricci/numerics/disjoint_sets.hpp"

namespace ricci {
namespace {

// The module's shared helpers (edge names, corner fans, the orientation search, face keys,
// sliver removal, the repair passes).
using namespace mesh_detail;

void note(RepairCount& count, int element, int max_examples) {
  if (static_cast<int>(count.examples.size()) < max_examples) count.examples.push_back(element);
  ++count.count;
}

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

/// " (e.g. vertices 3, 9)"; empty without examples.
std::string examples_text(const std::vector<int>& examples, const char* one, const char* many) {
  if (examples.empty()) return "";
  std::string text = std::string(" (e.g. ") + (examples.size() > 1 ? many : one) + " ";
  for (std::size_t i = 0; i < examples.size(); ++i) {
    text += (i == 0 ? "" : ", ") + std::to_string(examples[i]);
  }
  return text + ")";
}

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

bool RepairReport::changed() const {
  return welded_vertices.count > 0 || repeated_vertex_faces_removed.count > 0 ||
         duplicate_faces_removed.count > 0 || slivers_removed.count > 0 || faces_split.count > 0 ||
         non_manifold_edges_split > 0 || non_manifold_vertices_split.count > 0 ||
         faces_flipped.count > 0 || unreferenced_vertices_dropped.count > 0 ||
         smaller_components_removed.count > 0;
}

namespace {

/// The smallest weld tolerance other than 0. A radius below 1e-15 of the diagonal is below the
/// resolution of the coordinates themselves (double precision is 2.2e-16 relative), and above
/// it the weld grid's cell coordinates (below 1 / tolerance) stay well within 64 bits.
constexpr double kMinWeldTolerance = 1e-15;

/// Rounds of splitting again on the reversed faces (step 4); each must save vertex copies, and
/// four have sufficed for every mesh met so far.
constexpr int kMaxOrientRounds = 4;

/// Checks the options and the vertex indices (InvalidInput otherwise); #V: 1 for the vertices
/// some face uses.
std::vector<char> check_repair_input(const Mesh& mesh, const RepairOptions& options) {
  const int nv = mesh.num_vertices();
  const int nf = mesh.num_faces();
  const double tolerance = options.weld_tolerance;
  if (!std::isfinite(tolerance) || tolerance < 0 ||
      (tolerance > 0 && tolerance < kMinWeldTolerance)) {
    throw InvalidInput("repair_mesh: weld_tolerance " + std::to_string(tolerance) +
                       " must be 0 (exact positions) or at least 1e-15 (relative to the "
                       "bounding-box diagonal)");
  }
  if (!(options.zero_area_tolerance >= 0 && options.zero_area_tolerance < 1)) {
    throw InvalidInput("repair_mesh: zero_area_tolerance " +
                       std::to_string(options.zero_area_tolerance) + " must be in [0, 1)");
  }
  std::vector<char> referenced(nv, 0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k);
      if (v < 0 || v >= nv) {
        throw InvalidInput("repair_mesh: face " + std::to_string(f) + " uses vertex " +
                           std::to_string(v) + ", outside [0, " + std::to_string(nv) + ")");
      }
      referenced[v] = 1;
    }
  }
  return referenced;
}

/// (1) Welding, noted in the report: the representative of each input vertex (itself when it
/// was not welded, or when welding is off).
std::vector<int> weld_step(const Mesh& mesh, const std::vector<char>& referenced,
                           const RepairOptions& options, int max_examples, RepairReport& report) {
  const int nv = mesh.num_vertices();
  std::vector<int> representative(nv);
  std::iota(representative.begin(), representative.end(), 0);
  if (options.weld_vertices) {
    representative = weld(mesh.positions, referenced, options.weld_tolerance);
  }
  for (int v = 0; v < nv; ++v) {
    if (representative[v] != v) note(report.welded_vertices, v, max_examples);
  }
  return representative;
}

/// The faces on the welded vertices.
Triangles welded_triangles(const Triangles& triangles, const std::vector<int>& representative) {
  Triangles T(triangles.rows(), 3);
  for (int f = 0; f < static_cast<int>(triangles.rows()); ++f) {
    for (int k = 0; k < 3; ++k) T(f, k) = representative[triangles(f, k)];
  }
  return T;
}

/// What step (2) keeps: keep[f] is 0 for the faces removed; duplicate_of as
/// find_duplicate_faces gives it, for the report's example.
struct FaceDrops {
  std::vector<char> keep;
  std::vector<int> duplicate_of;
};

/// (2) Faces that use a vertex twice, then faces with the vertex set of an earlier face; noted
/// in the report.
FaceDrops drop_faces(const Triangles& T, int max_examples, RepairReport& report) {
  const int nf = static_cast<int>(T.rows());
  FaceDrops out;
  out.keep.assign(nf, 1);
  for (int f = 0; f < nf; ++f) {
    if (T(f, 0) != T(f, 1) && T(f, 1) != T(f, 2) && T(f, 0) != T(f, 2)) continue;
    out.keep[f] = 0;
    note(report.repeated_vertex_faces_removed, f, max_examples);
  }
  out.duplicate_of = find_duplicate_faces(T, out.keep);
  for (int f = 0; f < nf; ++f) {
    if (out.duplicate_of[f] < 0) continue;
    out.keep[f] = 0;
    note(report.duplicate_faces_removed, f, max_examples);
  }
  return out;
}

/// The faces that steps (3) to (5) take: the kept faces in input order, then (2b) with slivers
/// removed; source[i] is the input face of row i, piece[i] whether it is a piece of it.
struct WorkFaces {
  Triangles triangles;
  std::vector<int> source;
  std::vector<char> piece;
  std::string sliver_left_example;  ///< why the first zero-area face left was left
};

/// The kept faces of the welded triangles T, then (2b) the slivers removed (with
/// options.remove_slivers), noted in the report.
WorkFaces remove_sliver_step(const Positions& P, const Triangles& T, const std::vector<char>& keep,
                             const RepairOptions& options, int max_examples, RepairReport& report) {
  WorkFaces work;
  work.triangles.resize(std::count(keep.begin(), keep.end(), 1), 3);
  work.source.reserve(work.triangles.rows());
  for (int f = 0; f < static_cast<int>(T.rows()); ++f) {
    if (!keep[f]) continue;
    work.triangles.row(static_cast<Eigen::Index>(work.source.size())) = T.row(f);
    work.source.push_back(f);
  }
  work.piece.assign(work.source.size(), 0);
  if (!options.remove_slivers) return work;
  const std::vector<int>& source = work.source;
  SliverRemoval slivers = remove_slivers(P, work.triangles, options.zero_area_tolerance);
  for (std::size_t i = 0; i < slivers.removed.size(); ++i) {
    note(report.slivers_removed, source[slivers.removed[i]], max_examples);
    report.boundary_slivers_removed += slivers.on_boundary[i];
  }
  for (int row : slivers.split) note(report.faces_split, source[row], max_examples);
  for (std::size_t i = 0; i < slivers.left.size(); ++i) {
    // Counted per face; the pieces of one input face are one example.
    if (i == 0) work.sliver_left_example = sliver_left_reason(slivers.left_why[i]);
    RepairCount& left = report.zero_area_faces_left;
    if (i > 0 && slivers.left[i] == slivers.left[i - 1]) {
      ++left.count;
    } else {
      note(left, source[slivers.left[i]], max_examples);
    }
  }
  if (slivers.changed) {
    for (int& row : slivers.origin) row = source[row];
    work.triangles = std::move(slivers.triangles);
    work.source = std::move(slivers.origin);
    work.piece = std::move(slivers.piece);
  }
  return work;
}

/// The outcome of steps (3) and (4): the last split, and the faces reversed before it
/// (reversed[i] relative to the work faces; split.flip relative to those reversed ones).
struct OrientedSplit {
  Split split;
  std::vector<signed char> reversed;
};

/// (3) and (4). A non-manifold edge whose faces all run the same way has no pair to keep until
/// the orientation is fixed; so split again on the reversed faces while that saves copies.
OrientedSplit split_and_orient_rounds(const Positions& P, const Triangles& work, int nv,
                                      const RepairOptions& options) {
  const int nk = static_cast<int>(work.rows());
  std::vector<int> kept(nk);  // the rows of `work` that steps (3) to (5) take: all of them
  std::iota(kept.begin(), kept.end(), 0);
  Triangles oriented = work;  // work with the faces reversed so far
  OrientedSplit out;
  out.reversed.assign(nk, 0);
  Split& split = out.split;
  split = split_and_orient(P, oriented, kept, nv, options);
  for (int round = 0;
       round < kMaxOrientRounds && options.split_non_manifold && options.orient &&
       !split.non_manifold_edges.empty() && std::count(split.flip.begin(), split.flip.end(), 1) > 0;
       ++round) {
    Triangles next_oriented = oriented;
    for (int i = 0; i < nk; ++i) {
      if (split.flip[i]) std::swap(next_oriented(kept[i], 1), next_oriented(kept[i], 2));
    }
    Split next = split_and_orient(P, next_oriented, kept, nv, options);
    if (next.vertex_map.size() >= split.vertex_map.size() ||
        next.non_orientable.size() > split.non_orientable.size()) {
      break;
    }
    for (int i = 0; i < nk; ++i) out.reversed[i] ^= split.flip[i];
    oriented = std::move(next_oriented);
    split = std::move(next);
  }
  return out;
}

/// Notes steps (3) and (4) in the report: the non-manifold edges and vertices split, the
/// vertices no copy is left of, the non-orientable components and the faces reversed.
void note_split(const OrientedSplit& oriented, const std::vector<int>& representative,
                const std::vector<int>& source, const RepairOptions& options, int max_examples,
                RepairReport& report) {
  const Split& split = oriented.split;
  const int nv = static_cast<int>(representative.size());
  report.non_manifold_edges_split =
      options.split_non_manifold ? static_cast<int>(split.non_manifold_edges.size()) : 0;
  if (options.split_non_manifold) {
    for (std::size_t i = 0;
         i < split.non_manifold_edges.size() && static_cast<int>(i) < max_examples; ++i) {
      report.non_manifold_edge_examples.push_back(split.non_manifold_edges[i]);
    }
  }
  std::vector<int> copies(nv, 0);
  for (int v : split.vertex_map) ++copies[v];
  for (int v = 0; v < nv; ++v) {
    if (copies[v] > 1) note(report.non_manifold_vertices_split, v, max_examples);
    if (copies[v] == 0 && representative[v] == v) {
      note(report.unreferenced_vertices_dropped, v, max_examples);
    }
  }
  report.vertex_copies_added =
      static_cast<int>(split.vertex_map.size()) -
      static_cast<int>(std::count_if(copies.begin(), copies.end(), [](int n) { return n > 0; }));

  for (int i : split.non_orientable) {
    note(report.non_orientable_components, source[i], max_examples);
  }
  for (std::size_t i = 0; i < source.size(); ++i) {
    if (oriented.reversed[i] != split.flip[i]) {
      note(report.faces_flipped, source[i], max_examples);
    }
  }
}

/// (5) Which work faces go to the output: all of them, or with largest_component_only those of
/// the component with the most faces (the first on ties; the others noted in the report).
std::vector<char> output_faces(const Split& split, const std::vector<int>& source,
                               const RepairOptions& options, int max_examples,
                               RepairReport& report) {
  const int nk = static_cast<int>(source.size());
  std::vector<char> output_face(nk, 1);
  if (!options.largest_component_only || nk == 0) return output_face;
  const std::vector<int>& corner_output = split.corner_output;
  const int num_copies = static_cast<int>(split.vertex_map.size());
  DisjointSets parts(num_copies);
  for (int f = 0; f < nk; ++f) {
    parts.unite(corner_output[3 * f], corner_output[3 * f + 1]);
    parts.unite(corner_output[3 * f], corner_output[3 * f + 2]);
  }
  std::vector<int> faces_in(num_copies, 0), first_face(num_copies, -1);
  for (int f = 0; f < nk; ++f) {
    const int part = parts.find(corner_output[3 * f]);
    if (faces_in[part]++ == 0) first_face[part] = f;
  }
  int largest = parts.find(corner_output[0]);  // most faces; the first one on ties
  for (int f = 0; f < nk; ++f) {
    const int part = parts.find(corner_output[3 * f]);
    if (faces_in[part] > faces_in[largest]) largest = part;
  }
  for (int f = 0; f < nk; ++f) {
    const int part = parts.find(corner_output[3 * f]);
    if (part == largest) continue;
    output_face[f] = 0;
    ++report.smaller_component_faces_removed;
    if (first_face[part] == f) note(report.smaller_components_removed, source[f], max_examples);
  }
  return output_face;
}

/// (5) The output mesh and its maps. Unreferenced vertices are gone already: copies exist only
/// for corners; the copies of the faces removed go too.
void write_output(const Positions& P, const OrientedSplit& oriented, const WorkFaces& work,
                  const std::vector<char>& output_face, RepairResult& result) {
  const std::vector<int>& corner_output = oriented.split.corner_output;
  const std::vector<int>& vertex_map = oriented.split.vertex_map;
  const std::vector<signed char>& flip = oriented.split.flip;
  const int nk = static_cast<int>(work.source.size());
  std::vector<int> renumber(vertex_map.size(), -1);
  for (int f = 0; f < nk; ++f) {
    if (!output_face[f]) continue;
    for (int k = 0; k < 3; ++k) renumber[corner_output[3 * f + k]] = 0;
  }
  for (std::size_t v = 0; v < vertex_map.size(); ++v) {
    if (renumber[v] < 0) continue;
    renumber[v] = static_cast<int>(result.vertex_map.size());
    result.vertex_map.push_back(vertex_map[v]);
  }
  const int no = static_cast<int>(result.vertex_map.size());
  result.mesh.positions.resize(no, 3);
  for (int v = 0; v < no; ++v) result.mesh.positions.row(v) = P.row(result.vertex_map[v]);
  const int nout = static_cast<int>(std::count(output_face.begin(), output_face.end(), 1));
  result.mesh.triangles.resize(nout, 3);
  result.face_map.reserve(nout);
  result.face_flipped.reserve(nout);
  result.face_split.reserve(nout);
  for (int f = 0; f < nk; ++f) {
    if (!output_face[f]) continue;
    const int row = static_cast<int>(result.face_map.size());
    const int a = renumber[corner_output[3 * f]], b = renumber[corner_output[3 * f + 1]],
              c = renumber[corner_output[3 * f + 2]];
    if (flip[f]) {
      result.mesh.triangles.row(row) << a, c, b;
    } else {
      result.mesh.triangles.row(row) << a, b, c;
    }
    result.face_map.push_back(work.source[f]);
    result.face_flipped.push_back(oriented.reversed[f] != flip[f] ? 1 : 0);
    result.face_split.push_back(work.piece[f]);
  }
  result.report.output_vertices = no;
  result.report.output_faces = nout;
}

/// The report's lines for steps (1) and (2): welding, faces removed, slivers.
void removal_messages(const RepairOptions& options, const std::vector<int>& weld_map,
                      const std::vector<int>& duplicate_of, RepairReport& report) {
  std::vector<std::string>& out = report.messages;
  if (report.welded_vertices.count > 0) {
    const int v = report.welded_vertices.examples.empty() ? -1 : report.welded_vertices.examples[0];
    out.push_back("welded " + std::to_string(report.welded_vertices.count) +
                  " vertices onto earlier vertices at the same position" +
                  (options.weld_tolerance > 0 ? " (within the weld tolerance)" : std::string()) +
                  (v >= 0 ? " (e.g. vertex " + std::to_string(v) + " onto vertex " +
                                std::to_string(weld_map[v]) + ")"
                          : std::string()));
  }
  if (report.repeated_vertex_faces_removed.count > 0) {
    out.push_back("removed " + std::to_string(report.repeated_vertex_faces_removed.count) +
                  " faces that use a vertex twice" +
                  (report.welded_vertices.count > 0 ? " after welding" : "") +
                  examples_text(report.repeated_vertex_faces_removed.examples, "face", "faces"));
  }
  if (report.duplicate_faces_removed.count > 0) {
    const int f = report.duplicate_faces_removed.examples.empty()
                      ? -1
                      : report.duplicate_faces_removed.examples[0];
    out.push_back("removed " + std::to_string(report.duplicate_faces_removed.count) +
                  " duplicate faces" +
                  (f >= 0 ? " (e.g. face " + std::to_string(f) + ", the same vertices as face " +
                                std::to_string(duplicate_of[f]) + ")"
                          : std::string()));
  }
  if (report.slivers_removed.count > 0) {
    const int inside = report.slivers_removed.count - report.boundary_slivers_removed;
    std::string line = "removed " + std::to_string(report.slivers_removed.count) +
                       " zero-area faces with a vertex on their longest edge (slivers)" +
                       examples_text(report.slivers_removed.examples, "face", "faces") + ": ";
    if (inside > 0) {
      line += std::to_string(inside) + " by splitting the face across that edge at the vertex (" +
              std::to_string(report.faces_split.count) + " faces split" +
              examples_text(report.faces_split.examples, "face", "faces") +
              "; the surface is unchanged)";
    }
    if (report.boundary_slivers_removed > 0) {
      line += std::string(inside > 0 ? ", " : "") +
              std::to_string(report.boundary_slivers_removed) +
              " on the boundary (they cover nothing)";
    }
    out.push_back(line);
  }
}

/// The report's lines for steps (3) to (5), then one per defect left unrepaired.
void topology_messages(const std::string& sliver_left_example, RepairReport& report) {
  std::vector<std::string>& out = report.messages;
  if (report.non_manifold_edges_split > 0) {
    std::string line = "split " + std::to_string(report.non_manifold_edges_split) +
                       " non-manifold edges (more than two faces) into pairs of faces";
    if (!report.non_manifold_edge_examples.empty()) {
      line += " (e.g. edge " +
              edge_name(report.non_manifold_edge_examples[0][0],
                        report.non_manifold_edge_examples[0][1]) +
              ")";
    }
    out.push_back(line);
  }
  if (report.non_manifold_vertices_split.count > 0) {
    out.push_back("split " + std::to_string(report.non_manifold_vertices_split.count) +
                  " non-manifold vertices into one copy per fan of faces (" +
                  std::to_string(report.vertex_copies_added) + " copies added)" +
                  examples_text(report.non_manifold_vertices_split.examples, "vertex", "vertices"));
  }
  if (report.faces_flipped.count > 0) {
    out.push_back("reversed " + std::to_string(report.faces_flipped.count) +
                  " faces to orient their components consistently" +
                  examples_text(report.faces_flipped.examples, "face", "faces"));
  }
  if (report.unreferenced_vertices_dropped.count > 0) {
    out.push_back(
        "dropped " + std::to_string(report.unreferenced_vertices_dropped.count) +
        " unreferenced vertices" +
        examples_text(report.unreferenced_vertices_dropped.examples, "vertex", "vertices"));
  }
  if (report.smaller_components_removed.count > 0) {
    out.push_back("removed " + std::to_string(report.smaller_components_removed.count) +
                  " components smaller than the largest (" +
                  std::to_string(report.smaller_component_faces_removed) + " faces; " +
                  std::to_string(report.output_faces) + " faces kept)" +
                  examples_text(report.smaller_components_removed.examples, "the one with face",
                                "those with faces"));
  }
  if (report.non_orientable_components.count > 0) {
    out.push_back("not repaired: " + std::to_string(report.non_orientable_components.count) +
                  " non-orientable components (like a Moebius strip) cannot be oriented" +
                  examples_text(report.non_orientable_components.examples, "face", "faces"));
  }
  if (report.zero_area_faces_left.count > 0) {
    out.push_back("not repaired: " + std::to_string(report.zero_area_faces_left.count) +
                  " zero-area faces cannot be removed without changing the surface" +
                  examples_text(report.zero_area_faces_left.examples, "face", "faces") +
                  "; the first: " + sliver_left_example);
  }
}

}  // namespace

RepairResult repair_mesh(const Mesh& mesh, const RepairOptions& options) {
  const std::vector<char> referenced = check_repair_input(mesh, options);
  const int max_examples = std::max(options.max_examples, 0);
  RepairResult result;
  RepairReport& report = result.report;
  report.input_vertices = mesh.num_vertices();
  report.input_faces = mesh.num_faces();

  std::vector<int> representative = weld_step(mesh, referenced, options, max_examples, report);
  const Triangles T = welded_triangles(mesh.triangles, representative);
  const FaceDrops drops = drop_faces(T, max_examples, report);
  const WorkFaces work =
      remove_sliver_step(mesh.positions, T, drops.keep, options, max_examples, report);
  const OrientedSplit oriented =
      split_and_orient_rounds(mesh.positions, work.triangles, mesh.num_vertices(), options);
  note_split(oriented, representative, work.source, options, max_examples, report);
  const std::vector<char> output_face =
      output_faces(oriented.split, work.source, options, max_examples, report);
  write_output(mesh.positions, oriented, work, output_face, result);
  result.weld_map = std::move(representative);

  // Messages, in the order of the steps.
  removal_messages(options, result.weld_map, drops.duplicate_of, report);
  topology_messages(work.sliver_left_example, report);
  return result;
}

}  // namespace ricci
