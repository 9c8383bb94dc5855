// textured_mesh(ParamResult): what `ricci param` writes, consistent with the cut and the layout,
// and the OBJ that write_mesh makes of it read back by read_textured_obj.

#include "ricci/param/output_mesh.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

TEST(OutputMesh, TorusCornersIndexTheCutMeshUv) {
  const MeshParamResult result = parameterize(make_torus(16, 8));
  ASSERT_TRUE(result.converged) << result.message;
  const TexturedMesh textured = textured_mesh(result);
  EXPECT_EQ(textured.mesh.positions, result.mesh.positions);
  EXPECT_EQ(textured.mesh.triangles, result.mesh.triangles);
  // One uv per vertex of the cut mesh: more than the torus' vertices, since the cut splits them.
  EXPECT_EQ(textured.uv.rows(), static_cast<Eigen::Index>(result.cut_mesh.to_original.size()));
  EXPECT_GT(textured.uv.rows(), textured.mesh.num_vertices());
  EXPECT_EQ(textured.uv_weights.size(), 0);
  ASSERT_EQ(textured.uv_triangles.rows(), textured.mesh.num_faces());
  for (int f = 0; f < textured.mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      // Each corner's uv belongs to a copy of the corner's own vertex.
      EXPECT_EQ(result.cut_mesh.to_original[textured.uv_triangles(f, c)],
                textured.mesh.triangles(f, c));
    }
  }

  const fs::path folder = testing::suite_tmp_dir("output_mesh");
  write_mesh((folder / "torus.obj").string(), textured);
  // The bytes the CLI wrote before write_mesh: write_obj of the same arrays.
  write_obj((folder / "torus_write_obj.obj").string(), result.mesh, result.cut_mesh.triangles,
            result.uv);
  EXPECT_EQ(testing::read_text_file(folder / "torus.obj"),
            testing::read_text_file(folder / "torus_write_obj.obj"));
  const TexturedMesh back = read_textured_obj((folder / "torus.obj").string());
  EXPECT_EQ(back.uv.rows(), textured.uv.rows());
  EXPECT_EQ(back.uv, textured.uv);
  EXPECT_EQ(back.uv_triangles, textured.uv_triangles);
  EXPECT_EQ(back.mesh.triangles, textured.mesh.triangles);
}

TEST(OutputMesh, NoLayoutGivesNoTextureCoordinates) {
  ParamResult result;
  result.mesh = make_tetrahedron();
  const TexturedMesh textured = textured_mesh(result);
  EXPECT_FALSE(textured.has_uv());
  EXPECT_EQ(textured.mesh.triangles, result.mesh.triangles);
}

}  // namespace
}  // namespace ricci
