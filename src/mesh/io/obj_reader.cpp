#include <algorithm>
#include <iterator>
#include <limits>

#include "mesh/io/detail/readers.hpp"

namespace ricci::io_detail {
namespace {

bool obj_statement_ignored(std::string_view keyword) {
  static constexpr std::string_view ignored[] = {
      "vt",     "vn",       "vp",       "o",          "g",        "s",      "usemtl",
      "mtllib", "l",        "p",        "mg",         "lod",      "usemap", "maplib",
      "bevel",  "c_interp", "d_interp", "shadow_obj", "trace_obj"};
  return std::find(std::begin(ignored), std::end(ignored), keyword) != std::end(ignored);
}

bool obj_statement_free_form(std::string_view keyword) {
  static constexpr std::string_view free_form[] = {
      "cstype", "deg",  "bmat", "step", "curv", "curv2", "surf",  "parm",
      "trim",   "hole", "scrv", "sp",   "end",  "con",   "ctech", "stech"};
  return std::find(std::begin(free_form), std::end(free_form), keyword) != std::end(free_form);
}

/// Reads the corners of an f statement (`rest` is the line after "f") into `raw`.
void add_obj_face(const std::string& path, Where here, std::string_view rest, RawMesh& raw) {
  const int face = raw.num_polygons();
  int count = 0;
  for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
    // v, v/vt, v//vn or v/vt/vn: only v matters, the others must still be integers.
    std::string_view parts[3];
    int num_parts = 0;
    std::string_view remaining = token;
    while (true) {
      const std::size_t slash = remaining.find('/');
      if (num_parts == 3) io_error(path, here, "malformed face corner " + quote(token));
      parts[num_parts++] = remaining.substr(0, slash);
      if (slash == std::string_view::npos) break;
      remaining.remove_prefix(slash + 1);
    }
    for (int i = 1; i < num_parts; ++i) {
      if (!parts[i].empty() && !parse_integer(parts[i])) {
        io_error(path, here, "malformed face corner " + quote(token));
      }
    }
    const auto index = parse_integer(parts[0]);
    if (!index) io_error(path, here, "malformed face corner " + quote(token));
    // Negative indices count back from the last vertex read so far.
    const std::int64_t resolved = *index < 0 ? raw.num_vertices() + *index : *index - 1;
    if (*index == 0 || resolved < 0 || resolved >= std::numeric_limits<int>::max()) {
      bad_vertex_index(path, here, face, parts[0],
                       "outside the valid range [1, " + std::to_string(raw.num_vertices()) +
                           "] (or [-" + std::to_string(raw.num_vertices()) +
                           ", -1] counting back)");
    }
    raw.corners.push_back(static_cast<int>(resolved));
    ++count;
  }
  if (count < 3) too_few_corners(path, here, face, count);
  raw.end_polygon(here.value);
}

}  // namespace

RawMesh parse_obj(const std::string& path, std::string_view data) {
  RawMesh raw;
  raw.index_base = 1;
  ObjStatementReader statements(data);
  std::string_view rest;
  while (statements.next(rest)) {
    const Where here{statements.line_number(), false};
    const std::string_view keyword = next_token(rest);
    if (keyword.empty()) continue;
    if (keyword == "v") {
      add_text_vertex(path, here, rest, raw);  // a fourth (w) or further (colour) numbers ignored
    } else if (keyword == "f") {
      add_obj_face(path, here, rest, raw);
    } else if (obj_statement_ignored(keyword)) {
      continue;
    } else if (obj_statement_free_form(keyword)) {
      io_error(path, here, "free-form geometry ('" + std::string(keyword) + "') is not supported");
    } else {
      io_error(path, here, "unknown OBJ statement " + quote(keyword));
    }
  }
  return raw;
}

}  // namespace ricci::io_detail
