// The pictures of `ricci param --pictures`: every file written, readable, of the requested size.

#include <gtest/gtest.h>

#include <filesystem>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/render/param_pictures.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

TEST(ParamPictures, WritesEveryFileIntoANewFolder) {
  ParamOptions param;
  param.cone_mode = ConeMode::None;
  const MeshParamResult result = parameterize(make_torus(24, 12), param);
  ASSERT_TRUE(result.converged) << result.message;

  const fs::path folder = testing::render_tmp_dir() / "param_pictures" / "nested";
  fs::remove_all(folder.parent_path());
  ParamPicturesOptions options;
  options.render.width = options.render.height = 200;
  options.uv.width = options.uv.height = 240;
  options.convergence.width = 320;
  options.convergence.height = 200;
  options.gradient_max_iterations = 300;
  const ParamPicturesResult written =
      write_parameterization_pictures(folder.string(), result, options);
  // view.html besides the five pictures when this build has three.js.
  const std::size_t files = web_viewer_available() ? 6 : 5;
  ASSERT_EQ(written.files.size(), files);
  for (const std::string& file : written.files) EXPECT_TRUE(fs::is_regular_file(file)) << file;
  EXPECT_EQ(read_png((folder / "render.png").string()).width, 200);
  EXPECT_EQ(read_png((folder / "uv.png").string()).height, 240);
  const Image plot = read_png((folder / "convergence.png").string());
  EXPECT_EQ(plot.width, 320);
  EXPECT_EQ(plot.height, 200);
  const std::string svg = testing::read_text_file(folder / "uv.svg");
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_GE(testing::count_occurrences(svg, "<path"), result.mesh.num_faces());
  EXPECT_NE(testing::read_text_file(folder / "convergence.svg").find("</svg>"), std::string::npos);
  // 288 vertices: the gradient flow ran, and stopped at its iteration limit or converged.
  EXPECT_TRUE(written.gradient_ran);
  EXPECT_GT(written.gradient_iterations, 0);
  EXPECT_LE(written.gradient_iterations, 300);
  if (web_viewer_available()) {
    const std::string page = testing::read_text_file(folder / "view.html");
    EXPECT_NE(page.find("\"format\": \"ricci-viewer-1\""), std::string::npos);
    EXPECT_NE(page.find("\"faces\": " + std::to_string(result.mesh.num_faces())),
              std::string::npos);
  }
  // Nothing but those files (no temporary files left behind).
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++entries;
  EXPECT_EQ(entries, files);
}

TEST(ParamPictures, SkipsTheGradientFlowOnLargeMeshes) {
  ParamOptions param;
  param.cone_mode = ConeMode::None;
  const MeshParamResult result = parameterize(make_torus(24, 12), param);
  ASSERT_TRUE(result.converged) << result.message;
  ParamPicturesOptions options;
  options.render.width = options.render.height = 64;
  options.uv.width = options.uv.height = 64;
  options.convergence.width = options.convergence.height = 64;
  options.gradient_max_vertices = 100;
  const ParamPicturesResult written = write_parameterization_pictures(
      (testing::render_tmp_dir() / "param_pictures_small").string(), result, options);
  EXPECT_FALSE(written.gradient_ran);
  EXPECT_EQ(written.files.size(), web_viewer_available() ? 6u : 5u);
}

TEST(ParamPictures, FlatMeshWritesItsPictures) {
  // A flat grid is flat from the start: the flow's error is 0 or round-off; whichever it is,
  // the pictures that can be drawn are written and nothing throws.
  ParamOptions param;
  param.cone_mode = ConeMode::None;
  const MeshParamResult result = parameterize(make_grid(6, 4, 1.5, 1.0), param);
  ASSERT_TRUE(result.converged) << result.message;
  ParamPicturesOptions options;
  options.render.width = options.render.height = 64;
  options.uv.width = options.uv.height = 64;
  options.convergence.width = options.convergence.height = 64;
  const ParamPicturesResult written = write_parameterization_pictures(
      (testing::render_tmp_dir() / "param_pictures_flat").string(), result, options);
  EXPECT_GE(written.files.size(), 3u);
  EXPECT_LE(written.files.size(), 6u);
}

TEST(ParamPictures, RefusesAResultWithoutLayout) {
  EXPECT_THROW(write_parameterization_pictures(
                   (testing::render_tmp_dir() / "param_pictures_none").string(), MeshParamResult{}),
               InvalidInput);
}

}  // namespace
}  // namespace ricci
