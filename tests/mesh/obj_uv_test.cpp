// write_obj with per-corner texture coordinates: the file is parsed back by hand here, so that the
// test does not depend on the reader (which ignores vt).

#include <sys/resource.h>

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;
using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

fs::path uv_tmp_dir() {
  return testing::suite_tmp_dir("mesh_obj_uv");
}

/// The v, vt and f lines of an OBJ file written by write_obj, 0-based.
struct ParsedObj {
  std::vector<std::vector<double>> positions, texture_coordinates;
  std::vector<std::vector<int>> vertex_indices, uv_indices;
  int other_lines = 0;
};

ParsedObj parse_by_hand(const std::string& path) {
  ParsedObj parsed;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string keyword;
    fields >> keyword;
    if (keyword == "v" || keyword == "vt") {
      std::vector<double> row;
      std::string number;
      // strtod reads the shortest round-trip text back to the same double.
      while (fields >> number) row.push_back(std::strtod(number.c_str(), nullptr));
      (keyword == "v" ? parsed.positions : parsed.texture_coordinates).push_back(row);
    } else if (keyword == "f") {
      std::vector<int> vertices, uvs;
      std::string corner;
      while (fields >> corner) {
        const std::size_t slash = corner.find('/');
        EXPECT_NE(slash, std::string::npos) << "corner without a texture index: " << line;
        EXPECT_EQ(corner.find('/', slash + 1), std::string::npos) << "unexpected normal: " << line;
        vertices.push_back(std::stoi(corner.substr(0, slash)) - 1);
        uvs.push_back(std::stoi(corner.substr(slash + 1)) - 1);
      }
      parsed.vertex_indices.push_back(vertices);
      parsed.uv_indices.push_back(uvs);
    } else {
      ++parsed.other_lines;
    }
  }
  return parsed;
}

/// A tetrahedron whose coordinates need all 17 digits, cut open along three edges from vertex 0:
/// its 4 faces use 6 uv rows, so some corners share a uv index and others do not.
struct CutTetrahedron {
  Mesh mesh;
  Triangles uv_triangles;
  UV uv;
};

CutTetrahedron cut_tetrahedron() {
  CutTetrahedron t;
  t.mesh.positions.resize(4, 3);
  t.mesh.positions << 0.1, 1.0 / 3.0, std::numbers::pi, -1e-300, 2.5e17, 7.0 / 9.0, 1, -1, -1,
      std::sqrt(2.0), -1, 1e-5;
  t.mesh.triangles.resize(4, 3);
  t.mesh.triangles << 0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2;
  t.uv.resize(6, 2);
  t.uv << 1.0 / 7.0, -2.0 / 3.0, 0.5, 0.25, 1e-310, std::numbers::e, -3.5, 1e20, 0.1, 0.2, 0.3,
      -0.4;
  // Vertex 0 has three copies (uv 0, 4, 5); vertices 1, 2, 3 one each (uv 1, 2, 3).
  t.uv_triangles.resize(4, 3);
  t.uv_triangles << 0, 1, 2, 4, 2, 3, 5, 3, 1, 1, 3, 2;
  return t;
}

TEST(ObjUv, ParsedBackByHandIsExact) {
  const CutTetrahedron t = cut_tetrahedron();
  const std::string path = (uv_tmp_dir() / "tetrahedron_uv.obj").string();
  write_obj(path, t.mesh, t.uv_triangles, t.uv);

  const ParsedObj parsed = parse_by_hand(path);
  EXPECT_EQ(parsed.other_lines, 0);
  ASSERT_EQ(parsed.positions.size(), 4u);
  for (int v = 0; v < 4; ++v) {
    ASSERT_EQ(parsed.positions[v].size(), 3u);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(parsed.positions[v][k], t.mesh.positions(v, k));
  }
  ASSERT_EQ(parsed.texture_coordinates.size(), 6u);  // one vt per uv row, none per corner
  for (int r = 0; r < 6; ++r) {
    ASSERT_EQ(parsed.texture_coordinates[r].size(), 2u);
    for (int k = 0; k < 2; ++k) EXPECT_EQ(parsed.texture_coordinates[r][k], t.uv(r, k));
  }
  ASSERT_EQ(parsed.vertex_indices.size(), 4u);
  for (int f = 0; f < 4; ++f) {
    ASSERT_EQ(parsed.vertex_indices[f].size(), 3u);
    ASSERT_EQ(parsed.uv_indices[f].size(), 3u);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(parsed.vertex_indices[f][c], t.mesh.triangles(f, c));
      EXPECT_EQ(parsed.uv_indices[f][c], t.uv_triangles(f, c));
    }
  }
}

TEST(ObjUv, LinesHaveTheDocumentedForm) {
  const CutTetrahedron t = cut_tetrahedron();
  const std::string path = (uv_tmp_dir() / "tetrahedron_lines.obj").string();
  write_obj(path, t.mesh, t.uv_triangles, t.uv);
  std::istringstream lines(testing::read_text_file(path));
  std::string line;
  for (int i = 0; i < 4; ++i) std::getline(lines, line);
  std::getline(lines, line);
  EXPECT_EQ(line, "vt 0.14285714285714285 -0.6666666666666666");
  for (int i = 0; i < 5; ++i) std::getline(lines, line);
  std::getline(lines, line);
  EXPECT_EQ(line, "f 1/1 2/2 3/3");
  std::getline(lines, line);
  EXPECT_EQ(line, "f 1/5 3/3 4/4");
}

TEST(ObjUv, CornersSharingAUvIndexShareTheVt) {
  // A grid laid out as itself: every vertex has one uv row, so corners of a vertex share one vt.
  const Mesh grid = make_grid(3, 2, 1.5, 1.0);
  UV uv = grid.positions.leftCols<2>();
  const std::string path = (uv_tmp_dir() / "grid_uv.obj").string();
  write_obj(path, grid, grid.triangles, uv);
  const ParsedObj parsed = parse_by_hand(path);
  ASSERT_EQ(parsed.texture_coordinates.size(), static_cast<std::size_t>(grid.num_vertices()));
  ASSERT_EQ(parsed.uv_indices.size(), static_cast<std::size_t>(grid.num_faces()));
  for (int f = 0; f < grid.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      // Same vertex, same vt index, and that vt is the vertex's own position.
      EXPECT_EQ(parsed.uv_indices[f][c], parsed.vertex_indices[f][c]);
      const std::vector<double>& vt = parsed.texture_coordinates[parsed.uv_indices[f][c]];
      EXPECT_EQ(vt[0], grid.positions(grid.triangles(f, c), 0));
      EXPECT_EQ(vt[1], grid.positions(grid.triangles(f, c), 1));
    }
  }
}

TEST(ObjUv, ReaderIgnoresVtAndReadsTheSameMesh) {
  const Mesh sphere = make_icosphere(1);
  // Per-corner uv: every corner its own row (a triangle soup in the plane).
  Triangles uv_triangles(sphere.num_faces(), 3);
  UV uv(3 * sphere.num_faces(), 2);
  for (int f = 0; f < sphere.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      uv_triangles(f, c) = 3 * f + c;
      uv.row(3 * f + c) << f + 0.25 * c, 1.0 / (f + 1.0 + c);
    }
  }
  const std::string path = (uv_tmp_dir() / "icosphere_uv.obj").string();
  write_obj(path, sphere, uv_triangles, uv);
  const ReadResult result = read_mesh(path);
  EXPECT_EQ(result.mesh.positions, sphere.positions);
  EXPECT_EQ(result.mesh.triangles, sphere.triangles);
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_EQ(parse_by_hand(path).texture_coordinates.size(), uv.rows());
}

TEST(ObjUv, SizeMismatchesAreInvalidInputAndWriteNothing) {
  const CutTetrahedron t = cut_tetrahedron();
  const std::string path = (uv_tmp_dir() / "never_written.obj").string();
  fs::remove(path);
  auto message_of = [&](const Triangles& uv_triangles, const UV& uv) -> std::string {
    try {
      write_obj(path, t.mesh, uv_triangles, uv);
    } catch (const IoError& e) {
      ADD_FAILURE() << "IoError instead of InvalidInput: " << e.what();
    } catch (const InvalidInput& e) {
      return e.what();
    }
    ADD_FAILURE() << "no exception";
    return "";
  };
  const std::string rows = message_of(t.uv_triangles.topRows(3), t.uv);
  EXPECT_NE(rows.find("write_obj"), std::string::npos) << rows;
  EXPECT_NE(rows.find("3 rows but the mesh has 4 faces"), std::string::npos) << rows;

  Triangles out_of_range = t.uv_triangles;
  out_of_range(2, 1) = 6;
  const std::string index = message_of(out_of_range, t.uv);
  EXPECT_NE(index.find("face 2 corner 1: uv index 6 is out of range [0, 6)"), std::string::npos)
      << index;
  out_of_range(2, 1) = -1;
  EXPECT_NE(message_of(out_of_range, t.uv).find("uv index -1"), std::string::npos);

  UV not_finite = t.uv;
  not_finite(4, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message_of(t.uv_triangles, not_finite).find("uv row 4 is not finite"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(path));
}

/// For the death test's child: limits the size of files this process may write, so that writes
/// beyond it fail with EFBIG (SIGXFSZ ignored), then exits 0 when write_obj throws IoError.
[[noreturn]] void write_with_file_size_limit(const std::string& path, const Mesh& mesh,
                                             const UV& uv, rlim_t bytes) {
  std::signal(SIGXFSZ, SIG_IGN);
  const rlimit limit{bytes, bytes};
  if (setrlimit(RLIMIT_FSIZE, &limit) != 0) std::_Exit(2);
  try {
    write_obj(path, mesh, mesh.triangles, uv);
  } catch (const IoError&) {
    std::_Exit(0);
  }
  std::_Exit(1);
}

TEST(ObjUv, FailingWriteLeavesTheExistingFileUntouched) {
  const fs::path folder = uv_tmp_dir() / "failing_write";
  fs::remove_all(folder);
  fs::create_directories(folder);
  const std::string path = (folder / "keep.obj").string();
  {
    std::ofstream out(path, std::ios::binary);
    out << "old content\n";
  }
  const Mesh grid = make_grid(40, 40);
  const UV uv = grid.positions.leftCols<2>();

  // Invalid input is caught before anything is written.
  EXPECT_THROW(write_obj(path, grid, grid.triangles.topRows(5), uv), InvalidInput);
  EXPECT_EQ(testing::read_text_file(path), "old content\n");

  // A real I/O failure half-way: in a child process, files may grow to 4 KiB only (the grid's
  // file is about 100 KiB), so writing the temporary fails with EFBIG. The child exits 0 only
  // when write_obj reported that as an IoError.
  EXPECT_EXIT(write_with_file_size_limit(path, grid, uv, 4096), ::testing::ExitedWithCode(0), "");
  EXPECT_EQ(testing::read_text_file(path), "old content\n");
  // No temporary is left behind either.
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);

  // And the same write succeeds without the limit, replacing the file.
  write_obj(path, grid, grid.triangles, uv);
  EXPECT_EQ(parse_by_hand(path).texture_coordinates.size(),
            static_cast<std::size_t>(grid.num_vertices()));
}

}  // namespace
}  // namespace ricci
