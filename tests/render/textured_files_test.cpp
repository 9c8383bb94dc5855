// Textured files other tools open: the checkerboard, the OBJ's material library, glTF binary
// (read back with tinygltf, the library that wrote it, as a viewer would).
#include "ricci/render/textured_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/param/output_mesh.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/render/render_mesh.hpp"

#ifdef RICCI_HAVE_GLTF
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>
#endif

namespace ricci {
namespace {

namespace fs = std::filesystem;

/// write_mesh's options with the glTF writer of the picture library.
[[maybe_unused]] WriteOptions glb_options(const GlbOptions& glb = {}) {
  WriteOptions options;
  options.glb_writer = glb_writer(glb);
  return options;
}

TEST(TexturedFiles, CheckerboardSquaresStartLightAtTheOrigin) {
  const Image image = checkerboard_texture(64, 4);
  ASSERT_EQ(image.width, 64);
  const RenderOptions colours;
  const std::uint32_t light = pack_rgb(colours.checker_light);
  const std::uint32_t dark = pack_rgb(colours.checker_dark);
  // uv (0, 0) is the bottom left pixel; squares of 16 pixels alternate from there.
  EXPECT_EQ(image.at(0, 63), light);
  EXPECT_EQ(image.at(16, 63), dark);
  EXPECT_EQ(image.at(0, 47), dark);
  EXPECT_EQ(image.at(16, 47), light);
  EXPECT_EQ(image.at(63, 0), light);  // (3 + 3) even
  // Squares that do not divide the pixels: pixel (x, y) is in column floor(x N / P) and row
  // floor((P - 1 - y) N / P), as render_mesh counts them.
  const Image odd = checkerboard_texture(100, 7);
  for (int y = 0; y < 100; ++y) {
    for (int x = 0; x < 100; ++x) {
      const int parity = (x * 7 / 100 + (99 - y) * 7 / 100) & 1;
      ASSERT_EQ(odd.at(x, y), parity ? dark : light) << x << ", " << y;
    }
  }
  EXPECT_THROW(checkerboard_texture(4, 2), InvalidInput);
  EXPECT_THROW(checkerboard_texture(64, 0), InvalidInput);
}

TEST(TexturedFiles, TheMaterialLibraryNamesItsTexture) {
  const fs::path dir = testing::render_tmp_dir() / "material";
  fs::remove_all(dir);
  fs::create_directories(dir / "textures");
  const ObjMaterialFiles files = write_obj_material((dir / "mesh.obj").string());
  EXPECT_EQ(files.mtl, (dir / "mesh.mtl").string());
  EXPECT_EQ(files.library, "mesh.mtl");
  EXPECT_EQ(files.texture, (dir / "mesh.png").string());
  const std::string mtl = testing::read_text_file(files.mtl);
  EXPECT_NE(mtl.find("newmtl ricci_texture\n"), std::string::npos) << mtl;
  EXPECT_NE(mtl.find("map_Kd mesh.png\n"), std::string::npos) << mtl;
  const Image texture = read_png(files.texture);
  EXPECT_EQ(texture.width, 1024);
  EXPECT_EQ(texture.height, 1024);

  // A user's image is referred to where it is, relative to the OBJ.
  write_png((dir / "textures/brick.png").string(), checkerboard_texture(32, 2));
  fs::create_directories(dir / "out");
  const ObjMaterialFiles own =
      write_obj_material((dir / "out/m.obj").string(), (dir / "textures/brick.png").string());
  EXPECT_NE(testing::read_text_file(own.mtl).find("map_Kd ../textures/brick.png\n"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "out/m.png"));
  EXPECT_THROW(write_obj_material((dir / "out/n.obj").string(), (dir / "missing.png").string()),
               IoError);

  // The OBJ names the library and the material; the readers ignore both.
  Mesh mesh = make_disk(2);
  const MeshParamResult param = parameterize(mesh);
  write_obj((dir / "mesh.obj").string(), param.mesh, param.cut_mesh.triangles, param.uv,
            ObjMaterial{files.library});
  const std::string obj = testing::read_text_file(dir / "mesh.obj");
  EXPECT_EQ(obj.rfind("mtllib mesh.mtl\n", 0), 0u);
  EXPECT_NE(obj.find("usemtl ricci_texture\nf "), std::string::npos);
  EXPECT_EQ(read_mesh((dir / "mesh.obj").string()).mesh.num_faces(), mesh.num_faces());
}

#ifdef RICCI_HAVE_GLTF
/// Keeps an image's encoded bytes (no decoder: tinygltf is used without stb here).
bool keep_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  return true;
}

tinygltf::Model load_glb_model(const std::string& path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keep_bytes, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, path)) << error;
  EXPECT_TRUE(error.empty()) << error;
  return model;
}

template <class T>
const T* accessor_data(const tinygltf::Model& model, int accessor) {
  const tinygltf::Accessor& a = model.accessors[accessor];
  const tinygltf::BufferView& view = model.bufferViews[a.bufferView];
  return reinterpret_cast<const T*>(model.buffers[view.buffer].data.data() + view.byteOffset +
                                    a.byteOffset);
}

TEST(TexturedFiles, GlbHoldsTheMeshItsTextureCoordinatesAndTheTexture) {
  ASSERT_TRUE(glb_supported());
  const Mesh torus = make_torus(16, 8);
  const MeshParamResult param = parameterize(torus);  // a torus: seams, so vertices split
  const std::string path = (testing::render_tmp_dir() / "torus.glb").string();
  write_mesh(path, textured_mesh(param), glb_options());
  const tinygltf::Model model = load_glb_model(path);
  ASSERT_EQ(model.meshes.size(), 1u);
  ASSERT_EQ(model.meshes[0].primitives.size(), 1u);
  const tinygltf::Primitive& p = model.meshes[0].primitives[0];
  ASSERT_EQ(p.attributes.count("POSITION"), 1u);
  ASSERT_EQ(p.attributes.count("NORMAL"), 1u);
  ASSERT_EQ(p.attributes.count("TEXCOORD_0"), 1u);
  const int faces = torus.num_faces();
  EXPECT_EQ(model.accessors[p.indices].count, static_cast<std::size_t>(3 * faces));
  // One glTF vertex per distinct (vertex, uv) pair: more than the torus's vertices (seams), at
  // most its uv points.
  const std::size_t count = model.accessors[p.attributes.at("POSITION")].count;
  EXPECT_GT(count, static_cast<std::size_t>(torus.num_vertices()));
  EXPECT_LE(count, static_cast<std::size_t>(param.uv.rows()));
  // Every corner: position and (u, 1 - v) as written, in single precision.
  const auto* index = accessor_data<std::uint32_t>(model, p.indices);
  const auto* position = accessor_data<float>(model, p.attributes.at("POSITION"));
  const auto* texcoord = accessor_data<float>(model, p.attributes.at("TEXCOORD_0"));
  const auto* normal = accessor_data<float>(model, p.attributes.at("NORMAL"));
  double worst = 0;
  for (int f = 0; f < faces; ++f) {
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t i = index[3 * f + c];
      const int v = param.mesh.triangles(f, c), t = param.cut_mesh.triangles(f, c);
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(position[3 * i + k] - param.mesh.positions(v, k)));
      }
      worst = std::max(worst, std::abs(texcoord[2 * i] - param.uv(t, 0)));
      worst = std::max(worst, std::abs(texcoord[2 * i + 1] - (1 - param.uv(t, 1))));
      const double length = std::hypot(normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]);
      EXPECT_NEAR(length, 1.0, 1e-6);
    }
  }
  EXPECT_LT(worst, 1e-6);
  // The texture: the checkerboard's PNG bytes, the base colour of the one material.
  ASSERT_EQ(model.images.size(), 1u);
  EXPECT_EQ(model.images[0].mimeType, "image/png");
  ASSERT_GE(model.images[0].image.size(), 8u);
  EXPECT_EQ(std::string(model.images[0].image.begin(), model.images[0].image.begin() + 4),
            "\x89PNG");
  ASSERT_EQ(model.materials.size(), 1u);
  EXPECT_EQ(model.materials[0].pbrMetallicRoughness.baseColorTexture.index, 0);
  EXPECT_EQ(p.material, 0);
  ASSERT_EQ(model.accessors[p.attributes.at("POSITION")].minValues.size(), 3u);
}

TEST(TexturedFiles, GlbReadsBackWithItsSeamsWelded) {
  const Mesh torus = make_torus(16, 8);
  const MeshParamResult param = parameterize(torus);
  const std::string path = (testing::render_tmp_dir() / "torus_back.glb").string();
  write_mesh(path, textured_mesh(param), glb_options());
  const TexturedMesh back = read_textured_file(path);
  // The split seam vertices are one vertex again: the torus's own count and faces.
  EXPECT_EQ(back.mesh.num_vertices(), torus.num_vertices());
  ASSERT_EQ(back.mesh.num_faces(), torus.num_faces());
  double worst = 0;
  for (int f = 0; f < torus.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = back.mesh.triangles(f, c);
      worst = std::max(
          worst, (back.mesh.positions.row(v) - param.mesh.positions.row(param.mesh.triangles(f, c)))
                     .cwiseAbs()
                     .maxCoeff());
      worst = std::max(worst, (back.uv.row(back.uv_triangles(f, c)) -
                               param.uv.row(param.cut_mesh.triangles(f, c)))
                                  .cwiseAbs()
                                  .maxCoeff());
    }
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_THROW(ricci::read_glb((testing::render_tmp_dir() / "material/mesh.mtl").string()),
               IoError);
}

TEST(TexturedFiles, GlbRefusesWhatItCannotHold) {
  const Mesh disk = make_disk(2);
  const MeshParamResult param = parameterize(disk);
  const fs::path dir = testing::render_tmp_dir();
  std::ofstream(dir / "not_an_image.png") << "hello";
  GlbOptions options;
  options.texture_path = (dir / "not_an_image.png").string();
  EXPECT_THROW(write_mesh((dir / "x.glb").string(), textured_mesh(param), glb_options(options)),
               InvalidInput);
  TexturedMesh short_uv = textured_mesh(param);
  short_uv.uv_triangles = param.cut_mesh.triangles.topRows(2);
  EXPECT_THROW(write_mesh((dir / "x.glb").string(), short_uv, glb_options()), InvalidInput);
  EXPECT_FALSE(fs::exists(dir / "x.glb"));
}
#endif

}  // namespace
}  // namespace ricci
