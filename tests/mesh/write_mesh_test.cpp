// write_mesh: every format read back by read_mesh (same positions and faces), texture
// coordinates read back by read_textured_obj, the bytes of write_obj, and what it refuses.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

fs::path write_tmp_dir() {
  return testing::suite_tmp_dir("write_mesh");
}

std::string path_of(const std::string& name) {
  return (write_tmp_dir() / name).string();
}

/// path_of with no file there yet (a previous run's is removed), for the tests of refusals.
std::string fresh_path_of(const std::string& name) {
  fs::remove(path_of(name));
  return path_of(name);
}

TexturedMesh plain(const Mesh& mesh) {
  TexturedMesh textured;
  textured.mesh = mesh;
  return textured;
}

/// A grid with texture coordinates: its positions scaled, one uv per vertex (no seams).
TexturedMesh textured_grid() {
  TexturedMesh textured = plain(make_grid(4, 3, 1.5, 1.0));
  textured.uv_triangles = textured.mesh.triangles;
  textured.uv = textured.mesh.positions.leftCols(2) / 1.5;
  return textured;
}

/// The message of the InvalidInput that write_mesh throws, or "" when it throws none.
std::string refusal(const std::string& path, const TexturedMesh& mesh,
                    const WriteOptions& options = {}) {
  try {
    write_mesh(path, mesh, options);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(WriteMesh, ObjOffAndPlyReadBackExactly) {
  const Mesh torus = make_torus(9, 5, 1.0, 0.3);  // irrational coordinates: 17 digits matter
  for (const std::string name : {"torus.obj", "torus.off", "torus.ply", "TORUS.PLY"}) {
    const std::string path = path_of(name);
    write_mesh(path, plain(torus));
    const ReadResult read = read_mesh(path);
    EXPECT_EQ(read.mesh.positions, torus.positions) << name;
    EXPECT_EQ(read.mesh.triangles, torus.triangles) << name;
    EXPECT_EQ(read.file_vertices, torus.num_vertices()) << name;
  }
  EXPECT_EQ(read_mesh(path_of("torus.off")).format, MeshFormat::Off);
  EXPECT_EQ(read_mesh(path_of("torus.ply")).format, MeshFormat::Ply);
}

TEST(WriteMesh, StlReadsBackTheSameCornersInFloat) {
  Mesh sphere = make_icosphere(2);
  // STL stores float: positions that are floats already come back exactly.
  sphere.positions = sphere.positions.cast<float>().cast<double>();
  const std::string path = path_of("sphere.stl");
  write_mesh(path, plain(sphere));
  EXPECT_EQ(fs::file_size(path), 84u + 50u * sphere.num_faces());  // binary STL
  const ReadResult read = read_mesh(path);
  EXPECT_EQ(read.format, MeshFormat::Stl);
  ASSERT_EQ(read.mesh.num_faces(), sphere.num_faces());
  EXPECT_EQ(read.mesh.num_vertices(), sphere.num_vertices());  // corners welded again
  for (int f = 0; f < sphere.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(read.mesh.positions.row(read.mesh.triangles(f, c)),
                sphere.positions.row(sphere.triangles(f, c)))
          << "face " << f << " corner " << c;
    }
  }
}

TEST(WriteMesh, FormatOptionOverridesTheExtension) {
  const Mesh tetrahedron = make_tetrahedron();
  WriteOptions options;
  options.format = MeshFormat::Off;
  const std::string path = path_of("tetrahedron.txt");
  write_mesh(path, plain(tetrahedron), options);
  EXPECT_EQ(testing::read_text_file(path).substr(0, 4), "OFF\n");
  EXPECT_THROW(write_mesh(path, plain(tetrahedron)), IoError);  // .txt: no format
}

TEST(WriteMesh, ObjWithTextureCoordinatesIsWhatWriteObjWritesAndReadsBack) {
  const TexturedMesh grid = textured_grid();
  WriteOptions options;
  options.material.library = "grid.mtl";
  write_mesh(path_of("grid_mesh.obj"), grid, options);
  write_obj(path_of("grid_obj.obj"), grid.mesh, grid.uv_triangles, grid.uv, options.material);
  EXPECT_EQ(testing::read_text_file(path_of("grid_mesh.obj")),
            testing::read_text_file(path_of("grid_obj.obj")));
  EXPECT_NE(testing::read_text_file(path_of("grid_mesh.obj")).find("mtllib grid.mtl\n"),
            std::string::npos);

  const TexturedMesh back = read_textured_obj(path_of("grid_mesh.obj"));
  EXPECT_EQ(back.mesh.positions, grid.mesh.positions);
  EXPECT_EQ(back.mesh.triangles, grid.mesh.triangles);
  EXPECT_EQ(back.uv_triangles, grid.uv_triangles);
  EXPECT_EQ(back.uv, grid.uv);  // shortest round-trip digits: exact
  EXPECT_EQ(back.uv_weights.size(), 0);

  // Without texture coordinates: write_obj's plain OBJ.
  write_mesh(path_of("plain_mesh.obj"), plain(grid.mesh));
  write_obj(path_of("plain_obj.obj"), grid.mesh);
  EXPECT_EQ(testing::read_text_file(path_of("plain_mesh.obj")),
            testing::read_text_file(path_of("plain_obj.obj")));
}

TEST(WriteMesh, ObjKeepsHomogeneousTextureCoordinates) {
  TexturedMesh grid = textured_grid();
  grid.uv_weights.resize(grid.uv.rows());
  for (Eigen::Index t = 0; t < grid.uv.rows(); ++t) grid.uv_weights[t] = 0.5 + 0.25 * t;
  write_mesh(path_of("grid_uvw.obj"), grid);
  const TexturedMesh back = read_textured_obj(path_of("grid_uvw.obj"));
  ASSERT_EQ(back.uv_weights.size(), grid.uv.rows());
  EXPECT_EQ(back.uv_weights, grid.uv_weights);  // w written as it is
  // (u w) / w: one rounding of the product, one of the quotient.
  EXPECT_LE((back.uv - grid.uv).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(WriteMesh, RefusesTextureCoordinatesAFormatCannotHoldUnlessDropped) {
  const TexturedMesh grid = textured_grid();
  for (const std::string name : {"grid.off", "grid.ply", "grid.stl"}) {
    const std::string message = refusal(fresh_path_of(name), grid);
    EXPECT_NE(message.find("write_mesh: " + path_of(name)), std::string::npos) << message;
    EXPECT_NE(message.find("drop_uv"), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(path_of(name)));
  }
  WriteOptions drop;
  drop.drop_uv = true;
  write_mesh(path_of("grid.off"), grid, drop);
  EXPECT_EQ(read_mesh(path_of("grid.off")).mesh.triangles, grid.mesh.triangles);
}

TEST(WriteMesh, GlbNeedsTheWriterOfThePictureLibrary) {
  const TexturedMesh grid = textured_grid();
  const std::string message = refusal(fresh_path_of("grid.glb"), grid);
  EXPECT_NE(message.find("glb_writer"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(path_of("grid.glb")));
  // With a writer, write_mesh hands it the checked mesh.
  WriteOptions options;
  int calls = 0;
  options.glb_writer = [&](const std::string& path, const TexturedMesh& mesh) {
    EXPECT_EQ(path, path_of("grid.glb"));
    EXPECT_EQ(mesh.uv, grid.uv);
    ++calls;
  };
  write_mesh(path_of("grid.glb"), grid, options);
  EXPECT_EQ(calls, 1);
  EXPECT_NE(refusal(path_of("plain.glb"), plain(grid.mesh), options).find("texture coordinates"),
            std::string::npos);
}

TEST(WriteMesh, RefusesBadArraysNamingTheElement) {
  TexturedMesh grid = textured_grid();
  grid.uv_triangles(2, 1) = static_cast<int>(grid.uv.rows());
  EXPECT_NE(refusal(fresh_path_of("bad_uv.obj"), grid).find("face 2 corner 1: uv index"),
            std::string::npos);
  grid = textured_grid();
  grid.mesh.triangles(3, 0) = -1;
  EXPECT_NE(refusal(fresh_path_of("bad_vertex.off"), plain(grid.mesh)).find("face 3 corner 0"),
            std::string::npos);
  grid = textured_grid();
  grid.mesh.positions(5, 2) = std::nan("");
  EXPECT_NE(refusal(fresh_path_of("nan.ply"), plain(grid.mesh)).find("vertex 5"),
            std::string::npos);
  grid = textured_grid();
  grid.uv_weights = Eigen::VectorXd::Zero(grid.uv.rows());
  EXPECT_NE(refusal(fresh_path_of("zero_w.obj"), grid).find("uv weight 0"), std::string::npos);
  WriteOptions material;
  material.material.library = "m.mtl";
  EXPECT_NE(refusal(fresh_path_of("material.obj"), plain(grid.mesh), material).find("material"),
            std::string::npos);
  for (const char* name :
       {"bad_uv.obj", "bad_vertex.off", "nan.ply", "zero_w.obj", "material.obj"}) {
    EXPECT_FALSE(fs::exists(path_of(name))) << name;
  }
}

TEST(WriteMesh, UnwritablePathIsAnIoErrorNamingIt) {
  const std::string path = path_of("no_such_folder/mesh.ply");
  try {
    write_mesh(path, plain(make_tetrahedron()));
    FAIL() << "no exception";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ricci
