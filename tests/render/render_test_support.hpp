#pragma once
// Shared by the picture tests: a scratch folder and small textured meshes.

#include <cmath>
#include <filesystem>
#include <string>

#include "ricci/mesh/generate.hpp"
#include "support/shared_meshes.hpp"

namespace ricci::testing {

inline std::filesystem::path render_tmp_dir() {
  const std::filesystem::path folder = std::filesystem::path(test_tmp_dir()) / "render";
  std::filesystem::create_directories(folder);
  return folder;
}

/// Number of non-overlapping occurrences of `needle` in `text`.
inline int count_occurrences(const std::string& text, const std::string& needle) {
  int count = 0;
  for (std::size_t at = text.find(needle); at != std::string::npos;
       at = text.find(needle, at + needle.size())) {
    ++count;
  }
  return count;
}

/// A mesh with texture coordinates: `uv_triangles` (#F by 3) index the rows of `uv`.
struct TexturedMesh {
  Mesh mesh;
  Triangles uv_triangles;
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
};

/// A flat grid of the unit square with texture coordinates equal to (x, y), one per vertex.
inline TexturedMesh grid_with_uv(int n) {
  TexturedMesh g;
  g.mesh = make_grid(n, n, 1.0, 1.0);
  g.uv_triangles = g.mesh.triangles;
  g.uv = g.mesh.positions.leftCols(2);
  return g;
}

/// A square pyramid without its base: apex 0 at (0, 0, 1), base 1..4. The layout unrolls the
/// four faces around the apex with corner angles `angle`, cut along the edge apex-1 (vertex 1 has
/// two texture copies).
inline TexturedMesh unrolled_pyramid(double angle) {
  TexturedMesh p;
  p.mesh.positions.resize(5, 3);
  p.mesh.positions << 0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0;
  p.mesh.triangles.resize(4, 3);
  p.mesh.triangles << 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1;
  p.uv.resize(6, 2);
  p.uv.row(0) << 0, 0;
  for (int k = 0; k < 5; ++k) p.uv.row(k + 1) << std::cos(k * angle), std::sin(k * angle);
  p.uv_triangles.resize(4, 3);
  p.uv_triangles << 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5;
  return p;
}

}  // namespace ricci::testing
