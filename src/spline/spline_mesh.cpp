#include "ricci/spline/spline_mesh.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/LU>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

using Key = std::array<std::int64_t, 3>;

struct KeyHash {
  std::size_t operator()(const Key& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::int64_t x : k) {
      h ^= static_cast<std::uint64_t>(x) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    }
    return static_cast<std::size_t>(h);
  }
};

void check_ordinates(const SplineDomain& d, const Eigen::MatrixXd& ordinates, const char* who) {
  if (ordinates.rows() != kPowellSabinOrdinates * d.triangles.rows()) {
    throw InvalidInput(
        std::string(who) + ": ordinates have " + std::to_string(ordinates.rows()) +
        " rows, expected 19 #F = " + std::to_string(kPowellSabinOrdinates * d.triangles.rows()));
  }
}

/// Value of piece `slots` of face f at lattice point (i, j, l) / K: (1 by k).
using LatticeValue =
    std::function<Eigen::RowVectorXd(int f, const std::array<int, 6>& slots, int i, int j, int l)>;

SplineTessellation build_lattice(const SplineDomain& d, int refine, int num_columns,
                                 const LatticeValue& value) {
  const int nf = static_cast<int>(d.triangles.rows());
  const std::int64_t nv = d.num_vertices, ne = d.num_edges;
  const int kk = refine;
  const int per_piece = (kk + 1) * (kk + 2) / 2;
  std::unordered_map<Key, int, KeyHash> index;
  index.reserve(static_cast<std::size_t>(nf) * (3 * kk * kk + 3));
  std::vector<Eigen::RowVectorXd> values;
  std::vector<int> face;
  std::vector<Eigen::Vector3d> bary;
  std::vector<Eigen::Vector3i> tris;
  tris.reserve(static_cast<std::size_t>(nf) * 6 * kk * kk);
  std::vector<int> local(per_piece);
  auto local_index = [&](int j, int l) {
    // rows by l, then j: points with the same l are contiguous
    int offset = 0;
    for (int m = 0; m < l; ++m) offset += kk + 1 - m;
    return offset + j;
  };
  for (int f = 0; f < nf; ++f) {
    Eigen::Matrix2d face_frame;
    const Eigen::Vector2d c0(d.corner_uv(f, 0), d.corner_uv(f, 1));
    face_frame.col(0) = Eigen::Vector2d(d.corner_uv(f, 2), d.corner_uv(f, 3)) - c0;
    face_frame.col(1) = Eigen::Vector2d(d.corner_uv(f, 4), d.corner_uv(f, 5)) - c0;
    const Eigen::Matrix2d to_face = face_frame.inverse();
    for (int p = 0; p < kPowellSabinPieces; ++p) {
      const int k = p / 2;
      const std::int64_t vp = d.triangles(f, (k + 1) % 3), vq = d.triangles(f, (k + 2) % 3);
      const std::int64_t r = nv + d.halfedge_edge[3 * f + k];
      const std::int64_t z = nv + ne + f;
      const std::array<std::int64_t, 3> nodes = p % 2 == 0 ? std::array<std::int64_t, 3>{vp, r, z}
                                                           : std::array<std::int64_t, 3>{r, vq, z};
      const std::array<Eigen::Vector2d, 3> tri = piece_triangle(d, f, p);
      const std::array<int, 6> slots = piece_slots(p);
      for (int l = 0; l <= kk; ++l) {
        for (int j = 0; j <= kk - l; ++j) {
          const int i = kk - j - l;
          const std::array<int, 3> w = {i, j, l};
          Key key{-1, -1, -1};
          int n = 0;  // weights of the nodes the point combines
          for (int a = 0; a < 3; ++a) {
            if (w[a] > 0) key[n++] = nodes[a] * (kk + 1) + w[a];
          }
          // unused entries are -1 and stay first after sorting: the key is still canonical
          if (key[0] > key[1]) std::swap(key[0], key[1]);
          if (key[1] > key[2]) std::swap(key[1], key[2]);
          if (key[0] > key[1]) std::swap(key[0], key[1]);
          auto [it, inserted] = index.try_emplace(key, static_cast<int>(values.size()));
          if (inserted) {
            values.push_back(value(f, slots, i, j, l));
            const Eigen::Vector2d x = (i * tri[0] + j * tri[1] + l * tri[2]) / kk;
            const Eigen::Vector2d b = to_face * (x - c0);
            face.push_back(f);
            bary.emplace_back(1 - b.x() - b.y(), b.x(), b.y());
          }
          local[local_index(j, l)] = it->second;
        }
      }
      auto at = [&](int j, int l) { return local[local_index(j, l)]; };
      for (int l = 0; l < kk; ++l) {
        for (int j = 0; j < kk - l; ++j) {
          tris.emplace_back(at(j, l), at(j + 1, l), at(j, l + 1));  // (i, j, l) up
          if (j + 1 < kk - l) tris.emplace_back(at(j + 1, l), at(j + 1, l + 1), at(j, l + 1));
        }
      }
    }
  }
  SplineTessellation out;
  out.values.resize(static_cast<Eigen::Index>(values.size()), num_columns);
  out.barycentric.resize(static_cast<Eigen::Index>(values.size()), 3);
  for (std::size_t q = 0; q < values.size(); ++q) {
    out.values.row(static_cast<Eigen::Index>(q)) = values[q];
    out.barycentric.row(static_cast<Eigen::Index>(q)) = bary[q].transpose();
  }
  out.face = std::move(face);
  out.triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    out.triangles.row(static_cast<Eigen::Index>(t)) = tris[t].transpose();
  }
  return out;
}

}  // namespace

SplineTessellation tessellate_spline(const SplineDomain& d, const Eigen::MatrixXd& ordinates,
                                     int refine) {
  check_ordinates(d, ordinates, "tessellate_spline");
  if (refine < 1) {
    throw InvalidInput("tessellate_spline: refine must be >= 1, got " + std::to_string(refine));
  }
  const double kk = refine;
  return build_lattice(
      d, refine, static_cast<int>(ordinates.cols()),
      [&](int f, const std::array<int, 6>& s, int i, int j, int l) -> Eigen::RowVectorXd {
        const double a = i / kk, b = j / kk, c = l / kk;
        auto o = [&](int q) { return ordinates.row(kPowellSabinOrdinates * f + s[q]); };
        return o(0) * (a * a) + o(1) * (b * b) + o(2) * (c * c) + o(3) * (2 * a * b) +
               o(4) * (2 * a * c) + o(5) * (2 * b * c);
      });
}

SplineTessellation spline_control_net(const SplineDomain& d, const Eigen::MatrixXd& ordinates) {
  check_ordinates(d, ordinates, "spline_control_net");
  return build_lattice(
      d, 2, static_cast<int>(ordinates.cols()),
      [&](int f, const std::array<int, 6>& s, int i, int j, int l) -> Eigen::RowVectorXd {
        // lattice (2,0,0) (0,2,0) (0,0,2) (1,1,0) (1,0,1) (0,1,1) -> b200 b020 b002 b110 b101 b011
        int q = 0;
        if (i == 2)
          q = 0;
        else if (j == 2)
          q = 1;
        else if (l == 2)
          q = 2;
        else if (l == 0)
          q = 3;
        else if (j == 0)
          q = 4;
        else
          q = 5;
        return ordinates.row(kPowellSabinOrdinates * f + s[q]);
      });
}

}  // namespace ricci
