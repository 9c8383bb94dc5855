// The web viewer page: the data block decodes back to the mesh, the layout and the per-face
// figures; the page is self-contained (three.js inlined with its licence notice, no external
// URL); titles cannot break out of their elements; bad input is refused. (That the page draws
// in a browser is tests/cli/viewer_test.sh's part, in headless Chromium.)

#include "ricci/render/web_viewer.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/param/distortion.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/render/uv_chart.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

std::vector<unsigned char> base64_decode(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> bytes;
  EXPECT_EQ(text.size() % 4, 0u);
  for (std::size_t i = 0; i + 3 < text.size(); i += 4) {
    std::uint32_t group = 0;
    int padding = 0;
    for (std::size_t j = 0; j < 4; ++j) {
      const int v = text[i + j] == '=' ? (++padding, 0) : value(text[i + j]);
      EXPECT_GE(v, 0) << "not base64: " << text[i + j];
      group = (group << 6) | static_cast<std::uint32_t>(v);
    }
    for (int j = 0; j < 3 - padding; ++j) bytes.push_back((group >> (16 - 8 * j)) & 0xff);
  }
  return bytes;
}

/// A typed array of the data block (little-endian, as the page reads it; the test machines
/// are little-endian too).
template <typename T>
std::vector<T> array(const nlohmann::json& data, const char* name) {
  const std::vector<unsigned char> bytes = base64_decode(data.at(name).get<std::string>());
  EXPECT_EQ(bytes.size() % sizeof(T), 0u) << name;
  std::vector<T> values(bytes.size() / sizeof(T));
  if (!values.empty()) {  // an empty array's data() may be null, which memcpy must not get
    std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  }
  return values;
}

nlohmann::json data_block(const std::string& page) {
  const std::string open = "<script id=\"ricci-data\" type=\"application/json\">";
  const std::size_t start = page.find(open);
  EXPECT_NE(start, std::string::npos);
  const std::size_t end = page.find("</script>", start);
  return nlohmann::json::parse(page.substr(start + open.size(), end - start - open.size()));
}

/// A grid of the unit square laid out as itself, sheared: area kept, angles distorted.
testing::TexturedMesh sheared_grid() {
  testing::TexturedMesh g = testing::grid_with_uv(4);
  for (Eigen::Index t = 0; t < g.uv.rows(); ++t) g.uv(t, 0) += 0.5 * g.uv(t, 1);
  return g;
}

/// What in a page would fetch something from elsewhere: elements that load by themselves, and
/// src or href attributes (or properties) and CSS url()s whose value starts with a scheme or //.
std::vector<std::string> external_references(const std::string& page) {
  std::string lower = page;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::vector<std::string> found;
  for (const char* element : {"<link", "<img", "<iframe", "<script src", "@import", "import("}) {
    if (lower.find(element) != std::string::npos) found.emplace_back(element);
  }
  for (const std::string key : {"src", "href", "url("}) {
    for (std::size_t at = lower.find(key); at != std::string::npos; at = lower.find(key, at + 1)) {
      std::size_t i = at + key.size();
      auto skip = [&](const char* what) {
        while (i < lower.size() && std::strchr(what, lower[i]) != nullptr) ++i;
      };
      if (key != "url(") {
        skip(" ");
        if (i >= lower.size() || lower[i] != '=') continue;
        ++i;
      }
      skip(" \"'");
      const std::string value = lower.substr(i, 8);
      for (const char* scheme : {"http:", "https:", "//", "ftp:", "file:"}) {
        if (value.rfind(scheme, 0) == 0) found.push_back(page.substr(at, 40));
      }
    }
  }
  return found;
}

class WebViewer : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!web_viewer_available()) GTEST_SKIP() << "built without three.js (libjs-three)";
  }
};

TEST_F(WebViewer, DataBlockDecodesToTheMeshAndItsFigures) {
  testing::TexturedMesh g = sheared_grid();
  g.mesh.positions.col(2).setConstant(100.0);  // far from the origin: sent relative to the centre
  WebViewerInfo info;
  const std::string page = web_viewer_html(g.mesh, g.uv_triangles, g.uv, {}, &info);
  EXPECT_EQ(info.bytes, page.size());
  EXPECT_EQ(info.vertices, 25);
  EXPECT_EQ(info.faces, 32);
  EXPECT_EQ(info.texture_coordinates, 25);
  EXPECT_FALSE(info.projective);
  // The grid's 16 boundary edges are its seams; no interior vertex is a cone.
  EXPECT_EQ(info.seam_edges, 16);
  EXPECT_EQ(info.seam_halfedges, 16);
  EXPECT_EQ(info.cones, 0);
  EXPECT_EQ(info.flipped_faces, 0);

  const nlohmann::json data = data_block(page);
  EXPECT_EQ(data.at("format"), "ricci-viewer-1");
  EXPECT_EQ(data.at("faces"), 32);
  EXPECT_EQ(data.at("vertices"), 25);
  EXPECT_EQ(data.at("projective"), false);
  EXPECT_EQ(data.at("colouring"), "checker");
  EXPECT_EQ(data.at("checker"), 16);
  const Eigen::Vector3d centre(0.5, 0.5, 100.0);
  for (int axis = 0; axis < 3; ++axis) EXPECT_DOUBLE_EQ(data.at("centre")[axis], centre[axis]);

  const auto positions = array<float>(data, "positions");
  ASSERT_EQ(positions.size(), 75u);
  for (int v = 0; v < 25; ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      // Floats of numbers below 1 in magnitude: within 2^-24 relative.
      EXPECT_NEAR(positions[3 * v + axis], g.mesh.positions(v, axis) - centre[axis], 1e-7);
    }
  }
  const auto triangles = array<std::uint32_t>(data, "triangles");
  const auto uv_triangles = array<std::uint32_t>(data, "uv_triangles");
  ASSERT_EQ(triangles.size(), 96u);
  ASSERT_EQ(uv_triangles.size(), 96u);
  for (int f = 0; f < 32; ++f) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(triangles[3 * f + c], static_cast<std::uint32_t>(g.mesh.triangles(f, c)));
      EXPECT_EQ(uv_triangles[3 * f + c], static_cast<std::uint32_t>(g.uv_triangles(f, c)));
    }
  }
  const auto uvw = array<float>(data, "uvw");
  ASSERT_EQ(uvw.size(), 75u);
  for (int t = 0; t < 25; ++t) {
    EXPECT_NEAR(uvw[3 * t], g.uv(t, 0), 1e-7);
    EXPECT_NEAR(uvw[3 * t + 1], g.uv(t, 1), 1e-7);
    EXPECT_EQ(uvw[3 * t + 2], 1.0f);
  }
  // The shear (u, v) -> (u + v / 2, v) keeps every area (ln ratio 0) and has the same singular
  // values on every face: sigma_max / sigma_min = (s + sqrt(s^2 + 4)) / (-s + sqrt(s^2 + 4))
  // with s = 1/2.
  const double root = std::sqrt(0.25 + 4.0);
  const double expected_angle = (0.5 + root) / (-0.5 + root);
  const auto log_area = array<float>(data, "log_area");
  const auto angle = array<float>(data, "angle");
  const auto flipped = array<std::uint8_t>(data, "flipped");
  ASSERT_EQ(log_area.size(), 32u);
  ASSERT_EQ(angle.size(), 32u);
  ASSERT_EQ(flipped.size(), 32u);
  for (int f = 0; f < 32; ++f) {
    EXPECT_NEAR(log_area[f], 0.0, 1e-6);
    EXPECT_NEAR(angle[f], expected_angle, 1e-6);
    EXPECT_EQ(flipped[f], 0);
  }
  EXPECT_NEAR(info.angle_range, expected_angle - 1, 1e-12);
  EXPECT_DOUBLE_EQ(data.at("angle_range"), info.angle_range);
  EXPECT_EQ(info.log_area_range, 1e-3);  // the floor: nothing to show
  // Seams: the boundary halfedges, each naming a side without a neighbour.
  const UvChart chart = analyse_uv_chart(g.mesh, g.uv_triangles, g.uv);
  const auto seams = array<std::uint32_t>(data, "seams");
  ASSERT_EQ(seams.size(), chart.seam_halfedges.size());
  for (std::size_t i = 0; i < seams.size(); ++i) {
    EXPECT_EQ(seams[i], static_cast<std::uint32_t>(chart.seam_halfedges[i]));
  }
  EXPECT_TRUE(array<std::uint32_t>(data, "cone_vertices").empty());
}

TEST_F(WebViewer, ConesOfAClosedSurfaceCarryItsWholeCurvature) {
  // A sphere parameterized with cones: flat everywhere else, so the cones' curvatures add up to
  // 2 pi chi = 4 pi (Gauss-Bonnet) up to the flow's tolerance.
  const MeshParamResult result = parameterize(make_icosphere(2), {});
  ASSERT_TRUE(result.converged) << result.message;
  WebViewerInfo info;
  const std::string page =
      web_viewer_html(result.mesh, result.cut_mesh.triangles, result.uv, {}, &info);
  const nlohmann::json data = data_block(page);
  const auto cones = array<std::uint32_t>(data, "cone_vertices");
  const auto curvatures = array<float>(data, "cone_curvatures");
  ASSERT_GT(cones.size(), 0u);
  EXPECT_EQ(static_cast<int>(cones.size()), info.cones);
  ASSERT_EQ(curvatures.size(), cones.size());
  double total = 0;
  for (float k : curvatures) total += k;
  EXPECT_NEAR(total, 4 * std::numbers::pi, 1e-5);  // float32 curvatures
  EXPECT_EQ(info.flipped_faces, result.distortion.flipped_faces);
  // The per-face figures are measure_face_distortion's, whose statistics the result reports.
  const FaceDistortion faces =
      measure_face_distortion(result.mesh, result.cut_mesh.triangles, result.uv);
  const auto angle = array<float>(data, "angle");
  double largest = 0;
  for (int f = 0; f < result.mesh.num_faces(); ++f) {
    EXPECT_FLOAT_EQ(angle[f], static_cast<float>(faces.angle[f]));
    largest = std::max(largest, faces.angle[f]);
  }
  EXPECT_NEAR(largest, result.distortion.angle_distortion_max, 1e-12);
}

TEST_F(WebViewer, ProjectiveTextureCoordinatesKeepTheirWeights) {
  const testing::TexturedMesh g = testing::grid_with_uv(3);
  WebViewerOptions options;
  options.uv_weights = Eigen::VectorXd::LinSpaced(g.uv.rows(), 0.5, 2.0);
  options.colouring = ViewerColouring::Angle;
  options.checker = 40;
  WebViewerInfo info;
  const std::string page = web_viewer_html(g.mesh, g.uv_triangles, g.uv, options, &info);
  EXPECT_TRUE(info.projective);
  const nlohmann::json data = data_block(page);
  EXPECT_EQ(data.at("projective"), true);
  EXPECT_EQ(data.at("colouring"), "angle");
  EXPECT_EQ(data.at("checker"), 40);
  const auto uvw = array<float>(data, "uvw");
  ASSERT_EQ(uvw.size(), 3u * g.uv.rows());
  for (Eigen::Index t = 0; t < g.uv.rows(); ++t) {
    EXPECT_NEAR(uvw[3 * t], g.uv(t, 0), 1e-7);  // divided by w, as TexturedMesh::uv
    EXPECT_FLOAT_EQ(uvw[3 * t + 2], static_cast<float>(options.uv_weights[t]));
  }
  // The page's surface shader divides the interpolated (w u, w v, w) by w.
  EXPECT_NE(page.find("vHomogeneous.xy / vHomogeneous.z"), std::string::npos);
}

TEST_F(WebViewer, PageIsSelfContainedAndKeepsTheLicenceNotice) {
  const testing::TexturedMesh g = testing::grid_with_uv(3);
  const std::string page = web_viewer_html(g.mesh, g.uv_triangles, g.uv);
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.find("</html>"), std::string::npos);
  EXPECT_EQ(page.find("@RICCI_"), std::string::npos);  // every placeholder filled in
  // three.js and OrbitControls are inline, under the MIT licence notice.
  EXPECT_NE(page.find("Permission is hereby granted, free of charge"), std::string::npos);
  EXPECT_NE(page.find("three.js authors"), std::string::npos);
  EXPECT_NE(page.find("REVISION=\""), std::string::npos);
  EXPECT_NE(page.find("OrbitControls"), std::string::npos);
  // Nothing is loaded from elsewhere.
  EXPECT_EQ(external_references(page), std::vector<std::string>{});
}

TEST_F(WebViewer, TitleCannotBreakOutOfItsElements) {
  const testing::TexturedMesh g = testing::grid_with_uv(2);
  WebViewerOptions options;
  options.title = "a<b & \"c\" </script><script>alert(1)</script>";
  const std::string page = web_viewer_html(g.mesh, g.uv_triangles, g.uv, options);
  EXPECT_NE(page.find("<title>a&lt;b &amp; &quot;c&quot; &lt;/script&gt;"), std::string::npos);
  EXPECT_EQ(page.find("alert(1)</script>"), std::string::npos);
  EXPECT_EQ(data_block(page).at("title"), options.title);
}

TEST_F(WebViewer, WritesThePageAtomically) {
  const testing::TexturedMesh g = sheared_grid();
  const std::filesystem::path folder = testing::render_tmp_dir() / "web_viewer";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  const std::string path = (folder / "view.html").string();
  const WebViewerInfo info = write_web_viewer(path, g.mesh, g.uv_triangles, g.uv);
  const std::string written = testing::read_text_file(path);
  EXPECT_EQ(written, web_viewer_html(g.mesh, g.uv_triangles, g.uv));
  EXPECT_EQ(info.bytes, written.size());
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder)) ++entries;
  EXPECT_EQ(entries, 1);  // no temporary file left
  EXPECT_THROW(
      write_web_viewer((folder / "missing" / "view.html").string(), g.mesh, g.uv_triangles, g.uv),
      IoError);
}

TEST_F(WebViewer, RefusesBadInput) {
  const testing::TexturedMesh g = testing::grid_with_uv(2);
  WebViewerOptions options;
  options.uv_weights = Eigen::VectorXd::Ones(3);  // not one per uv row
  EXPECT_THROW(web_viewer_html(g.mesh, g.uv_triangles, g.uv, options), InvalidInput);
  options.uv_weights = Eigen::VectorXd::Ones(g.uv.rows());
  options.uv_weights[1] = 0;
  EXPECT_THROW(web_viewer_html(g.mesh, g.uv_triangles, g.uv, options), InvalidInput);
  UV uv = g.uv;
  uv(2, 1) = std::nan("");
  EXPECT_THROW(web_viewer_html(g.mesh, g.uv_triangles, uv), InvalidInput);
  Triangles uv_triangles = g.uv_triangles;
  uv_triangles(0, 0) = 99;
  EXPECT_THROW(web_viewer_html(g.mesh, uv_triangles, g.uv), InvalidInput);
  WebViewerOptions checker;
  checker.checker = 0;
  EXPECT_THROW(web_viewer_html(g.mesh, g.uv_triangles, g.uv, checker), InvalidInput);
}

}  // namespace
}  // namespace ricci
