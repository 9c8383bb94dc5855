#include <algorithm>
#include <cmath>

#include "mesh/io/detail/readers.hpp"
#include "ricci/errors.hpp"

namespace ricci::io_detail {
namespace {

/// STL stores every triangle with its own three corners; this merges corners at exactly equal
/// positions into one vertex (in order of first appearance) and fills the raw mesh.
void weld_stl_corners(const std::vector<double>& corner_xyz,
                      const std::vector<std::int64_t>& corner_where, RawMesh& raw) {
  const int nc = static_cast<int>(corner_where.size());
  std::vector<int> order;
  order.reserve(nc);
  for (int c = 0; c < nc; ++c) {
    const double* p = &corner_xyz[3 * c];
    // A corner with a NaN compares unequal to everything, so it stays a vertex of its own.
    if (!std::isnan(p[0]) && !std::isnan(p[1]) && !std::isnan(p[2])) order.push_back(c);
  }
  auto less = [&](int a, int b) {
    const double* p = &corner_xyz[3 * a];
    const double* q = &corner_xyz[3 * b];
    if (p[0] != q[0]) return p[0] < q[0];
    if (p[1] != q[1]) return p[1] < q[1];
    if (p[2] != q[2]) return p[2] < q[2];
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> representative(nc);
  for (int c = 0; c < nc; ++c) representative[c] = c;
  for (std::size_t i = 1; i < order.size(); ++i) {
    const double* p = &corner_xyz[3 * order[i - 1]];
    const double* q = &corner_xyz[3 * order[i]];
    if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) {
      representative[order[i]] = representative[order[i - 1]];
    }
  }
  std::vector<int> vertex_of_corner(nc, -1);
  for (int c = 0; c < nc; ++c) {
    if (representative[c] == c) {
      vertex_of_corner[c] = raw.num_vertices();
      raw.add_vertex(corner_xyz[3 * c], corner_xyz[3 * c + 1], corner_xyz[3 * c + 2],
                     corner_where[c]);
    } else {
      vertex_of_corner[c] = vertex_of_corner[representative[c]];
    }
    raw.corners.push_back(vertex_of_corner[c]);
  }
}

/// The triangle count a binary STL declares after its 80-byte comment (little-endian).
/// \pre data.size() >= 84
std::uint64_t binary_stl_count(std::string_view data) {
  return load_binary<std::uint32_t>(data.data() + 80, native_big_endian);
}

RawMesh parse_stl_binary(const std::string& path, std::string_view data) {
  RawMesh raw;
  raw.binary = true;
  if (data.size() < 84) {
    io_error(path, Where{static_cast<std::int64_t>(data.size()), true},
             "truncated: a binary STL needs an 84-byte header, the file has " +
                 std::to_string(data.size()) + " bytes");
  }
  const std::uint64_t count = binary_stl_count(data);
  if (count == 0) io_error(path, "no faces (the binary STL header declares 0 triangles)");
  const std::uint64_t expected = 84 + 50 * count;
  if (data.size() < expected) {
    const std::uint64_t complete = (data.size() - 84) / 50;
    io_error(path, Where{static_cast<std::int64_t>(84 + 50 * complete), true},
             "truncated: the header declares " + std::to_string(count) + " triangles (" +
                 std::to_string(expected) + " bytes) but the file has " +
                 std::to_string(data.size()) + " bytes: triangle " + std::to_string(complete) +
                 " at byte " + std::to_string(84 + 50 * complete) + " is cut off");
  }
  if (data.size() > expected) {
    io_error(path, Where{static_cast<std::int64_t>(expected), true},
             std::to_string(data.size() - expected) + " unexpected bytes after the " +
                 std::to_string(count) + " declared triangles");
  }
  std::vector<double> corner_xyz(9 * count);
  std::vector<std::int64_t> corner_where(3 * count);
  for (std::uint64_t t = 0; t < count; ++t) {
    const std::size_t start = 84 + 50 * t;
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = start + 12 + 12 * k;  // after the 12-byte normal
      for (int axis = 0; axis < 3; ++axis) {
        corner_xyz[9 * t + 3 * k + axis] =
            load_binary<float>(data.data() + at + 4 * axis, native_big_endian);
      }
      corner_where[3 * t + k] = static_cast<std::int64_t>(at);
    }
  }
  weld_stl_corners(corner_xyz, corner_where, raw);
  for (std::uint64_t t = 0; t < count; ++t) {
    raw.polygon_start.push_back(static_cast<int>(3 * (t + 1)));
    raw.polygon_where.push_back(static_cast<std::int64_t>(84 + 50 * t));
  }
  return raw;
}

RawMesh parse_stl_ascii(const std::string& path, std::string_view data) {
  RawMesh raw;
  TokenReader tokens(data, 0, 1);
  std::string_view token;
  std::vector<double> corner_xyz;
  std::vector<std::int64_t> corner_where;
  std::vector<int> polygon_size;
  auto here = [&] { return Where{tokens.line(), false}; };
  auto expect = [&](std::string_view keyword) {
    if (!tokens.next(token)) {
      io_error(path, here(),
               "truncated: the file ends where '" + std::string(keyword) + "' was expected");
    }
    if (token != keyword) {
      io_error(path, here(), "expected '" + std::string(keyword) + "', found " + quote(token));
    }
  };
  auto number = [&](const char* what) {
    if (!tokens.next(token))
      io_error(path, here(), std::string("truncated: ") + what + " expected");
    const auto value = parse_double(token);
    if (!value) io_error(path, here(), "malformed number " + quote(token) + " in " + what);
    return *value;
  };
  bool any_solid = false;
  while (tokens.next(token)) {
    if (token != "solid") io_error(path, here(), "expected 'solid', found " + quote(token));
    any_solid = true;
    tokens.skip_line();  // the solid's name
    while (true) {
      if (!tokens.next(token)) {
        io_error(path, here(), "truncated: the file ends without 'endsolid'");
      }
      if (token == "endsolid") {
        tokens.skip_line();
        break;
      }
      if (token != "facet") {
        io_error(path, here(), "expected 'facet' or 'endsolid', found " + quote(token));
      }
      const std::int64_t facet_line = tokens.line();
      const std::string facet = "facet " + std::to_string(polygon_size.size());
      expect("normal");
      for (int axis = 0; axis < 3; ++axis) number(("the normal of " + facet).c_str());
      expect("outer");
      expect("loop");
      int corners = 0;
      while (true) {
        if (!tokens.next(token)) io_error(path, here(), "truncated: the file ends inside " + facet);
        if (token == "endloop") break;
        if (token != "vertex") {
          io_error(path, here(), "expected 'vertex' or 'endloop', found " + quote(token));
        }
        const std::int64_t vertex_line = tokens.line();
        for (int axis = 0; axis < 3; ++axis) {
          corner_xyz.push_back(number(("a vertex of " + facet).c_str()));
        }
        corner_where.push_back(vertex_line);
        ++corners;
      }
      if (corners < 3) {
        io_error(path, Where{facet_line, false},
                 facet + " has " + std::to_string(corners) + " vertices, need at least 3");
      }
      expect("endfacet");
      polygon_size.push_back(corners);
      raw.polygon_where.push_back(facet_line);
    }
  }
  if (!any_solid || polygon_size.empty()) io_error(path, "no faces (the STL holds no facets)");
  weld_stl_corners(corner_xyz, corner_where, raw);
  for (int size : polygon_size) raw.polygon_start.push_back(raw.polygon_start.back() + size);
  return raw;
}

/// Whether the data reads as an ASCII STL: the keyword "solid" (with a name, or alone on its
/// line), then either text only or "facet normal" / "endsolid" as the next statement. A binary
/// STL's 80-byte comment may begin with "solid" too, but its counts and floats are not text and
/// what follows the comment is no facet.
bool looks_like_ascii_stl(std::string_view data) {
  TokenReader tokens(data, 0, 1);
  std::string_view token;
  if (!tokens.next(token) || token != "solid") return false;
  const bool text = std::all_of(data.begin(), data.end(), [](char c) {
    return c == '\n' || c == '\t' || c == '\r' || static_cast<unsigned char>(c) >= 32;
  });
  if (text) return true;
  tokens.skip_line();  // the solid's name
  if (!tokens.next(token)) return false;
  if (token == "endsolid") return true;
  return token == "facet" && tokens.next(token) && token == "normal";
}

}  // namespace

RawMesh parse_stl(const std::string& path, std::string_view data) {
  // A binary STL is exactly 84 + 50 n bytes long for the n its header declares; an ASCII one
  // starts with "solid" and reads as text. A file that passes both tests (an ASCII file of a
  // size that happens to match) is ASCII when it parses as such.
  const bool binary_size = data.size() >= 84 && data.size() == 84 + 50 * binary_stl_count(data);
  if (!looks_like_ascii_stl(data)) return parse_stl_binary(path, data);
  if (!binary_size) return parse_stl_ascii(path, data);
  try {
    return parse_stl_ascii(path, data);
  } catch (const IoError&) {
    return parse_stl_binary(path, data);
  }
}

}  // namespace ricci::io_detail
