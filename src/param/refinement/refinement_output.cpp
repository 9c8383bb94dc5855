// The output stages of common_refinement (param/refinement/detail/refinement_stages.hpp): the
// pieces numbered and written out, laid out in the final metric and fitted onto the layout, and
// the figures that measure the result.
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include "param/refinement/detail/refinement_stages.hpp"
#include "param/refinement/detail/refinement_support.hpp"

namespace ricci::refinement_support {
namespace {

/// A piece is counted degenerate when its 3D area is below this fraction of its longest side
/// squared: chords through one point, up to the rounding of the crossings (a few ulps).
constexpr double kDegenerateArea = 1e-14;

/// Per input face of the front, its pieces in order.
std::vector<std::vector<int>> pieces_by_face(const std::vector<Piece>& pieces, int front_faces) {
  std::vector<std::vector<int>> by_face(static_cast<std::size_t>(front_faces));
  for (int p = 0; p < static_cast<int>(pieces.size()); ++p) {
    by_face[pieces[p].input_face].push_back(p);
  }
  return by_face;
}

/// Per refinement edge id, the piece sides 3 p + k on it (-1: none).
std::vector<std::array<int, 2>> sides_by_edge(const Context& c, const std::vector<Piece>& pieces) {
  std::vector<std::array<int, 2>> edge_pieces(static_cast<std::size_t>(c.num_edge_ids), {-1, -1});
  for (int p = 0; p < static_cast<int>(pieces.size()); ++p) {
    for (int k = 0; k < 3; ++k) {
      auto& slot = edge_pieces[pieces[p].edge_id[k]];
      (slot[0] < 0 ? slot[0] : slot[1]) = 3 * p + k;
    }
  }
  return edge_pieces;
}

/// Corner k of a piece in its final face's own plane.
Complex final_position(const Context& c, const Piece& piece, int k) {
  const auto& shape = c.final_shapes[piece.final_face];
  const Vec3& b = piece.final_bary[k];
  return b[0] * shape[0] + b[1] * shape[1] + b[2] * shape[2];
}

/// Places the pieces of one input face (`list`) in the final metric: rigid motions across the
/// final edges inside it, from the first piece outward (motion, placed: per piece).
void develop_face_pieces(const Context& c, const std::vector<Piece>& pieces,
                         const std::vector<int>& list,
                         const std::vector<std::array<int, 2>>& edge_pieces,
                         std::vector<Rigid>& motion, std::vector<char>& placed, int f) {
  auto halfedge_ends = [&](int g, int h) {
    const auto& shape = c.final_shapes[g];
    return std::pair<Complex, Complex>{shape[(h % 3 + 1) % 3], shape[(h % 3 + 2) % 3]};
  };
  std::vector<int> queue{list.front()};
  placed[list.front()] = 1;
  motion[list.front()] = {};
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int p = queue[head];
    for (int k = 0; k < 3; ++k) {
      if (pieces[p].input_edge[k] >= 0) continue;
      const auto& slot = edge_pieces[pieces[p].edge_id[k]];
      const int other = slot[0] == 3 * p + k ? slot[1] : slot[0];
      if (other < 0 || placed[other / 3]) continue;
      const int q = other / 3, kq = other % 3;
      const int hp = pieces[p].final_halfedge[k], hq = pieces[q].final_halfedge[kq];
      if (hp >= 0) {
        if (hq < 0 || c.tp.halfedge_twin[hp] != hq) internal_error("final edge sides disagree");
        const auto [p_tail, p_head] = halfedge_ends(pieces[p].final_face, hp);
        const auto [q_tail, q_head] = halfedge_ends(pieces[q].final_face, hq);
        motion[q] = compose(motion[p], segment_motion(q_tail, q_head, p_head, p_tail));
      } else {
        if (pieces[q].final_face != pieces[p].final_face) {
          internal_error("pieces of two final faces meet off a final edge");
        }
        motion[q] = motion[p];
      }
      placed[q] = 1;
      queue.push_back(q);
    }
  }
  if (queue.size() != list.size()) {
    internal_error("the pieces of input face " + std::to_string(f) + " are not connected");
  }
}

/// The rigid motion fitting input face f's developed corners onto its corners in exact_uv (the
/// rotation of least squares about the centroids); records the mismatch.
Rigid fit_to_layout(const Context& c, const std::vector<Piece>& pieces,
                    const std::vector<int>& list, const std::vector<Rigid>& motion, int f,
                    const Eigen::Matrix<double, Eigen::Dynamic, 2>& exact_uv,
                    CommonRefinement& result) {
  std::array<Complex, 3> developed{}, target{};
  std::array<int, 3> found{0, 0, 0};
  for (int p : list) {
    for (int k = 0; k < 3; ++k) {
      const int v = pieces[p].vertex[k];
      for (int j = 0; j < 3; ++j) {
        if (v == c.t0.triangles(f, j) && !found[j]) {
          developed[j] = motion[p](final_position(c, pieces[p], k));
          found[j] = 1;
        }
      }
    }
  }
  double longest = 0;
  for (int j = 0; j < 3; ++j) {
    if (!found[j]) internal_error("input face " + std::to_string(f) + " misses a corner");
    const int cv = c.param.cut_mesh.triangles(f, j);
    target[j] = {exact_uv(cv, 0), exact_uv(cv, 1)};
  }
  for (int j = 0; j < 3; ++j)
    longest = std::max(longest, std::abs(target[(j + 1) % 3] - target[j]));
  const Complex cd = (developed[0] + developed[1] + developed[2]) / 3.0;
  const Complex ct = (target[0] + target[1] + target[2]) / 3.0;
  Complex rot = 0;
  for (int j = 0; j < 3; ++j) rot += std::conj(developed[j] - cd) * (target[j] - ct);
  rot = std::abs(rot) > 0 ? rot / std::abs(rot) : Complex(1);
  const Rigid fit{rot, ct - rot * cd};
  for (int j = 0; j < 3; ++j) {
    result.max_corner_mismatch =
        std::max(result.max_corner_mismatch, std::abs(fit(developed[j]) - target[j]) / longest);
  }
  return fit;
}

/// result.projective_uv from uv and the pieces' log weights (each triangle's largest w 1).
void write_projective_uv(const std::vector<Piece>& pieces, CommonRefinement& result) {
  const int nt = static_cast<int>(pieces.size());
  result.projective_uv.resize(3 * nt, 3);
  for (int p = 0; p < nt; ++p) {
    const auto& lw = pieces[p].log_w;
    const double top = std::max({lw[0], lw[1], lw[2]});
    for (int k = 0; k < 3; ++k) {
      const double w = std::exp(lw[k] - top);
      const auto uv = result.uv.row(result.uv_triangles(p, k));
      result.projective_uv.row(3 * p + k) << w * uv[0], w * uv[1], w;
    }
  }
}

}  // namespace

std::vector<int> number_vertices(const Context& c, std::vector<Piece>& pieces,
                                 CommonRefinement& result) {
  const int nv = c.mesh.num_vertices();            // the surface flowed
  const int nv_out = c.param.mesh.num_vertices();  // the mesh parameterized
  std::vector<int> out_index(static_cast<std::size_t>(nv) + c.rows.size(), -1);
  for (int v = 0; v < nv_out; ++v) out_index[v] = v;
  for (Piece& piece : pieces) {
    for (int v : piece.vertex) {
      if (v >= nv_out && v < nv) internal_error("a front piece uses a mirror vertex");
      if (v >= nv) out_index[v] = 0;  // used; numbered below
    }
  }
  std::vector<int> raw_of;  // output vertex -> raw index
  raw_of.reserve(out_index.size());
  for (int v = 0; v < nv_out; ++v) raw_of.push_back(v);
  for (int r = nv; r < static_cast<int>(out_index.size()); ++r) {
    if (out_index[r] < 0) continue;
    out_index[r] = static_cast<int>(raw_of.size());
    raw_of.push_back(r);
    const char kind = c.kind[r - nv];
    ++(kind == 0   ? result.input_delaunay_points
       : kind == 1 ? result.delaunay_intrinsic_points
                   : result.interior_points);
  }
  for (Piece& piece : pieces) {
    for (int& v : piece.vertex) v = out_index[v];
  }
  return raw_of;
}

void write_vertices_and_pieces(const Context& c, const std::vector<int>& raw_of,
                               const std::vector<Piece>& pieces,
                               const CommonRefinementOptions& options, CommonRefinement& result) {
  const int nv = c.mesh.num_vertices();
  const int nv_out = c.param.mesh.num_vertices();
  const int nr = static_cast<int>(raw_of.size());
  auto row_of = [&](int out) -> const Row& { return c.rows[raw_of[out] - nv]; };
  result.positions.resize(nr, 3);
  result.positions.topRows(nv_out) = c.param.mesh.positions;
  for (int r = nv_out; r < nr; ++r) {
    Eigen::RowVector3d p = Eigen::RowVector3d::Zero();
    for (const auto& [v, w] : row_of(r)) p += w * c.mesh.positions.row(v);
    result.positions.row(r) = p;
  }
  if (options.interpolation_matrix) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(nv_out);
    for (int v = 0; v < nv_out; ++v) triplets.emplace_back(v, v, 1.0);
    for (int r = nv_out; r < nr; ++r) {
      for (const auto& [v, w] : row_of(r)) {
        if (v >= nv_out) internal_error("a front point leans on a mirror vertex");
        if (w != 0) triplets.emplace_back(r, v, w);
      }
    }
    result.interpolation.resize(nr, nv_out);
    result.interpolation.setFromTriplets(triplets.begin(), triplets.end());
  }
  result.input_vertex.resize(nv_out);
  for (int v = 0; v < nv_out; ++v) result.input_vertex[v] = v;
  const int nt = static_cast<int>(pieces.size());
  result.triangles.resize(nt, 3);
  result.input_face.resize(nt);
  result.delaunay_face.resize(nt);
  result.intrinsic_face.resize(nt);
  result.delaunay_barycentric.resize(3 * nt, 3);
  result.intrinsic_barycentric.resize(3 * nt, 3);
  for (int p = 0; p < nt; ++p) {
    const Piece& piece = pieces[p];
    for (int k = 0; k < 3; ++k) {
      result.triangles(p, k) = piece.vertex[k];
      result.delaunay_barycentric.row(3 * p + k) = piece.delaunay_bary[k].transpose();
      result.intrinsic_barycentric.row(3 * p + k) = piece.final_bary[k].transpose();
    }
    result.input_face[p] = piece.input_face;
    result.delaunay_face[p] = piece.delaunay_face;
    result.intrinsic_face[p] = piece.final_face;
  }
}

std::vector<std::array<Complex, 3>> lay_out_pieces(
    const Context& c, const std::vector<Piece>& pieces, int front_faces,
    const Eigen::Matrix<double, Eigen::Dynamic, 2>& exact_uv, CommonRefinement& result) {
  const int nt = static_cast<int>(pieces.size());
  const std::vector<std::array<int, 2>> edge_pieces = sides_by_edge(c, pieces);
  const std::vector<std::vector<int>> by_face = pieces_by_face(pieces, front_faces);
  std::vector<Rigid> motion(static_cast<std::size_t>(nt));
  std::vector<char> placed(static_cast<std::size_t>(nt), 0);
  std::vector<std::array<Complex, 3>> corner_uv(static_cast<std::size_t>(nt));
  for (int f = 0; f < front_faces; ++f) {
    const auto& list = by_face[f];
    if (list.empty()) internal_error("input face " + std::to_string(f) + " has no pieces");
    develop_face_pieces(c, pieces, list, edge_pieces, motion, placed, f);
    const Rigid fit = fit_to_layout(c, pieces, list, motion, f, exact_uv, result);
    for (int p : list) {
      for (int k = 0; k < 3; ++k) corner_uv[p][k] = fit(motion[p](final_position(c, pieces[p], k)));
    }
  }
  return corner_uv;
}

void write_texture_coordinates(const Context& c, const std::vector<Piece>& pieces,
                               const std::vector<int>& raw_of,
                               const std::vector<std::array<Complex, 3>>& corner_uv,
                               int front_faces, bool polished,
                               const Eigen::Matrix<double, Eigen::Dynamic, 2>& exact_uv,
                               CommonRefinement& result) {
  const Parameterization& param = c.param;
  const int nv = c.mesh.num_vertices();
  const int nv_out = param.mesh.num_vertices();
  const int nt = static_cast<int>(pieces.size());
  // Input edges of the surface flowed -> the mesh's (the front faces' halfedges are the mesh's).
  const Topology mesh_topology = build_topology(param.mesh.triangles, nv_out);
  std::vector<int> mesh_edge(static_cast<std::size_t>(c.t0.num_edges), -1);
  for (int h = 0; h < 3 * front_faces; ++h)
    mesh_edge[c.t0.halfedge_edge[h]] = mesh_topology.halfedge_edge[h];
  const std::vector<std::vector<int>> by_face = pieces_by_face(pieces, front_faces);
  const int base = static_cast<int>(param.uv.rows());
  std::vector<Eigen::Vector2d> extra;
  std::unordered_map<long long, int> key_index;
  result.uv_triangles.resize(nt, 3);
  for (int f = 0; f < front_faces; ++f) {
    for (int p : by_face[f]) {
      for (int k = 0; k < 3; ++k) {
        const int v = pieces[p].vertex[k];
        if (v < nv_out) {
          int j = 0;
          while (j < 3 && c.t0.triangles(f, j) != v) ++j;
          result.uv_triangles(p, k) = param.cut_mesh.triangles(f, j);
          continue;
        }
        const int ie =
            c.on_input_edge[raw_of[v] - nv] < 0 ? -1 : mesh_edge[c.on_input_edge[raw_of[v] - nv]];
        const bool seam = ie >= 0 && !param.cut.is_cut_edge.empty() && param.cut.is_cut_edge[ie];
        const long long key = static_cast<long long>(v) * (front_faces + 1) + (seam ? f + 1 : 0);
        auto [it, inserted] = key_index.emplace(key, base + static_cast<int>(extra.size()));
        if (inserted) {
          const Complex z = corner_uv[p][k];
          extra.emplace_back((Eigen::Vector2d(z.real(), z.imag()) - param.uv_offset) *
                             param.uv_scale);
        }
        result.uv_triangles(p, k) = it->second;
      }
    }
  }
  result.uv.resize(base + static_cast<int>(extra.size()), 2);
  if (polished) {
    result.uv.topRows(base) = (exact_uv.rowwise() - param.uv_offset.transpose()) * param.uv_scale;
  } else {
    result.uv.topRows(base) = param.uv;
  }
  for (std::size_t i = 0; i < extra.size(); ++i)
    result.uv.row(base + static_cast<int>(i)) = extra[i].transpose();
  write_projective_uv(pieces, result);
}

void measure_refinement(const Context& c, const std::vector<Piece>& pieces,
                        const std::vector<int>& on_final_all, const Eigen::VectorXd& final_lengths,
                        CommonRefinement& result) {
  const int nt = static_cast<int>(pieces.size());
  std::vector<double> along(static_cast<std::size_t>(c.tp.num_edges), 0.0);
  std::vector<int> on_final_kept(static_cast<std::size_t>(c.tp.num_edges), 0);
  for (int p = 0; p < nt; ++p) {
    const Eigen::RowVector3d a = result.positions.row(result.triangles(p, 0));
    const Eigen::RowVector3d b = result.positions.row(result.triangles(p, 1));
    const Eigen::RowVector3d d = result.positions.row(result.triangles(p, 2));
    const double longest =
        std::max({(b - a).squaredNorm(), (d - b).squaredNorm(), (a - d).squaredNorm()});
    const double area = (b - a).cross(d - a).norm();
    const auto u0 = result.uv.row(result.uv_triangles(p, 0));
    const auto u1 = result.uv.row(result.uv_triangles(p, 1));
    const auto u2 = result.uv.row(result.uv_triangles(p, 2));
    const double uv_area = (u1[0] - u0[0]) * (u2[1] - u0[1]) - (u2[0] - u0[0]) * (u1[1] - u0[1]);
    if (area <= kDegenerateArea * longest) {
      ++result.degenerate_triangles;
    } else if (uv_area <= 0) {
      ++result.inverted_triangles;
    }
    for (int k = 0; k < 3; ++k) {
      const int hp = pieces[p].final_halfedge[k];
      if (hp < 0) continue;
      const int ep = c.tp.halfedge_edge[hp];
      if (hp != c.tp.edge_halfedges(ep, 0)) continue;
      ++on_final_kept[ep];
      along[ep] += (result.uv.row(result.uv_triangles(p, (k + 1) % 3)) -
                    result.uv.row(result.uv_triangles(p, (k + 2) % 3)))
                       .norm() /
                   c.param.uv_scale;
    }
  }
  for (int e = 0; e < c.tp.num_edges; ++e) {
    // Final edges of a doubled surface that reach into the mirror half are not all laid out.
    if (on_final_kept[e] != on_final_all[e]) continue;
    result.max_intrinsic_length_error =
        std::max(result.max_intrinsic_length_error,
                 std::abs(along[e] - final_lengths[e]) / final_lengths[e]);
  }
}

}  // namespace ricci::refinement_support
