#include "ricci/mesh/validate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>

#include <Eigen/Geometry>

#include "mesh/detail/corner_fans.hpp"
#include "mesh/detail/edge_name.hpp"
#include "mesh/detail/face_keys.hpp"
#include "mesh/detail/orientation.hpp"
#include "mesh/detail/zero_area.hpp"
#include "numerics/detail/bucket_sort.hpp"
#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"
#include "ricci/numerics/disjoint_sets.hpp"

namespace ricci {
namespace {

// The module's shared helpers (edge names, corner fans, the orientation search, face keys,
// the zero-area test).
using namespace mesh_detail;

constexpr int kNumKinds = static_cast<int>(DefectKind::UnreferencedVertex) + 1;

/// The order in which defects are checked and reported; throw_first_defect relies on it.
constexpr std::array<DefectKind, kNumKinds> kCheckOrder = {
    DefectKind::NonFiniteCoordinate,     DefectKind::IndexOutOfRange, DefectKind::RepeatedVertex,
    DefectKind::DuplicateFace,           DefectKind::NonManifoldEdge, DefectKind::NonManifoldVertex,
    DefectKind::InconsistentOrientation, DefectKind::NonOrientable,   DefectKind::ZeroAreaFace,
    DefectKind::UnreferencedVertex,
};

/// Collects defects, building a message only for the first max_defects_per_kind of each kind so
/// that a mesh with a million bad faces is still summarised quickly.
class DefectCollector {
 public:
  explicit DefectCollector(int max_per_kind) : max_per_kind_(max_per_kind) { counts_.fill(0); }

  template <class MessageFn>
  void add(DefectKind kind, int element, MessageFn&& message) {
    const int k = static_cast<int>(kind);
    if (counts_[k]++ < max_per_kind_) defects_.push_back({kind, element, message()});
  }

  /// Takes in the defects another collector found (of other kinds than this one's).
  void merge(DefectCollector&& other) {
    for (int k = 0; k < kNumKinds; ++k) counts_[k] += other.counts_[k];
    defects_.insert(defects_.end(), std::make_move_iterator(other.defects_.begin()),
                    std::make_move_iterator(other.defects_.end()));
  }

  ValidationReport finish() {
    ValidationReport report;
    report.defects = std::move(defects_);
    // The checks add their defects kind after kind, except that one search finds both
    // orientation kinds; a stable sort by rank restores the check order within each kind's order.
    std::stable_sort(report.defects.begin(), report.defects.end(),
                     [](const Defect& a, const Defect& b) { return rank(a.kind) < rank(b.kind); });
    for (DefectKind kind : kCheckOrder) {
      const int count = counts_[static_cast<int>(kind)];
      if (count > 0) report.counts.emplace_back(kind, count);
    }
    return report;
  }

  static int rank(DefectKind kind) {
    for (int i = 0; i < kNumKinds; ++i) {
      if (kCheckOrder[i] == kind) return i;
    }
    return kNumKinds;
  }

 private:
  int max_per_kind_;
  std::array<int, kNumKinds> counts_;
  std::vector<Defect> defects_;
};

std::string face_vertices(const Triangles& t, int f) {
  return "(" + std::to_string(t(f, 0)) + ", " + std::to_string(t(f, 1)) + ", " +
         std::to_string(t(f, 2)) + ")";
}

std::string format_number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

bool is_topological(DefectKind kind) {
  return kind == DefectKind::NonManifoldEdge || kind == DefectKind::NonManifoldVertex ||
         kind == DefectKind::InconsistentOrientation || kind == DefectKind::NonOrientable;
}

/// The halfedges of a triangle list: h = 3 f + k lies opposite corner k of face f.
struct FaceHalfedges {
  const Triangles& T;
  int tail(int h) const { return T(h / 3, (h % 3 + 1) % 3); }
  int head(int h) const { return T(h / 3, (h % 3 + 2) % 3); }
};

/// Vertices with a non-finite coordinate, reported; #V: 1 for the finite ones.
std::vector<char> check_coordinates(const Positions& P, DefectCollector& out) {
  const int nv = static_cast<int>(P.rows());
  std::vector<char> finite(nv, 1);
  for (int v = 0; v < nv; ++v) {
    if (std::isfinite(P(v, 0)) && std::isfinite(P(v, 1)) && std::isfinite(P(v, 2))) continue;
    finite[v] = 0;
    out.add(DefectKind::NonFiniteCoordinate, v, [&] {
      return "vertex " + std::to_string(v) + " has a non-finite coordinate (" +
             format_number(P(v, 0)) + ", " + format_number(P(v, 1)) + ", " +
             format_number(P(v, 2)) + ")";
    });
  }
  return finite;
}

/// Which faces the connectivity checks take, and which vertices some face names.
struct FaceUse {
  /// #F: 1 where the face's indices are valid and distinct. Duplicate faces stay usable: their
  /// edges really are shared by more than two faces, and counting them so agrees with how other
  /// tools count non-manifold edges and vertices.
  std::vector<char> usable;
  std::vector<char> referenced;  ///< #V: 1 where a face names the vertex
};

/// Faces with an index out of range, then faces that use a vertex twice, reported.
FaceUse check_indices(const Triangles& T, int nv, DefectCollector& out) {
  const int nf = static_cast<int>(T.rows());
  FaceUse use;
  use.usable.assign(nf, 1);
  use.referenced.assign(nv, 0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = T(f, k);
      if (v >= 0 && v < nv) {
        use.referenced[v] = 1;
      } else if (use.usable[f]) {
        use.usable[f] = 0;
        out.add(DefectKind::IndexOutOfRange, f, [&] {
          return "face " + std::to_string(f) + " uses vertex " + std::to_string(v) +
                 ", outside [0, " + std::to_string(nv) + ")";
        });
      }
    }
  }
  for (int f = 0; f < nf; ++f) {
    if (!use.usable[f]) continue;
    const int a = T(f, 0), b = T(f, 1), c = T(f, 2);
    if (a != b && b != c && a != c) continue;
    use.usable[f] = 0;
    out.add(DefectKind::RepeatedVertex, f, [&] {
      const int twice = (a == b || a == c) ? a : b;
      return "face " + std::to_string(f) + " uses vertex " + std::to_string(twice) +
             " more than once " + face_vertices(T, f);
    });
  }
  return use;
}

/// Duplicate faces: sort faces by their sorted vertex triple; equal neighbours are duplicates,
/// each reported with the first face on its vertices.
void check_duplicate_faces(const Triangles& T, const std::vector<char>& usable,
                           DefectCollector& out) {
  const int nf = static_cast<int>(T.rows());
  const std::vector<std::array<int, 4>> keyed =
      sorted_face_keys(T, [&](int f) { return usable[f] != 0; });
  std::vector<int> first_copy(nf, -1);
  for (std::size_t i = 1; i < keyed.size(); ++i) {
    if (std::equal(keyed[i].begin(), keyed[i].begin() + 3, keyed[i - 1].begin())) {
      const int earlier =
          first_copy[keyed[i - 1][3]] >= 0 ? first_copy[keyed[i - 1][3]] : keyed[i - 1][3];
      first_copy[keyed[i][3]] = earlier;
    }
  }
  for (int f = 0; f < nf; ++f) {
    if (first_copy[f] < 0) continue;
    out.add(DefectKind::DuplicateFace, f, [&] {
      return "face " + std::to_string(f) + " " + face_vertices(T, f) +
             " has the same vertices as face " + std::to_string(first_copy[f]) + " " +
             face_vertices(T, first_copy[f]);
    });
  }
}

/// Edges: sort the halfedges of usable faces on their undirected edge key; edges with more than
/// two faces are reported (by their first face). #H: the other halfedge of each two-faced edge,
/// -1 elsewhere.
std::vector<int> check_edges(const Triangles& T, const std::vector<char>& usable, int nv,
                             DefectCollector& out) {
  const FaceHalfedges halfedges{T};
  const int nh = 3 * static_cast<int>(T.rows());
  std::vector<std::pair<std::uint64_t, int>> keyed;
  keyed.reserve(nh);
  for (int h = 0; h < nh; ++h) {
    if (!usable[h / 3]) continue;
    const auto a = static_cast<std::uint64_t>(halfedges.tail(h));
    const auto b = static_cast<std::uint64_t>(halfedges.head(h));
    keyed.emplace_back((std::min(a, b) << 32) | std::max(a, b), h);
  }
  // (Usable faces name vertices in [0, nv): the smaller end leads the key.)
  numerics_detail::bucket_sort(keyed, nv, [](const std::pair<std::uint64_t, int>& x) {
    return static_cast<int>(x.first >> 32);
  });
  std::vector<int> twin(nh, -1);
  std::vector<std::pair<int, std::size_t>> non_manifold;  // (first face, start in keyed)
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i + 1;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    if (j - i == 2) {
      twin[keyed[i].second] = keyed[i + 1].second;
      twin[keyed[i + 1].second] = keyed[i].second;
    } else if (j - i > 2) {
      non_manifold.emplace_back(keyed[i].second / 3, i);
    }
    i = j;
  }
  std::sort(non_manifold.begin(), non_manifold.end());
  for (const auto& [face, start] : non_manifold) {
    // Init-capture: clang 14 cannot capture structured bindings.
    out.add(DefectKind::NonManifoldEdge, face, [&, start = start] {
      std::size_t end = start;
      while (end < keyed.size() && keyed[end].first == keyed[start].first) ++end;
      const int h = keyed[start].second;
      std::string faces;
      for (std::size_t i = start; i < end && i < start + 6; ++i) {
        faces += (i == start ? "" : ", ") + std::to_string(keyed[i].second / 3);
      }
      if (end - start > 6) faces += ", ...";
      return "non-manifold edge " + edge_name(halfedges.tail(h), halfedges.head(h)) +
             " is shared by " + std::to_string(end - start) + " faces (" + faces + ")";
    });
  }
  return twin;
}

/// Fans: join the corners at each end of every two-faced edge. A manifold vertex has one fan;
/// the others are reported.
void check_fans(const Triangles& T, const std::vector<int>& twin, const std::vector<char>& usable,
                int nv, DefectCollector& out) {
  const FaceHalfedges halfedges{T};
  auto tail = [&](int h) { return halfedges.tail(h); };
  auto head = [&](int h) { return halfedges.head(h); };
  const int nh = static_cast<int>(twin.size());
  DisjointSets fans(nh);
  for (int h = 0; h < nh; ++h) {
    const int g = twin[h];
    if (g < h) continue;
    unite_fans_across(fans, h, g, tail, head);
  }
  std::vector<int> fan_count(nv, 0), first_fan_face(nv, -1), second_fan_face(nv, -1);
  for (int c = 0; c < nh; ++c) {
    if (!usable[c / 3] || fans.find(c) != c) continue;
    const int v = T(c / 3, c % 3);
    if (fan_count[v]++ == 0) {
      first_fan_face[v] = c / 3;
    } else if (fan_count[v] == 2) {
      second_fan_face[v] = c / 3;
    }
  }
  for (int v = 0; v < nv; ++v) {
    if (fan_count[v] < 2) continue;
    out.add(DefectKind::NonManifoldVertex, v, [&] {
      return "non-manifold vertex " + std::to_string(v) + ": its faces form " +
             std::to_string(fan_count[v]) + " fans that meet only at the vertex (e.g. faces " +
             std::to_string(first_fan_face[v]) + " and " + std::to_string(second_fan_face[v]) + ")";
    });
  }
}

/// An edge whose two faces traverse it in the same direction, in an orientable component.
struct Inconsistency {
  int face;     // the face on the minority side of its component: reversing it helps
  int other;    // the face across the edge
  int h;        // one halfedge of the shared edge, for the vertex names
  int to_flip;  // faces of the component on the minority side
  bool operator<(const Inconsistency& o) const {
    return std::tie(face, other) < std::tie(o.face, o.other);
  }
};

/// The inconsistent edges of an orientable component, each reported from the minority side.
void add_inconsistencies(const FaceHalfedges& halfedges, const std::vector<int>& twin,
                         const OrientationSearch& search, const OrientationComponent& component,
                         std::vector<Inconsistency>& inconsistent) {
  const int minority = component.minority();
  for (int i = component.begin; i < component.end; ++i) {
    const int f = search.order[i];
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k, g = twin[h];
      if (g < h || halfedges.tail(h) != halfedges.tail(g)) continue;
      const int reported = search.side[f] == minority ? f : g / 3;
      inconsistent.push_back({reported, reported == f ? g / 3 : f, h, component.to_reverse()});
    }
  }
}

/// Orientation: breadth-first search across two-faced edges assigns each face a flip bit so
/// that neighbours traverse their shared edge in opposite directions. A contradiction means no
/// consistent orientation exists (non-orientable); otherwise every same-direction edge is an
/// inconsistency that flipping the faces with the minority bit of the component would fix.
void check_orientation(const Triangles& T, const std::vector<int>& twin,
                       const std::vector<char>& usable, DefectCollector& out) {
  const FaceHalfedges halfedges{T};
  auto tail = [&](int h) { return halfedges.tail(h); };
  auto head = [&](int h) { return halfedges.head(h); };
  std::vector<Inconsistency> inconsistent;
  const OrientationSearch search =
      search_orientation(twin, tail, [&](int f) { return usable[f] != 0; });
  for (const OrientationComponent& component : search.components) {
    if (component.conflict < 0) {
      add_inconsistencies(halfedges, twin, search, component, inconsistent);
      continue;
    }
    out.add(DefectKind::NonOrientable, component.seed, [&] {
      const int h = component.conflict, g = twin[h];
      return "non-orientable surface (like a Moebius strip): the " +
             std::to_string(component.size()) + " faces connected to face " +
             std::to_string(component.seed) +
             " cannot be oriented consistently (the contradiction closes at edge " +
             edge_name(tail(h), head(h)) + " between faces " + std::to_string(h / 3) + " and " +
             std::to_string(g / 3) + ")";
    });
  }
  std::sort(inconsistent.begin(), inconsistent.end());
  for (const Inconsistency& bad : inconsistent) {
    out.add(DefectKind::InconsistentOrientation, bad.face, [&] {
      return "inconsistent orientation: faces " + std::to_string(bad.face) + " and " +
             std::to_string(bad.other) + " traverse edge " + edge_name(tail(bad.h), head(bad.h)) +
             " in the same direction (from " + std::to_string(tail(bad.h)) + " to " +
             std::to_string(head(bad.h)) + "); the surface is orientable: reversing face " +
             std::to_string(bad.face) +
             (bad.to_flip > 1
                  ? " and the other " + std::to_string(bad.to_flip - 1) + " faces on its side"
                  : std::string()) +
             " makes it consistent";
    });
  }
}

/// Zero area: twice the area against the longest edge squared (zero_area.hpp, the test that
/// repair_mesh's sliver removal answers), on usable faces with finite corners.
void check_zero_area(const Positions& P, const Triangles& T, const std::vector<char>& usable,
                     const std::vector<char>& finite, double tolerance, DefectCollector& out) {
  for (int f = 0; f < static_cast<int>(T.rows()); ++f) {
    if (!usable[f]) continue;
    const int a = T(f, 0), b = T(f, 1), c = T(f, 2);
    if (!finite[a] || !finite[b] || !finite[c]) continue;
    const AreaMeasure measure = area_measure(P, a, b, c);
    if (!is_zero_area(measure, tolerance)) continue;
    out.add(DefectKind::ZeroAreaFace, f, [&] {
      return "face " + std::to_string(f) + " " + face_vertices(T, f) +
             " has zero area (twice its area is " + format_number(measure.twice_area) +
             ", its longest edge squared " + format_number(measure.longest_squared) + ")";
    });
  }
}
}  // namespace

const char* defect_name(DefectKind kind) {
  return enum_name(kind);
}

int ValidationReport::count(DefectKind kind) const {
  for (const auto& [k, c] : counts) {
    if (k == kind) return c;
  }
  return 0;
}

bool ValidationReport::ok() const {
  for (const auto& [kind, count] : counts) {
    if (kind != DefectKind::UnreferencedVertex && count > 0) return false;
  }
  return true;
}

ValidationReport find_defects(const Mesh& mesh, const ValidationOptions& options) {
  const Positions& P = mesh.positions;
  const Triangles& T = mesh.triangles;
  DefectCollector out(options.max_defects_per_kind);
  const std::vector<char> finite = check_coordinates(P, out);
  const FaceUse use = check_indices(T, mesh.num_vertices(), out);
  // Duplicate faces and zero areas beside the edges, fans and orientation (a quarter of the
  // work: bunny's 28k faces, 7.8 ms on one thread); each kind is found by one of the two.
  auto duplicates_and_areas = [&] {
    DefectCollector found(options.max_defects_per_kind);
    check_duplicate_faces(T, use.usable, found);
    check_zero_area(P, T, use.usable, finite, options.zero_area_tolerance, found);
    return found;
  };
  // (Below some thousands of faces the checks take well under a millisecond: all here.)
  constexpr int kMinFacesBeside = 4096;
  parallel::Task<DefectCollector> beside;
  if (mesh.num_faces() >= kMinFacesBeside) beside = parallel::run_beside(duplicates_and_areas);
  const std::vector<int> twin = check_edges(T, use.usable, mesh.num_vertices(), out);
  check_fans(T, twin, use.usable, mesh.num_vertices(), out);
  check_orientation(T, twin, use.usable, out);
  out.merge(beside.valid() ? beside.get() : duplicates_and_areas());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (use.referenced[v]) continue;
    out.add(DefectKind::UnreferencedVertex, v,
            [&] { return "vertex " + std::to_string(v) + " is not used by any face"; });
  }
  return out.finish();
}

void throw_first_defect(const ValidationReport& report, const std::string& context) {
  for (const Defect& defect : report.defects) {
    if (defect.kind == DefectKind::UnreferencedVertex) continue;
    std::string message =
        (context.empty() ? std::string("validate_mesh") : context) + ": " + defect.message;
    for (const auto& [kind, count] : report.counts) {
      if (kind == defect.kind && count > 1) {
        message += " (and " + std::to_string(count - 1) + " more " + defect_name(kind) + " defect" +
                   (count > 2 ? "s" : "") + ")";
      }
    }
    if (is_topological(defect.kind)) throw TopologyError(message);
    throw InvalidInput(message);
  }
}

void validate_mesh(const Mesh& mesh, const std::string& context, const ValidationOptions& options) {
  throw_first_defect(find_defects(mesh, options), context);
}

}  // namespace ricci
