#pragma once
/// \file
/// Private to the mesh readers: what the OBJ, OFF, PLY and STL readers share. Text scanning and
/// number parsing, the error messages (which name the file and the line or byte offset), the raw
/// polygon soup every reader fills, and its assembly into a ReadResult (triangulation, validation
/// and dropping unreferenced vertices).

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ricci/mesh/io.hpp"

namespace ricci::io_detail {

// ---------------------------------------------------------------------------------------------
// Error formatting

/// Where an element sits in its file: a line number (text formats) or a byte offset (binary).
struct Where {
  std::int64_t value = 0;
  bool is_byte = false;
};

/// "line 12" or "byte 84".
std::string describe(Where where);

/// A short printable rendering of a token for error messages: quoted, at most 40 characters,
/// non-printable bytes as \xNN.
std::string quote(std::string_view token);

/// \throw IoError "path: what"
[[noreturn]] void io_error(const std::string& path, const std::string& what);

/// \throw IoError "path: line N: what" (or "byte N")
[[noreturn]] void io_error(const std::string& path, Where where, const std::string& what);

/// \throw InvalidInput "path: line N: face F uses vertex index I, <range>", where `index` is the
///        index as the file writes it and `range` says why it is out of range
[[noreturn]] void bad_vertex_index(const std::string& path, Where where, std::int64_t face,
                                   std::string_view index, const std::string& range);

/// \throw IoError "path: line N: face F has C corners, need at least 3"
[[noreturn]] void too_few_corners(const std::string& path, Where where, std::int64_t face,
                                  std::int64_t count);

// ---------------------------------------------------------------------------------------------
// Text scanning and number parsing

/// Whitespace within a line (everything std::isspace accepts except '\n').
inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Splits off the next whitespace-separated token of `rest`; empty at the end.
inline std::string_view next_token(std::string_view& rest) {
  std::size_t i = 0;
  while (i < rest.size() && is_space(rest[i])) ++i;
  std::size_t j = i;
  while (j < rest.size() && !is_space(rest[j])) ++j;
  const std::string_view token = rest.substr(i, j - i);
  rest.remove_prefix(j);
  return token;
}

/// The line up to its first '#' (OBJ and OFF comments).
inline std::string_view strip_comment(std::string_view line) {
  return line.substr(0, line.find('#'));
}

/// A decimal number; accepts a leading '+', nan and inf (validation reports those later).
std::optional<double> parse_double(std::string_view token);

/// An integer; nullopt when malformed, and saturated when it overflows 64 bits (any such index
/// is out of range anyway).
std::optional<std::int64_t> parse_integer(std::string_view token);

/// Iterates the lines of a text buffer, counting them from 1 and stripping '\r'.
class LineReader {
 public:
  explicit LineReader(std::string_view data, std::size_t start = 0) : data_(data), pos_(start) {}
  /// False at the end of the data.
  bool next(std::string_view& line) {
    if (pos_ >= data_.size()) return false;
    std::size_t end = data_.find('\n', pos_);
    if (end == std::string_view::npos) end = data_.size();
    line = data_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = std::min(end + 1, data_.size());
    ++line_number_;
    return true;
  }
  /// The number of the last line returned.
  std::int64_t line_number() const { return line_number_; }
  /// The offset of the next line.
  std::size_t position() const { return pos_; }

 private:
  std::string_view data_;
  std::size_t pos_;
  std::int64_t line_number_ = 0;
};

/// Iterates the statements of an OBJ file (read_mesh's and read_textured_obj's one tokenizer):
/// its lines without comments, where a line whose content ends with a backslash continues on the
/// next line (the backslash and the line break read as a space). A '#' comment ends its physical
/// line only, so a backslash inside a comment continues nothing.
class ObjStatementReader {
 public:
  explicit ObjStatementReader(std::string_view data) : lines_(data) {}
  /// False at the end of the data. `statement` stays valid until the next call.
  bool next(std::string_view& statement);
  /// The physical line where the last statement returned starts (error messages name it).
  std::int64_t line_number() const { return first_line_; }

 private:
  LineReader lines_;
  std::string joined_;  ///< a continued statement, its lines joined
  std::int64_t first_line_ = 0;
};

/// Iterates whitespace-separated tokens across lines, knowing the line of each.
class TokenReader {
 public:
  TokenReader(std::string_view data, std::size_t start, std::int64_t first_line)
      : data_(data), pos_(start), line_(first_line) {}
  /// False at the end of the data.
  bool next(std::string_view& token) {
    while (pos_ < data_.size() && (is_space(data_[pos_]) || data_[pos_] == '\n')) {
      if (data_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= data_.size()) return false;
    const std::size_t start = pos_;
    while (pos_ < data_.size() && !is_space(data_[pos_]) && data_[pos_] != '\n') ++pos_;
    token = data_.substr(start, pos_ - start);
    return true;
  }
  /// The line of the last token returned (or of the end of the data).
  std::int64_t line() const { return line_; }
  /// Skips the rest of the current line.
  void skip_line() {
    while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
  }

 private:
  std::string_view data_;
  std::size_t pos_;
  std::int64_t line_;
};

// ---------------------------------------------------------------------------------------------
// Binary values

/// Whether the machine stores numbers big-endian (binary PLY and STL files may not).
inline constexpr bool native_big_endian = std::endian::native == std::endian::big;

/// Reads a T stored at `p` (unaligned); `swap` reverses its byte order.
template <class T>
T load_binary(const char* p, bool swap) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

// ---------------------------------------------------------------------------------------------
// The raw polygon soup

/// A mesh as the file states it, before triangulation and before dropping unreferenced vertices.
struct RawMesh {
  std::vector<double> xyz;                  ///< 3 #V coordinates in file order
  std::vector<std::int64_t> vertex_where;   ///< #V line or byte offset of each vertex
  std::vector<int> corners;                 ///< the polygons' corners, 0-based file indices
  std::vector<int> polygon_start;           ///< #P + 1 offsets into corners
  std::vector<std::int64_t> polygon_where;  ///< #P line or byte offset of each polygon
  bool binary = false;                      ///< the offsets are bytes rather than lines
  int index_base = 0;                       ///< 1 for OBJ, whose indices count from 1
  std::vector<std::string> warnings;

  RawMesh() { polygon_start.push_back(0); }
  int num_vertices() const { return static_cast<int>(vertex_where.size()); }
  int num_polygons() const { return static_cast<int>(polygon_where.size()); }
  Where vertex_at(int v) const { return {vertex_where[v], binary}; }
  Where polygon_at(int p) const { return {polygon_where[p], binary}; }
  void add_vertex(double x, double y, double z, std::int64_t where) {
    xyz.insert(xyz.end(), {x, y, z});
    vertex_where.push_back(where);
  }
  void end_polygon(std::int64_t where) {
    polygon_start.push_back(static_cast<int>(corners.size()));
    polygon_where.push_back(where);
  }
};

/// Reads a text vertex "x y z ..." from `rest` (the line after any keyword) into `raw`; numbers
/// after the third (OBJ's w, OFF's normals and colours) must parse but are ignored.
/// \throw IoError naming the line when a number is malformed or fewer than three are given
void add_text_vertex(const std::string& path, Where here, std::string_view rest, RawMesh& raw);

/// Checks every corner index against the vertex count, triangulates the polygons, validates (when
/// options.validate is set) and drops unreferenced vertices.
/// \throw IoError when the mesh has no face
/// \throw InvalidInput naming the face when a corner names a vertex the file does not hold
/// \throw InvalidInput / TopologyError from throw_first_defect, with the file position as context
ReadResult assemble(const std::string& path, MeshFormat format, RawMesh raw,
                    const ReadOptions& options);

}  // namespace ricci::io_detail
