// The OBJ reader with texture coordinates: what it reads and what it refuses, with file and line.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

std::filesystem::path textured_tmp_dir() {
  return testing::suite_tmp_dir("textured_obj");
}

std::string write_file(const std::string& name, const std::string& content) {
  return testing::write_text_file(textured_tmp_dir() / name, content);
}

/// Reads one triangle, corners (0, 0, 0), (1, 0, 0), (0, 1, 0), whose corners take the three
/// texture coordinates of `vt_lines` in order.
TexturedMesh read_triangle_with_vt(const std::string& name, const std::string& vt_lines) {
  return read_textured_obj(
      write_file(name, "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + vt_lines + "f 1/1 2/2 3/3\n"));
}

/// The message of the exception E that reading `content` throws (fails when none is thrown).
template <class E>
std::string error_of(const std::string& name, const std::string& content) {
  const std::string path = write_file(name, content);
  try {
    read_textured_obj(path);
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << name << ": no exception of the expected type";
  return {};
}

TEST(TexturedObj, ReadsVerticesTextureCoordinatesAndCorners) {
  const std::string path = write_file("square.obj",
                                      "# a square as two triangles and one quad\n"
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1 0.5\n"
                                      "vn 0 0 1\n"
                                      "g square\nusemtl none\ns off\n"
                                      "f 1/1/1 2/2/1 3/3/1\n"
                                      "f -4/-4 -2/-2 -1/-1\n"
                                      "f 1/1 2/2 3/3 4/4\n");
  const TexturedMesh t = read_textured_obj(path);
  ASSERT_EQ(t.mesh.num_vertices(), 4);
  ASSERT_EQ(t.mesh.num_faces(), 4);  // the quad becomes two triangles
  ASSERT_EQ(t.uv.rows(), 4);
  EXPECT_EQ(t.polygons_triangulated, 1);
  EXPECT_EQ(t.mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(t.uv_triangles.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(t.mesh.triangles.row(3), Eigen::RowVector3i(0, 2, 3));
  EXPECT_DOUBLE_EQ(t.uv(3, 1), 1.0);
}

TEST(TexturedObj, ReadsWhatWriteObjWrites) {
  const Mesh grid = make_grid(3, 2, 1.5, 1.0);
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv = grid.positions.leftCols(2) * 0.25;
  const std::string path = (textured_tmp_dir() / "grid_uv.obj").string();
  write_obj(path, grid, grid.triangles, uv);
  const TexturedMesh t = read_textured_obj(path);
  EXPECT_EQ(t.mesh.positions, grid.positions);
  EXPECT_EQ(t.mesh.triangles, grid.triangles);
  EXPECT_EQ(t.uv_triangles, grid.triangles);
  EXPECT_EQ(t.uv, uv);  // written in shortest round-trip digits: exact
}

TEST(TexturedObj, ReadsHomogeneousTextureCoordinates) {
  // Every vt with a positive third component: (u / w, v / w) and the weights.
  const Mesh grid = make_grid(2, 1);
  Eigen::Matrix<double, Eigen::Dynamic, 3> uvw(grid.num_vertices(), 3);
  for (int v = 0; v < grid.num_vertices(); ++v) {
    const double w = 0.5 + v;
    uvw.row(v) << w * grid.positions(v, 0), w * grid.positions(v, 1), w;
  }
  const std::string path = (textured_tmp_dir() / "grid_uvw.obj").string();
  write_obj(path, grid, grid.triangles, uvw);
  const TexturedMesh t = read_textured_obj(path);
  ASSERT_EQ(t.uv_weights.size(), grid.num_vertices());
  for (int v = 0; v < grid.num_vertices(); ++v) {
    EXPECT_EQ(t.uv_weights[v], 0.5 + v);
    EXPECT_NEAR(t.uv(v, 0), grid.positions(v, 0), 1e-15);
    EXPECT_NEAR(t.uv(v, 1), grid.positions(v, 1), 1e-15);
  }
  // A third component of 0 (a common exporter habit) or missing on one vt: ordinary (u, v).
  const TexturedMesh zero = read_triangle_with_vt("zero_w.obj", "vt 0 0 0\nvt 1 0 0\nvt 0 1 0\n");
  EXPECT_EQ(zero.uv_weights.size(), 0);
  EXPECT_EQ(zero.uv(1, 0), 1.0);
  const TexturedMesh mixed = read_triangle_with_vt("mixed_w.obj", "vt 0 0 2\nvt 1 0\nvt 0 1 2\n");
  EXPECT_EQ(mixed.uv_weights.size(), 0);
  EXPECT_EQ(mixed.uv(2, 1), 1.0);
}

TEST(TexturedObj, MissingTextureCoordinateNamesFileAndLine) {
  const std::string message = error_of<InvalidInput>(
      "missing_vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n\nf 1/1 2/2 3/3\n");
  EXPECT_NE(message.find("missing_vt.obj"), std::string::npos) << message;
  EXPECT_NE(message.find("line 7"), std::string::npos) << message;
  EXPECT_NE(message.find("texture coordinate 3"), std::string::npos) << message;
}

TEST(TexturedObj, RefusesMalformedFilesWithFileAndLine) {
  struct Case {
    const char* name;
    const char* content;
    const char* line;
    const char* says;
  };
  const Case cases[] = {
      {"no_vt_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2 3\n", "line 5",
       "no texture coordinate index"},
      {"empty_vt_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1//1 2//1 3//1\n", "line 5",
       "no texture coordinate index"},
      {"bad_number.obj", "v 0 0 0\nv 1 zero 0\n", "line 2", "malformed number"},
      {"short_vt.obj", "v 0 0 0\nvt 0.5\n", "line 2", "vt needs 2 coordinates"},
      {"nan.obj", "v 0 0 nan\n", "line 1", "not finite"},
      {"two_corners.obj", "v 0 0 0\nv 1 0 0\nvt 0 0\nf 1/1 2/1\n", "line 4", "need at least 3"},
      {"unknown.obj", "v 0 0 0\nbogus 1 2\n", "line 2", "unsupported OBJ statement"},
      {"bad_corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/x 2/1 3/1\n", "line 5",
       "malformed face corner"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of<IoError>(c.name, c.content);
    EXPECT_NE(message.find(c.name), std::string::npos) << message;
    EXPECT_NE(message.find(c.line), std::string::npos) << message;
    EXPECT_NE(message.find(c.says), std::string::npos) << message;
  }
  const std::string vertex =
      error_of<InvalidInput>("missing_v.obj", "v 0 0 0\nv 1 0 0\nvt 0 0\nf 1/1 2/1 3/1\n");
  EXPECT_NE(vertex.find("line 4"), std::string::npos) << vertex;
  EXPECT_NE(vertex.find("vertex 3"), std::string::npos) << vertex;
  EXPECT_NE(error_of<IoError>("no_faces.obj", "v 0 0 0\n").find("no faces"), std::string::npos);
  EXPECT_THROW(read_textured_obj((textured_tmp_dir() / "absent.obj").string()), IoError);
}

}  // namespace
}  // namespace ricci
