#include <algorithm>
#include <limits>

#include "readers.hpp"

namespace ricci::io_detail {
namespace {

/// Next line that holds anything but whitespace and comments, comments stripped.
bool next_content_line(LineReader& lines, std::string_view& line) {
  while (lines.next(line)) {
    line = strip_comment(line);
    std::string_view probe = line;
    if (!next_token(probe).empty()) return true;
  }
  return false;
}

/// The next content line, which must hold the `index`-th of the `declared` vertices or faces
/// (`what`) the header announced.
/// \throw IoError when the file ends before it
std::string_view next_declared_line(const std::string& path, LineReader& lines, int declared,
                                    int index, const char* what) {
  std::string_view line;
  if (!next_content_line(lines, line)) {
    io_error(path, "truncated: the header declares " + std::to_string(declared) + " " + what +
                       " but the file ends after " + std::to_string(index) + " (line " +
                       std::to_string(lines.line_number()) + ")");
  }
  return line;
}

/// Checks the header keyword [ST][C][N][4][n]OFF: texture coordinates, colours and normals only
/// add per-vertex numbers after x y z, which are skipped; 4D and n-dimensional vertices are not
/// surfaces in R^3.
void check_off_header(const std::string& path, Where here, std::string_view header) {
  std::string_view prefix = header;
  if (prefix.size() < 3 || prefix.substr(prefix.size() - 3) != "OFF") {
    io_error(path, here,
             "not an OFF file: header " + quote(header) + " (expected OFF, COFF, NOFF, ...)");
  }
  prefix.remove_suffix(3);
  if (prefix.find_first_of("4n") != std::string_view::npos) {
    io_error(path, here,
             "OFF variant " + quote(header) + " (4D or n-dimensional vertices) is not supported");
  }
  if (prefix.starts_with("ST")) prefix.remove_prefix(2);
  if (prefix.starts_with("C")) prefix.remove_prefix(1);
  if (prefix.starts_with("N")) prefix.remove_prefix(1);
  if (!prefix.empty()) io_error(path, here, "unknown OFF header " + quote(header));
}

/// Reads a face line "n i_1 ... i_n [colour]" (the `f`-th face) into `raw`.
void add_off_face(const std::string& path, Where here, std::string_view rest, int f, int nv,
                  RawMesh& raw) {
  const std::string_view count_token = next_token(rest);
  const auto count = parse_integer(count_token);
  if (!count) {
    io_error(path, here,
             "malformed corner count " + quote(count_token) + " of face " + std::to_string(f));
  }
  if (*count < 3) too_few_corners(path, here, f, *count);
  for (std::int64_t k = 0; k < *count; ++k) {
    const std::string_view token = next_token(rest);
    if (token.empty()) {
      io_error(path, here,
               "face " + std::to_string(f) + " declares " + std::to_string(*count) +
                   " corners but lists " + std::to_string(k));
    }
    const auto index = parse_integer(token);
    if (!index) {
      io_error(path, here,
               "malformed vertex index " + quote(token) + " in face " + std::to_string(f));
    }
    if (*index < 0 || *index >= nv) {
      bad_vertex_index(path, here, f, token, "outside [0, " + std::to_string(nv) + ")");
    }
    raw.corners.push_back(static_cast<int>(*index));
  }
  // Anything after the corners is a colour: numbers, which are skipped.
  for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
    if (!parse_double(token)) {
      io_error(path, here, "malformed number " + quote(token) + " after face " + std::to_string(f));
    }
  }
  raw.end_polygon(here.value);
}

}  // namespace

RawMesh parse_off(const std::string& path, std::string_view data) {
  RawMesh raw;
  LineReader lines(data);
  std::string_view line;
  if (!next_content_line(lines, line)) io_error(path, "no OFF header (file holds only comments)");
  std::string_view rest = line;
  check_off_header(path, Where{lines.line_number(), false}, next_token(rest));
  // The counts may follow the keyword on the same line.
  std::int64_t counts[3] = {0, 0, 0};
  int num_counts = 0;
  std::int64_t counts_line = lines.line_number();
  while (num_counts < 2) {
    for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
      const auto value = parse_integer(token);
      if (!value || *value < 0 || num_counts == 3) {
        io_error(path, Where{counts_line, false},
                 "malformed OFF counts: " + quote(token) + " (expected: vertices faces edges)");
      }
      counts[num_counts++] = *value;
    }
    if (num_counts >= 2) break;
    if (num_counts == 1) {
      io_error(path, Where{counts_line, false}, "OFF counts line needs vertices faces edges");
    }
    if (!next_content_line(lines, line)) io_error(path, "truncated: no OFF counts line");
    rest = line;
    counts_line = lines.line_number();
  }
  if (counts[0] > std::numeric_limits<int>::max() || counts[1] > std::numeric_limits<int>::max()) {
    io_error(path, Where{counts_line, false}, "OFF counts too large");
  }
  const int nv = static_cast<int>(counts[0]);
  const int nf = static_cast<int>(counts[1]);
  if (nf == 0) io_error(path, Where{counts_line, false}, "no faces (the header declares 0)");
  const std::size_t plausible = data.size() / 4;  // never reserve beyond what the file can hold
  raw.xyz.reserve(std::min<std::size_t>(3 * static_cast<std::size_t>(nv), plausible));
  raw.vertex_where.reserve(std::min<std::size_t>(nv, plausible));

  for (int v = 0; v < nv; ++v) {
    rest = next_declared_line(path, lines, nv, v, "vertices");
    add_text_vertex(path, Where{lines.line_number(), false}, rest, raw);
  }
  for (int f = 0; f < nf; ++f) {
    rest = next_declared_line(path, lines, nf, f, "faces");
    add_off_face(path, Where{lines.line_number(), false}, rest, f, nv, raw);
  }
  if (next_content_line(lines, line)) {
    io_error(path, Where{lines.line_number(), false},
             "unexpected data after the last of the " + std::to_string(nf) + " declared faces");
  }
  return raw;
}

}  // namespace ricci::io_detail
