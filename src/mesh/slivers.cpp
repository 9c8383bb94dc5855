#include "mesh/detail/slivers.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <utility>

#include <Eigen/Geometry>

#include "mesh/detail/zero_area.hpp"

namespace ricci::mesh_detail {
namespace {

/// The faces as they change, with each vertex's faces, so that the faces on an edge are found
/// among the few around one of its ends.
class SliverWork {
 public:
  SliverWork(const Positions& P, const Triangles& T, double tolerance)
      : P_(P), tolerance_(tolerance) {
    const int nf = static_cast<int>(T.rows());
    faces_.resize(nf);
    root_.resize(nf);
    piece_.assign(nf, 0);
    alive_.assign(nf, 1);
    why_.assign(nf, SliverLeft::Unresolved);
    on_boundary_.assign(nf, 0);
    around_.resize(P.rows());
    finite_.resize(P.rows());
    for (Eigen::Index v = 0; v < P.rows(); ++v) finite_[v] = P.row(v).allFinite() ? 1 : 0;
    for (int f = 0; f < nf; ++f) {
      faces_[f] = {T(f, 0), T(f, 1), T(f, 2)};
      root_[f] = f;
      for (int v : faces_[f]) around_[v].push_back(f);
    }
    zero_at_start_.resize(nf);
    for (int f = 0; f < nf; ++f) zero_at_start_[f] = zero(f) ? 1 : 0;
  }

  bool zero_at_start(int f) const { return zero_at_start_[f] != 0; }

  int num_faces() const { return static_cast<int>(faces_.size()); }
  bool alive(int f) const { return alive_[f] != 0; }
  /// Zero area (faces with a non-finite corner are validation's business, not this one's).
  bool zero(int f) const {
    const std::array<int, 3>& face = faces_[f];
    return finite_[face[0]] && finite_[face[1]] && finite_[face[2]] &&
           is_zero_area(P_, face[0], face[1], face[2], tolerance_);
  }
  SliverLeft why(int f) const { return why_[f]; }

  /// Removes sliver f, or splits the face across its longest edge; false (with why(f) set) when
  /// neither is exact. A neighbour that is a sliver itself is split only when `chain` is set.
  /// New pieces of zero area are appended to `pending`.
  bool remove(int f, bool chain, std::vector<int>& pending) {
    const std::array<int, 3>& face = faces_[f];
    // w: the corner opposite the longest edge, which runs u -> v in f.
    int k = 0;
    double longest = -1;
    for (int i = 0; i < 3; ++i) {
      const double length = squared_length(face[(i + 1) % 3], face[(i + 2) % 3]);
      if (length > longest) {
        longest = length;
        k = i;
      }
    }
    const int w = face[k], u = face[(k + 1) % 3], v = face[(k + 2) % 3];
    const std::vector<int> on = faces_on(u, v);
    if (on.size() == 1) {  // a boundary edge: the sliver covers nothing
      kill(f);
      on_boundary_[root_[f]] = 1;
      return true;
    }
    if (on.size() > 2) return refuse(f, SliverLeft::CrowdedEdge);
    const int g = on[0] == f ? on[1] : on[0];
    // g = (x, a, b) in its own order, a -> b its side of the edge.
    int m = 0;
    while (faces_[g][m] == u || faces_[g][m] == v) ++m;
    const int x = faces_[g][m], a = faces_[g][(m + 1) % 3], b = faces_[g][(m + 2) % 3];
    if (x == w || !faces_on(w, x).empty()) return refuse(f, SliverLeft::ExistingEdge);
    const bool g_zero = zero(g);
    if (g_zero) {
      // Along one line: split only where uv is g's longest edge too (x between u and v), so
      // that the new edge wx is shorter than uv.
      if (!chain) return refuse(f, SliverLeft::Unresolved);
      if (squared_length(x, a) > longest || squared_length(x, b) > longest) {
        return refuse(f, SliverLeft::Unresolved);
      }
    }
    const Eigen::Vector3d pa = point(a), pb = point(b), pw = point(w), px = point(x);
    const double t = (pw - pa).dot(pb - pa) / (pb - pa).squaredNorm();
    if (!(t > 0 && t < 1)) return refuse(f, SliverLeft::Needle);
    if (!g_zero) {
      // Both pieces keep g's side and have an area of their own.
      const Eigen::Vector3d normal = (pa - px).cross(pb - px);
      if (!((pa - px).cross(pw - px).dot(normal) > 0) ||
          !((pw - px).cross(pb - px).dot(normal) > 0) || is_zero_area(P_, x, a, w, tolerance_) ||
          is_zero_area(P_, x, w, b, tolerance_)) {
        return refuse(f, SliverLeft::Needle);
      }
    }
    kill(f);
    detach(g);
    faces_[g] = {x, a, w};
    piece_[g] = 1;
    attach(g);
    const int n = num_faces();
    faces_.push_back({x, w, b});
    root_.push_back(root_[g]);
    piece_.push_back(1);
    alive_.push_back(1);
    why_.push_back(SliverLeft::Unresolved);
    attach(n);
    if (zero(g)) pending.push_back(g);
    if (zero(n)) pending.push_back(n);
    return true;
  }

  /// The alive faces, the pieces of an input row in its place, and what became of the rows.
  void emit(SliverRemoval& out) const {
    const int rows = static_cast<int>(zero_at_start_.size());
    std::vector<char> kept(rows, 0), in_pieces(rows, 0);
    for (int f = 0; f < num_faces(); ++f) {
      if (!alive_[f]) continue;
      kept[root_[f]] = 1;
      if (piece_[f]) in_pieces[root_[f]] = 1;
    }
    for (int row = 0; row < rows; ++row) {
      if (zero_at_start_[row] && !kept[row]) {
        out.removed.push_back(row);
        out.on_boundary.push_back(on_boundary_[row]);
      }
      if (!zero_at_start_[row] && in_pieces[row]) out.split.push_back(row);
    }
    std::vector<int> order;
    for (int f = 0; f < num_faces(); ++f) {
      if (alive_[f]) order.push_back(f);
    }
    std::stable_sort(order.begin(), order.end(), [&](int p, int q) { return root_[p] < root_[q]; });
    out.triangles.resize(static_cast<Eigen::Index>(order.size()), 3);
    out.origin.clear();
    out.piece.clear();
    for (std::size_t i = 0; i < order.size(); ++i) {
      const int f = order[i];
      for (int k = 0; k < 3; ++k) out.triangles(static_cast<Eigen::Index>(i), k) = faces_[f][k];
      out.origin.push_back(root_[f]);
      out.piece.push_back(piece_[f]);
    }
  }

  int root(int f) const { return root_[f]; }

 private:
  Eigen::Vector3d point(int v) const { return P_.row(v).transpose(); }
  double squared_length(int p, int q) const { return (P_.row(p) - P_.row(q)).squaredNorm(); }
  std::vector<int> faces_on(int p, int q) const {
    std::vector<int> on;
    for (int f : around_[p]) {
      if (faces_[f][0] == q || faces_[f][1] == q || faces_[f][2] == q) on.push_back(f);
    }
    return on;
  }
  bool refuse(int f, SliverLeft why) {
    why_[f] = why;
    return false;
  }
  void attach(int f) {
    for (int v : faces_[f]) around_[v].push_back(f);
  }
  void detach(int f) {
    for (int v : faces_[f]) {
      std::vector<int>& list = around_[v];
      list.erase(std::remove(list.begin(), list.end(), f), list.end());
    }
  }
  void kill(int f) {
    detach(f);
    alive_[f] = 0;
  }

  const Positions& P_;
  double tolerance_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<int> root_;  // input row
  std::vector<char> piece_, alive_, finite_;
  std::vector<char> zero_at_start_, on_boundary_;  // per input row
  std::vector<SliverLeft> why_;                    // why the face was last refused
  std::vector<std::vector<int>> around_;
};

}  // namespace

SliverRemoval remove_slivers(const Positions& P, const Triangles& T, double tolerance) {
  SliverRemoval out;
  // Most meshes have none: then nothing is built.
  bool any = false;
  for (Eigen::Index f = 0; f < T.rows() && !any; ++f) {
    const int a = T(f, 0), b = T(f, 1), c = T(f, 2);
    any = P.row(a).allFinite() && P.row(b).allFinite() && P.row(c).allFinite() &&
          is_zero_area(P, a, b, c, tolerance);
  }
  if (!any) return out;
  SliverWork work(P, T, tolerance);
  std::vector<int> pending;
  for (int f = 0; f < work.num_faces(); ++f) {
    if (work.zero_at_start(f)) pending.push_back(f);
  }
  // Each removal without `chain` leaves one zero-area face fewer; a split across another sliver
  // leaves at most as many, with a shorter edge in place of the longest; their number is bounded
  // all the same, so that no configuration keeps the loop going.
  const std::int64_t n0 = static_cast<std::int64_t>(pending.size());
  const std::int64_t chain_budget = std::min<std::int64_t>(4 * n0 * n0 + 64, 200000);
  std::int64_t chain_splits = 0;
  auto still_pending = [&](int f) { return work.alive(f) && work.zero(f); };
  while (!pending.empty()) {
    bool removed = false;
    for (std::size_t i = 0; i < pending.size(); ++i) {  // pending may grow meanwhile
      const int f = pending[i];
      if (still_pending(f) && work.remove(f, false, pending)) removed = out.changed = true;
    }
    std::vector<int> next;
    for (int f : pending) {
      if (still_pending(f)) next.push_back(f);
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    pending = std::move(next);
    if (removed || pending.empty()) continue;
    // Only slivers next to slivers are left: one split across a pair, then the plain removals
    // again.
    if (chain_splits >= chain_budget) break;
    bool chained = false;
    for (std::size_t i = 0; i < pending.size() && !chained; ++i) {
      chained = work.remove(pending[i], true, pending);
    }
    if (!chained) break;
    out.changed = true;
    ++chain_splits;
  }
  for (int f : pending) {
    if (!still_pending(f)) continue;
    out.left.push_back(work.root(f));
    out.left_why.push_back(work.why(f));
  }
  if (out.changed) work.emit(out);
  // Rows in ascending order, each reason with its row (a row once per piece left).
  std::vector<std::size_t> by_row(out.left.size());
  std::iota(by_row.begin(), by_row.end(), std::size_t{0});
  std::stable_sort(by_row.begin(), by_row.end(),
                   [&](std::size_t p, std::size_t q) { return out.left[p] < out.left[q]; });
  std::vector<int> rows;
  std::vector<SliverLeft> whys;
  for (std::size_t i : by_row) {
    rows.push_back(out.left[i]);
    whys.push_back(out.left_why[i]);
  }
  out.left = std::move(rows);
  out.left_why = std::move(whys);
  return out;
}

std::string sliver_left_reason(SliverLeft why) {
  switch (why) {
    case SliverLeft::Needle:
      return "a vertex nearly coincides with another (a needle, not a sliver: welding with a "
             "tolerance would remove it)";
    case SliverLeft::CrowdedEdge:
      return "its longest edge has more than two faces";
    case SliverLeft::ExistingEdge:
      return "splitting its neighbour would repeat an edge the mesh has";
    case SliverLeft::Unresolved:
      return "a chain of zero-area faces that splitting did not resolve";
  }
  return "";
}

}  // namespace ricci::mesh_detail
