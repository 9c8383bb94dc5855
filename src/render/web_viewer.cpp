#include "ricci/render/web_viewer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/param/distortion.hpp"
#include "ricci/render/render_mesh.hpp"
#include "ricci/render/uv_chart.hpp"

namespace ricci {
namespace render_detail {
// The page template (src/render/web_viewer.html) and Debian's three.js files, embedded at build
// time by cmake/embed_files.cmake (web_viewer_assets.cpp in the build tree); the scripts are
// empty when CMake did not find them.
extern const unsigned char kViewerTemplate[], kThreeJs[], kOrbitControlsJs[];
extern const std::size_t kViewerTemplateSize, kThreeJsSize, kOrbitControlsJsSize;
}  // namespace render_detail

namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

std::string_view embedded(const unsigned char* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Writes bytes as base64 (RFC 4648, with padding), in blocks so that nothing large is held.
class Base64Writer {
 public:
  explicit Base64Writer(std::ostream& out) : out_(out) {}
  Base64Writer(const Base64Writer&) = delete;
  Base64Writer& operator=(const Base64Writer&) = delete;
  ~Base64Writer() = default;

  void write(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      pending_[pending_size_++] = bytes[i];
      if (pending_size_ == 3) emit(3);
    }
  }
  void finish() {
    if (pending_size_ > 0) emit(pending_size_);
    flush();
  }

 private:
  void emit(int count) {
    static constexpr char kAlphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = count; i < 3; ++i) pending_[i] = 0;
    const std::uint32_t group = (std::uint32_t{pending_[0]} << 16) |
                                (std::uint32_t{pending_[1]} << 8) | std::uint32_t{pending_[2]};
    for (int i = 0; i < 4; ++i) {
      block_[block_size_++] = i <= count ? kAlphabet[(group >> (18 - 6 * i)) & 63] : '=';
    }
    pending_size_ = 0;
    if (block_size_ + 4 > block_.size()) flush();
  }
  void flush() {
    out_.write(block_.data(), static_cast<std::streamsize>(block_size_));
    block_size_ = 0;
  }

  std::ostream& out_;
  std::array<unsigned char, 3> pending_{};
  int pending_size_ = 0;
  std::array<char, 1 << 16> block_{};
  std::size_t block_size_ = 0;
};

/// A typed array as a JSON string of its little-endian bytes in base64 (what the page decodes
/// into a Float32Array, Uint32Array or Uint8Array).
template <typename T, typename Value>
void write_array(std::ostream& out, const char* name, std::size_t count, const Value& value) {
  static_assert(sizeof(T) == 4 || sizeof(T) == 1);
  out << ",\n\"" << name << "\": \"";
  Base64Writer base64(out);
  for (std::size_t i = 0; i < count; ++i) {
    const T x = static_cast<T>(value(i));
    if constexpr (sizeof(T) == 4) {
      auto bits = std::bit_cast<std::uint32_t>(x);
      if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
      base64.write(&bits, sizeof bits);
    } else {
      base64.write(&x, 1);
    }
  }
  base64.finish();
  out << "\"";
}

/// A JSON string that can sit inside a <script> element: <, > and & as \u escapes.
std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c == '<' || c == '>' || c == '&') {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", c);
      out += escape;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

std::string html_text(std::string_view text) {
  std::string out;
  for (const char ch : text) {
    switch (ch) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

/// A finite number as JSON (NaN and infinities as null).
std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);  // read back exactly
  return text;
}

/// Everything the page shows, computed once from the mesh.
struct ViewerData {
  FaceDistortion distortion;
  UvChart chart;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0;
  Eigen::Vector3d view = Eigen::Vector3d::UnitZ(), up = Eigen::Vector3d::UnitY();  ///< camera
  WebViewerInfo info;
};

ViewerData prepare(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv,
                   const WebViewerOptions& options) {
  const char* fn = "web_viewer_html";
  if (!web_viewer_available()) {
    throw IoError(std::string(fn) +
                  ": this ricci was built without three.js (install Debian's libjs-three, "
                  "then configure and build again)");
  }
  check_uv_layout(fn, mesh, uv_triangles, uv);
  if (mesh.num_faces() == 0) throw InvalidInput(std::string(fn) + ": the mesh has no faces");
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    if (!mesh.positions.row(v).allFinite()) {
      throw InvalidInput(std::string(fn) + ": vertex " + std::to_string(v) +
                         " has a coordinate that is not finite");
    }
  }
  for (Eigen::Index t = 0; t < uv.rows(); ++t) {
    if (!uv.row(t).allFinite()) {
      throw InvalidInput(std::string(fn) + ": uv row " + std::to_string(t) + " is not finite");
    }
  }
  const Eigen::VectorXd& w = options.uv_weights;
  if (w.size() != 0 && w.size() != uv.rows()) {
    throw InvalidInput(std::string(fn) + ": uv_weights has " + std::to_string(w.size()) +
                       " entries but uv has " + std::to_string(uv.rows()) + " rows");
  }
  for (Eigen::Index t = 0; t < w.size(); ++t) {
    if (!(std::isfinite(w[t]) && w[t] > 0)) {
      throw InvalidInput(std::string(fn) + ": uv weight " + std::to_string(t) +
                         " is not finite and positive");
    }
  }
  if (!(options.checker > 0 && std::isfinite(options.checker))) {
    throw InvalidInput(std::string(fn) + ": checker must be finite and > 0");
  }

  ViewerData d;
  d.distortion = measure_face_distortion(mesh, uv_triangles, uv);
  d.chart = analyse_uv_chart(mesh, uv_triangles, uv, options.cone_tolerance);
  // The bounding box of the vertices the faces use.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d p = mesh.positions.row(mesh.triangles(f, c)).transpose();
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  d.centre = 0.5 * (lo + hi);
  d.radius = 0.5 * (hi - lo).norm();
  // The page opens looking from where render.png looks.
  d.view = automatic_view(mesh, &d.up);

  WebViewerInfo& info = d.info;
  info.vertices = mesh.num_vertices();
  info.faces = mesh.num_faces();
  info.texture_coordinates = static_cast<int>(uv.rows());
  info.projective = w.size() != 0;
  info.seam_edges = d.chart.seam_edges;
  info.seam_halfedges = static_cast<int>(d.chart.seam_halfedges.size());
  info.cones = static_cast<int>(d.chart.cones.size());
  double largest_log = 0, largest_angle = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    info.flipped_faces += d.distortion.flipped[f];
    if (!std::isfinite(d.distortion.log_area[f])) {
      ++info.degenerate_faces;
      continue;
    }
    largest_log = std::max(largest_log, std::abs(d.distortion.log_area[f]));
    largest_angle = std::max(largest_angle, d.distortion.angle[f] - 1);
  }
  // Tiny floors keep a perfect layout's colour scale finite.
  info.log_area_range = std::clamp(largest_log, 1e-3, 2.0);
  info.angle_range = std::clamp(largest_angle, 1e-3, 2.0);
  return d;
}

/// The JSON block the page reads (its fields are documented in web_viewer.html).
void write_data(std::ostream& out, const Mesh& mesh, const Triangles& uv_triangles, const UV& uv,
                const WebViewerOptions& options, const ViewerData& d) {
  const WebViewerInfo& info = d.info;
  const Eigen::VectorXd& w = options.uv_weights;
  out << "{\"format\": \"ricci-viewer-1\"";
  out << ",\n\"title\": " << json_string(options.title.empty() ? "ricci viewer" : options.title);
  out << ",\n\"vertices\": " << info.vertices << ", \"faces\": " << info.faces
      << ", \"texture_coordinates\": " << info.texture_coordinates
      << ", \"projective\": " << (info.projective ? "true" : "false")
      << ",\n\"seam_edges\": " << info.seam_edges << ", \"seam_halfedges\": " << info.seam_halfedges
      << ", \"cones\": " << info.cones << ", \"flipped_faces\": " << info.flipped_faces
      << ", \"degenerate_faces\": " << info.degenerate_faces;
  out << ",\n\"centre\": [" << json_number(d.centre.x()) << ", " << json_number(d.centre.y())
      << ", " << json_number(d.centre.z()) << "], \"radius\": " << json_number(d.radius);
  out << ",\n\"view\": [" << json_number(d.view.x()) << ", " << json_number(d.view.y()) << ", "
      << json_number(d.view.z()) << "], \"up\": [" << json_number(d.up.x()) << ", "
      << json_number(d.up.y()) << ", " << json_number(d.up.z()) << "]";
  out << ",\n\"checker\": " << json_number(options.checker) << ", \"colouring\": \""
      << enum_name(options.colouring, "checker") << "\"";
  out << ",\n\"log_area_range\": " << json_number(info.log_area_range)
      << ", \"angle_range\": " << json_number(info.angle_range);

  // Positions relative to the centre keep float precision for meshes far from the origin.
  write_array<float>(out, "positions", 3 * static_cast<std::size_t>(mesh.positions.rows()),
                     [&](std::size_t i) { return mesh.positions(i / 3, i % 3) - d.centre[i % 3]; });
  write_array<std::uint32_t>(out, "triangles", 3 * static_cast<std::size_t>(info.faces),
                             [&](std::size_t i) { return mesh.triangles(i / 3, i % 3); });
  write_array<float>(out, "uvw", 3 * static_cast<std::size_t>(uv.rows()), [&](std::size_t i) {
    const Eigen::Index t = static_cast<Eigen::Index>(i / 3);
    if (i % 3 < 2) return uv(t, i % 3);
    return w.size() != 0 ? w[t] : 1.0;
  });
  write_array<std::uint32_t>(out, "uv_triangles", 3 * static_cast<std::size_t>(info.faces),
                             [&](std::size_t i) { return uv_triangles(i / 3, i % 3); });
  write_array<float>(out, "log_area", static_cast<std::size_t>(info.faces),
                     [&](std::size_t f) { return d.distortion.log_area[f]; });
  write_array<float>(out, "angle", static_cast<std::size_t>(info.faces),
                     [&](std::size_t f) { return d.distortion.angle[f]; });
  write_array<std::uint8_t>(out, "flipped", static_cast<std::size_t>(info.faces),
                            [&](std::size_t f) { return d.distortion.flipped[f]; });
  write_array<std::uint32_t>(out, "seams", d.chart.seam_halfedges.size(),
                             [&](std::size_t i) { return d.chart.seam_halfedges[i]; });
  write_array<std::uint32_t>(out, "cone_vertices", d.chart.cones.size(),
                             [&](std::size_t i) { return d.chart.cones[i]; });
  write_array<float>(out, "cone_curvatures", d.chart.cones.size(),
                     [&](std::size_t i) { return 2 * std::numbers::pi - d.chart.cone_angles[i]; });
  out << "}";
}

/// The notice three.js's licence asks to keep with every copy (Debian's minified build carries
/// none of its own).
void write_three_notice(std::ostream& out, std::string_view three) {
  std::string revision = "?";
  const std::size_t at = three.find("REVISION=\"");
  if (at != std::string_view::npos) {
    const std::size_t end = three.find('"', at + 10);
    if (end != std::string_view::npos && end - at < 20) {
      revision = std::string(three.substr(at + 10, end - at - 10));
    }
  }
  out << "/*\n * three.js r" << revision
      << " and its OrbitControls, from Debian's libjs-three (/usr/share/javascript/three).\n"
         " * Copyright (c) 2010-2019 three.js authors\n"
         " * MIT License (Expat):\n"
         " * Permission is hereby granted, free of charge, to any person obtaining a copy of this\n"
         " * software and associated documentation files (the \"Software\"), to deal in the\n"
         " * Software without restriction, including without limitation the rights to use, "
         "copy,\n"
         " * modify, merge, publish, distribute, sublicense, and/or sell copies of the Software,\n"
         " * and to permit persons to whom the Software is furnished to do so, subject to the\n"
         " * following conditions:\n"
         " * The above copyright notice and this permission notice shall be included in all\n"
         " * copies or substantial portions of the Software.\n"
         " * THE SOFTWARE IS PROVIDED \"AS IS\", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR "
         "IMPLIED,\n"
         " * INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY, FITNESS FOR A\n"
         " * PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE AUTHORS OR COPYRIGHT\n"
         " * HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER LIABILITY, WHETHER IN AN ACTION OF\n"
         " * CONTRACT, TORT OR OTHERWISE, ARISING FROM, OUT OF OR IN CONNECTION WITH THE SOFTWARE\n"
         " * OR THE USE OR OTHER DEALINGS IN THE SOFTWARE.\n"
         " */\n";
}

/// The template with its @RICCI_...@ placeholders filled in.
void write_page(std::ostream& out, const Mesh& mesh, const Triangles& uv_triangles, const UV& uv,
                const WebViewerOptions& options, const ViewerData& d) {
  using namespace render_detail;
  const std::string_view page = embedded(kViewerTemplate, kViewerTemplateSize);
  const std::string_view three = embedded(kThreeJs, kThreeJsSize);
  const std::string title = html_text(options.title.empty() ? "ricci viewer" : options.title);
  std::size_t from = 0;
  while (true) {
    const std::size_t at = page.find("@RICCI_", from);
    out << page.substr(from, at == std::string_view::npos ? std::string_view::npos : at - from);
    if (at == std::string_view::npos) break;
    const std::size_t end = page.find('@', at + 1);
    const std::string_view name = page.substr(at, end + 1 - at);
    if (name == "@RICCI_TITLE@") {
      out << title;
    } else if (name == "@RICCI_THREE_JS@") {
      write_three_notice(out, three);
      out << three;
    } else if (name == "@RICCI_ORBIT_CONTROLS_JS@") {
      out << embedded(kOrbitControlsJs, kOrbitControlsJsSize);
    } else if (name == "@RICCI_DATA@") {
      write_data(out, mesh, uv_triangles, uv, options, d);
    } else {
      throw std::logic_error("web_viewer: unknown placeholder " + std::string(name));
    }
    from = end + 1;
  }
}

}  // namespace

bool web_viewer_available() {
  return render_detail::kThreeJsSize > 0 && render_detail::kOrbitControlsJsSize > 0;
}

std::string web_viewer_html(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv,
                            const WebViewerOptions& options, WebViewerInfo* info) {
  ViewerData d = prepare(mesh, uv_triangles, uv, options);
  std::ostringstream out;
  write_page(out, mesh, uv_triangles, uv, options, d);
  std::string page = std::move(out).str();
  d.info.bytes = page.size();
  if (info) *info = d.info;
  return page;
}

WebViewerInfo write_web_viewer(const std::string& path, const Mesh& mesh,
                               const Triangles& uv_triangles, const UV& uv,
                               const WebViewerOptions& options) {
  ViewerData d = prepare(mesh, uv_triangles, uv, options);
  write_file_atomically(path, [&](std::ostream& out) {
    const std::streampos start = out.tellp();
    write_page(out, mesh, uv_triangles, uv, options, d);
    d.info.bytes = static_cast<std::size_t>(out.tellp() - start);
  });
  return d.info;
}

}  // namespace ricci
