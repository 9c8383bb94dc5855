#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>
#include <vector>

#include "mesh/io/detail/reader_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci {
namespace {

using io_detail::next_token;

/// Reading position, for messages.
struct Place {
  const std::string& path;
  std::int64_t line = 0;
};

[[noreturn]] void malformed(const Place& at, const std::string& what) {
  throw IoError(at.path + ": line " + std::to_string(at.line) + ": " + what);
}

std::string quoted(std::string_view token) {
  std::string text(token.substr(0, 40));
  for (char& c : text) {
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  }
  return "'" + text + (token.size() > 40 ? "...'" : "'");
}

std::optional<double> parse_number(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (token.empty() || error != std::errc() || end != token.data() + token.size()) {
    return std::nullopt;
  }
  return value;
}

std::optional<std::int64_t> parse_index(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (token.empty() || error != std::errc() || end != token.data() + token.size()) {
    return std::nullopt;
  }
  return value;
}

/// 1-based (or negative, counting back) OBJ index -> 0-based; throws when out of range.
int resolve(const Place& at, std::int64_t face, std::string_view written, std::int64_t index,
            std::int64_t count, const char* what) {
  const std::int64_t resolved = index < 0 ? count + index : index - 1;
  if (index == 0 || resolved < 0 || resolved >= count) {
    throw InvalidInput(at.path + ": line " + std::to_string(at.line) + ": face " +
                       std::to_string(face) + " refers to " + what + " " + std::string(written) +
                       ", but the file has defined " + std::to_string(count) + " " + what +
                       (count == 1 ? "" : "s") + " so far (valid: 1.." + std::to_string(count) +
                       " or -" + std::to_string(count) + "..-1)");
  }
  return static_cast<int>(resolved);
}

bool ignored_statement(std::string_view keyword) {
  static constexpr std::string_view ignored[] = {
      "vn", "vp",  "o",      "g",      "s",     "usemtl",   "mtllib",   "l",          "p",
      "mg", "lod", "usemap", "maplib", "bevel", "c_interp", "d_interp", "shadow_obj", "trace_obj"};
  for (std::string_view k : ignored) {
    if (k == keyword) return true;
  }
  return false;
}

}  // namespace

TexturedMesh read_textured_obj(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the file");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(path + ": reading failed");

  std::vector<double> positions, texture;  // flat x y z, u v
  std::vector<double> third;               // per vt: w, or NaN when absent
  std::vector<int> corners, uv_corners;    // 3 per triangle
  int polygons = 0;
  Polygons faces_as_polygons;  // every face, its corners as corners of its fan triangles
  faces_as_polygons.corner_start.push_back(0);
  std::int64_t faces = 0;
  Place at{path, 0};
  std::vector<int> face_vertices, face_uvs;

  io_detail::ObjStatementReader statements(data);
  std::string_view rest;
  while (statements.next(rest)) {
    at.line = statements.line_number();
    const std::string_view keyword = next_token(rest);
    if (keyword.empty()) continue;

    if (keyword == "v" || keyword == "vt") {
      const int needed = keyword == "v" ? 3 : 2;
      for (int i = 0; i < needed; ++i) {
        const std::string_view token = next_token(rest);
        if (token.empty()) {
          malformed(at, std::string(keyword) + " needs " + std::to_string(needed) +
                            " coordinates, found " + std::to_string(i));
        }
        const std::optional<double> value = parse_number(token);
        if (!value) malformed(at, "malformed number " + quoted(token));
        if (!std::isfinite(*value)) {
          malformed(at, std::string(keyword) + " coordinate " + quoted(token) + " is not finite");
        }
        (keyword == "v" ? positions : texture).push_back(*value);
      }
      // Further numbers (w, colours) are allowed; they must still be numbers. A vt's third is
      // kept: homogeneous texture coordinates when every vt has a positive one.
      bool first_extra = true;
      for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
        const std::optional<double> value = parse_number(token);
        if (!value) malformed(at, "malformed number " + quoted(token));
        if (keyword == "vt" && first_extra) third.push_back(*value);
        first_extra = false;
      }
      if (keyword == "vt" && first_extra) third.push_back(std::nan(""));
    } else if (keyword == "f") {
      face_vertices.clear();
      face_uvs.clear();
      const std::int64_t num_vertices = static_cast<std::int64_t>(positions.size() / 3);
      const std::int64_t num_uvs = static_cast<std::int64_t>(texture.size() / 2);
      for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
        const std::size_t slash = token.find('/');
        if (slash == std::string_view::npos) {
          malformed(at, "face corner " + quoted(token) +
                            " has no texture coordinate index (expected v/vt or v/vt/vn)");
        }
        const std::string_view v_text = token.substr(0, slash);
        std::string_view vt_text = token.substr(slash + 1);
        const std::size_t second = vt_text.find('/');
        if (second != std::string_view::npos) {
          const std::string_view vn_text = vt_text.substr(second + 1);
          if (!vn_text.empty() && !parse_index(vn_text)) {
            malformed(at, "malformed face corner " + quoted(token));
          }
          vt_text = vt_text.substr(0, second);
        }
        if (vt_text.empty()) {
          malformed(at, "face corner " + quoted(token) +
                            " has no texture coordinate index (expected v/vt or v/vt/vn)");
        }
        const std::optional<std::int64_t> v = parse_index(v_text), vt = parse_index(vt_text);
        if (!v || !vt) malformed(at, "malformed face corner " + quoted(token));
        face_vertices.push_back(resolve(at, faces, v_text, *v, num_vertices, "vertex"));
        face_uvs.push_back(resolve(at, faces, vt_text, *vt, num_uvs, "texture coordinate"));
      }
      if (face_vertices.size() < 3) {
        malformed(at, "face " + std::to_string(faces) + " has " +
                          std::to_string(face_vertices.size()) + " corners, need at least 3");
      }
      if (face_vertices.size() > 3) ++polygons;
      // Corner 0 and 1 of the polygon are corners 0 and 1 of its first fan triangle, corner
      // k + 1 is corner 2 of its k-th.
      const int first = static_cast<int>(corners.size());
      faces_as_polygons.corners.insert(faces_as_polygons.corners.end(), {first, first + 1});
      for (std::size_t k = 1; k + 1 < face_vertices.size(); ++k) {
        faces_as_polygons.corners.push_back(static_cast<int>(corners.size()) + 2);
        faces_as_polygons.triangle_polygon.push_back(static_cast<int>(faces));
        for (std::size_t c : {std::size_t{0}, k, k + 1}) {
          corners.push_back(face_vertices[c]);
          uv_corners.push_back(face_uvs[c]);
        }
      }
      faces_as_polygons.corner_start.push_back(static_cast<int>(faces_as_polygons.corners.size()));
      ++faces;
    } else if (ignored_statement(keyword)) {
      continue;
    } else {
      malformed(at, "unsupported OBJ statement " + quoted(keyword));
    }
  }
  if (faces == 0) throw IoError(path + ": no faces (f statements) found");

  TexturedMesh result;
  const Eigen::Index nv = static_cast<Eigen::Index>(positions.size() / 3);
  const Eigen::Index nt = static_cast<Eigen::Index>(texture.size() / 2);
  const Eigen::Index nf = static_cast<Eigen::Index>(corners.size() / 3);
  result.mesh.positions.resize(nv, 3);
  for (Eigen::Index v = 0; v < nv; ++v) {
    for (int i = 0; i < 3; ++i) result.mesh.positions(v, i) = positions[3 * v + i];
  }
  result.uv.resize(nt, 2);
  for (Eigen::Index t = 0; t < nt; ++t) {
    for (int i = 0; i < 2; ++i) result.uv(t, i) = texture[2 * t + i];
  }
  const bool homogeneous = nt > 0 && std::all_of(third.begin(), third.end(), [](double w) {
                             return std::isfinite(w) && w > 0;
                           });
  if (homogeneous) {
    result.uv_weights.resize(nt);
    for (Eigen::Index t = 0; t < nt; ++t) {
      result.uv_weights[t] = third[t];
      result.uv.row(t) /= third[t];
    }
  }
  result.mesh.triangles.resize(nf, 3);
  result.uv_triangles.resize(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      result.mesh.triangles(f, c) = corners[3 * f + c];
      result.uv_triangles(f, c) = uv_corners[3 * f + c];
    }
  }
  result.polygons_triangulated = polygons;
  if (polygons > 0) result.polygons = std::move(faces_as_polygons);
  return result;
}

}  // namespace ricci
