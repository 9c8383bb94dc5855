#include "ricci/mesh/io.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <optional>
#include <ostream>
#include <string_view>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

/// Where an element sits in its file: a line number (text formats) or a byte offset (binary).
struct Where {
  std::int64_t value = 0;
  bool is_byte = false;
};

std::string describe(Where where) {
  return (where.is_byte ? "byte " : "line ") + std::to_string(where.value);
}

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

/// A short printable rendering of a token for error messages.
std::string quote(std::string_view token) {
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (std::isprint(c)) {
      out += static_cast<char>(c);
    } else {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\x%02x", c);
      out += buffer;
    }
  }
  if (token.size() > 40) out += "...";
  return out + "'";
}

[[noreturn]] void io_error(const std::string& path, const std::string& what) {
  throw IoError(path + ": " + what);
}

[[noreturn]] void io_error(const std::string& path, Where where, const std::string& what) {
  throw IoError(path + ": " + describe(where) + ": " + what);
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Splits off the next whitespace-separated token of `rest`; empty at the end.
std::string_view next_token(std::string_view& rest) {
  std::size_t i = 0;
  while (i < rest.size() && is_space(rest[i])) ++i;
  std::size_t j = i;
  while (j < rest.size() && !is_space(rest[j])) ++j;
  const std::string_view token = rest.substr(i, j - i);
  rest.remove_prefix(j);
  return token;
}

/// A decimal number; accepts a leading '+', nan and inf (validation reports those later).
std::optional<double> parse_double(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size() || token.empty()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    // Overflow or underflow: strtod gives the limit value (inf or 0), which is what the number
    // means; validation rejects the infinite ones.
    return std::strtod(std::string(token).c_str(), nullptr);
  }
  if (ec != std::errc()) return std::nullopt;
  return value;
}

/// An integer; nullopt when malformed, and saturated when it overflows 64 bits (any such index
/// is out of range anyway).
std::optional<std::int64_t> parse_integer(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size() || token.empty()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    return token[0] == '-' ? std::numeric_limits<std::int64_t>::min()
                           : std::numeric_limits<std::int64_t>::max();
  }
  if (ec != std::errc()) return std::nullopt;
  return value;
}

/// Iterates the lines of a text buffer, counting them from 1 and stripping '\r'.
class LineReader {
 public:
  LineReader(std::string_view data, std::size_t start = 0) : data_(data), pos_(start) {}
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
  std::int64_t line_number() const { return line_number_; }
  std::size_t position() const { return pos_; }

 private:
  std::string_view data_;
  std::size_t pos_;
  std::int64_t line_number_ = 0;
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

std::string read_whole_file(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) io_error(path, "no such file");
  if (!fs::is_regular_file(status)) io_error(path, "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) io_error(path, std::string("cannot open: ") + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  std::string data(static_cast<std::size_t>(std::max<std::streamoff>(size, 0)), '\0');
  if (size > 0 && !in.read(data.data(), size)) io_error(path, "read failed");
  if (data.empty()) io_error(path, "empty file (0 bytes)");
  return data;
}

// ---------------------------------------------------------------------------------------------
// OBJ

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

RawMesh parse_obj(const std::string& path, std::string_view data) {
  RawMesh raw;
  raw.index_base = 1;
  LineReader lines(data);
  std::string_view line;
  while (lines.next(line)) {
    const Where here{lines.line_number(), false};
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    std::string_view rest = line;
    const std::string_view keyword = next_token(rest);
    if (keyword.empty()) continue;
    if (keyword == "v") {
      double x[3];
      int count = 0;
      for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
        const auto value = parse_double(token);
        if (!value)
          io_error(path, here,
                   "malformed number " + quote(token) + " in vertex " +
                       std::to_string(raw.num_vertices()));
        if (count < 3) x[count] = *value;
        ++count;  // a fourth (w) or further (colour) numbers are allowed and ignored
      }
      if (count < 3) {
        io_error(path, here,
                 "vertex " + std::to_string(raw.num_vertices()) + " has " + std::to_string(count) +
                     " coordinates, need 3");
      }
      raw.add_vertex(x[0], x[1], x[2], here.value);
    } else if (keyword == "f") {
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
          throw InvalidInput(path + ": " + describe(here) + ": face " + std::to_string(face) +
                             " uses vertex index " + std::string(parts[0]) +
                             ", outside the valid range [1, " + std::to_string(raw.num_vertices()) +
                             "] (or [-" + std::to_string(raw.num_vertices()) +
                             ", -1] counting back)");
        }
        raw.corners.push_back(static_cast<int>(resolved));
        ++count;
      }
      if (count < 3) {
        io_error(path, here,
                 "face " + std::to_string(face) + " has " + std::to_string(count) +
                     " corners, need at least 3");
      }
      raw.end_polygon(here.value);
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

// ---------------------------------------------------------------------------------------------
// OFF

/// Next line that holds anything but whitespace and comments, comments stripped.
bool next_content_line(LineReader& lines, std::string_view& line) {
  while (lines.next(line)) {
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    std::string_view probe = line;
    if (!next_token(probe).empty()) return true;
  }
  return false;
}

RawMesh parse_off(const std::string& path, std::string_view data) {
  RawMesh raw;
  LineReader lines(data);
  std::string_view line;
  if (!next_content_line(lines, line)) io_error(path, "no OFF header (file holds only comments)");
  std::string_view rest = line;
  const std::string_view header = next_token(rest);
  // [ST][C][N][4][n]OFF: texture coordinates, colours and normals only add per-vertex numbers
  // after x y z, which are skipped; 4D and n-dimensional vertices are not surfaces in R^3.
  {
    std::string_view prefix = header;
    if (prefix.size() < 3 || prefix.substr(prefix.size() - 3) != "OFF") {
      io_error(path, Where{lines.line_number(), false},
               "not an OFF file: header " + quote(header) + " (expected OFF, COFF, NOFF, ...)");
    }
    prefix.remove_suffix(3);
    if (prefix.find_first_of("4n") != std::string_view::npos) {
      io_error(path, Where{lines.line_number(), false},
               "OFF variant " + quote(header) + " (4D or n-dimensional vertices) is not supported");
    }
    if (prefix.starts_with("ST")) prefix.remove_prefix(2);
    if (prefix.starts_with("C")) prefix.remove_prefix(1);
    if (prefix.starts_with("N")) prefix.remove_prefix(1);
    if (!prefix.empty()) {
      io_error(path, Where{lines.line_number(), false}, "unknown OFF header " + quote(header));
    }
  }
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
    if (!next_content_line(lines, line)) {
      io_error(path, "truncated: the header declares " + std::to_string(nv) +
                         " vertices but the file ends after " + std::to_string(v) + " (line " +
                         std::to_string(lines.line_number()) + ")");
    }
    const Where here{lines.line_number(), false};
    rest = line;
    double x[3];
    int count = 0;
    for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
      const auto value = parse_double(token);
      if (!value) {
        io_error(path, here,
                 "malformed number " + quote(token) + " in vertex " + std::to_string(v));
      }
      if (count < 3) x[count] = *value;
      ++count;
    }
    if (count < 3) {
      io_error(
          path, here,
          "vertex " + std::to_string(v) + " has " + std::to_string(count) + " coordinates, need 3");
    }
    raw.add_vertex(x[0], x[1], x[2], here.value);
  }
  for (int f = 0; f < nf; ++f) {
    if (!next_content_line(lines, line)) {
      io_error(path, "truncated: the header declares " + std::to_string(nf) +
                         " faces but the file ends after " + std::to_string(f) + " (line " +
                         std::to_string(lines.line_number()) + ")");
    }
    const Where here{lines.line_number(), false};
    rest = line;
    const std::string_view count_token = next_token(rest);
    const auto count = parse_integer(count_token);
    if (!count)
      io_error(path, here,
               "malformed corner count " + quote(count_token) + " of face " + std::to_string(f));
    if (*count < 3) {
      io_error(path, here,
               "face " + std::to_string(f) + " has " + std::to_string(*count) +
                   " corners, need at least 3");
    }
    for (std::int64_t k = 0; k < *count; ++k) {
      const std::string_view token = next_token(rest);
      if (token.empty()) {
        io_error(path, here,
                 "face " + std::to_string(f) + " declares " + std::to_string(*count) +
                     " corners but lists " + std::to_string(k));
      }
      const auto index = parse_integer(token);
      if (!index)
        io_error(path, here,
                 "malformed vertex index " + quote(token) + " in face " + std::to_string(f));
      if (*index < 0 || *index >= nv) {
        throw InvalidInput(path + ": " + describe(here) + ": face " + std::to_string(f) +
                           " uses vertex index " + std::string(token) + ", outside [0, " +
                           std::to_string(nv) + ")");
      }
      raw.corners.push_back(static_cast<int>(*index));
    }
    // Anything after the corners is a colour: numbers, which are skipped.
    for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
      if (!parse_double(token)) {
        io_error(path, here,
                 "malformed number " + quote(token) + " after face " + std::to_string(f));
      }
    }
    raw.end_polygon(here.value);
  }
  if (next_content_line(lines, line)) {
    io_error(path, Where{lines.line_number(), false},
             "unexpected data after the last of the " + std::to_string(nf) + " declared faces");
  }
  return raw;
}

// ---------------------------------------------------------------------------------------------
// PLY

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<PlyType> ply_type(std::string_view name) {
  if (name == "char" || name == "int8") return PlyType::Int8;
  if (name == "uchar" || name == "uint8") return PlyType::UInt8;
  if (name == "short" || name == "int16") return PlyType::Int16;
  if (name == "ushort" || name == "uint16") return PlyType::UInt16;
  if (name == "int" || name == "int32") return PlyType::Int32;
  if (name == "uint" || name == "uint32") return PlyType::UInt32;
  if (name == "float" || name == "float32") return PlyType::Float32;
  if (name == "double" || name == "float64") return PlyType::Float64;
  return std::nullopt;
}

int ply_size(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 0;
}

bool ply_is_integer(PlyType type) {
  return type != PlyType::Float32 && type != PlyType::Float64;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  ///< value type (of the items, for a list)
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;  ///< type of a list's length
};

struct PlyElement {
  std::string name;
  std::int64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyEncoding { Ascii, LittleEndian, BigEndian };

/// Reads one binary value of the given type as a double; `swap` reverses the byte order.
double ply_load(PlyType type, const char* p, bool swap) {
  unsigned char bytes[8];
  const int size = ply_size(type);
  std::memcpy(bytes, p, size);
  if (swap) std::reverse(bytes, bytes + size);
  switch (type) {
    case PlyType::Int8:
      return static_cast<std::int8_t>(bytes[0]);
    case PlyType::UInt8:
      return bytes[0];
    case PlyType::Int16: {
      std::int16_t v;
      std::memcpy(&v, bytes, 2);
      return v;
    }
    case PlyType::UInt16: {
      std::uint16_t v;
      std::memcpy(&v, bytes, 2);
      return v;
    }
    case PlyType::Int32: {
      std::int32_t v;
      std::memcpy(&v, bytes, 4);
      return v;
    }
    case PlyType::UInt32: {
      std::uint32_t v;
      std::memcpy(&v, bytes, 4);
      return v;
    }
    case PlyType::Float32: {
      float v;
      std::memcpy(&v, bytes, 4);
      return v;
    }
    case PlyType::Float64: {
      double v;
      std::memcpy(&v, bytes, 8);
      return v;
    }
  }
  return 0;
}

/// The header of a PLY file and the offset where its data begins.
struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  std::size_t data_start = 0;
  std::int64_t data_line = 0;  ///< line number of the first data line (ASCII)
};

PlyHeader parse_ply_header(const std::string& path, std::string_view data) {
  PlyHeader header;
  LineReader lines(data);
  std::string_view line;
  if (!lines.next(line) || line != "ply") {
    io_error(path, Where{1, false}, "not a PLY file (the first line must be 'ply')");
  }
  bool have_format = false, have_end = false;
  while (lines.next(line)) {
    const Where here{lines.line_number(), false};
    std::string_view rest = line;
    const std::string_view keyword = next_token(rest);
    if (keyword == "end_header") {
      have_end = true;
      break;
    }
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      const std::string_view encoding = next_token(rest);
      const std::string_view version = next_token(rest);
      if (encoding == "ascii") {
        header.encoding = PlyEncoding::Ascii;
      } else if (encoding == "binary_little_endian") {
        header.encoding = PlyEncoding::LittleEndian;
      } else if (encoding == "binary_big_endian") {
        header.encoding = PlyEncoding::BigEndian;
      } else {
        io_error(path, here, "unknown PLY format " + quote(encoding));
      }
      if (version != "1.0") io_error(path, here, "unsupported PLY version " + quote(version));
      have_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      element.name = std::string(next_token(rest));
      const std::string_view count_token = next_token(rest);
      const auto count = parse_integer(count_token);
      if (element.name.empty() || !count || *count < 0 ||
          *count > std::numeric_limits<int>::max()) {
        io_error(path, here, "malformed element line (expected: element <name> <count>)");
      }
      element.count = *count;
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) io_error(path, here, "property before any element");
      PlyProperty property;
      std::string_view type_name = next_token(rest);
      if (type_name == "list") {
        property.is_list = true;
        const std::string_view count_name = next_token(rest);
        const auto count_type = ply_type(count_name);
        if (!count_type || !ply_is_integer(*count_type)) {
          io_error(path, here, "list length type " + quote(count_name) + " is not an integer type");
        }
        property.count_type = *count_type;
        type_name = next_token(rest);
      }
      const auto type = ply_type(type_name);
      if (!type) io_error(path, here, "unknown property type " + quote(type_name));
      property.type = *type;
      property.name = std::string(next_token(rest));
      if (property.name.empty()) io_error(path, here, "property without a name");
      header.elements.back().properties.push_back(std::move(property));
    } else {
      io_error(path, here, "unknown PLY header line starting with " + quote(keyword));
    }
  }
  if (!have_end) io_error(path, "truncated: PLY header has no end_header");
  if (!have_format) io_error(path, "PLY header has no format line");
  header.data_start = lines.position();
  header.data_line = lines.line_number() + 1;
  return header;
}

/// Which properties of the vertex and face elements carry the mesh.
struct PlyRoles {
  int vertex_element = -1, face_element = -1;
  int coordinate[3] = {-1, -1, -1};  ///< property indices of x, y, z in the vertex element
  int corners = -1;                  ///< property index of vertex_indices in the face element
};

PlyRoles find_ply_roles(const std::string& path, const PlyHeader& header, RawMesh& raw) {
  PlyRoles roles;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    if (element.name == "vertex" && roles.vertex_element < 0) {
      roles.vertex_element = static_cast<int>(e);
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        for (int axis = 0; axis < 3; ++axis) {
          if (property.name != std::string(1, static_cast<char>('x' + axis))) continue;
          if (property.is_list) io_error(path, "vertex property " + property.name + " is a list");
          roles.coordinate[axis] = static_cast<int>(p);
        }
      }
    } else if (element.name == "face" && roles.face_element < 0) {
      roles.face_element = static_cast<int>(e);
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (property.name != "vertex_indices" && property.name != "vertex_index") continue;
        if (!property.is_list || !ply_is_integer(property.type)) {
          io_error(path, "face property " + property.name + " must be a list of integers");
        }
        roles.corners = static_cast<int>(p);
      }
    } else if (element.count > 0) {
      raw.warnings.push_back(path + ": skipped PLY element '" + element.name + "' (" +
                             std::to_string(element.count) + " items)");
    }
  }
  if (roles.vertex_element < 0) io_error(path, "PLY header declares no vertex element");
  for (int axis = 0; axis < 3; ++axis) {
    if (roles.coordinate[axis] < 0) {
      io_error(path,
               std::string("PLY vertex element has no property ") + static_cast<char>('x' + axis));
    }
  }
  if (roles.face_element < 0 || header.elements[roles.face_element].count == 0) {
    io_error(path, "no faces (the PLY header declares no face element or 0 faces)");
  }
  if (roles.corners < 0) io_error(path, "PLY face element has no vertex_indices property");
  return roles;
}

/// Checks a face's corner count and index, shared by the ASCII and binary PLY readers.
void check_ply_corner(const std::string& path, Where here, int face, double index, int nv) {
  if (index < 0 || index >= nv) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.0f", index);
    throw InvalidInput(path + ": " + describe(here) + ": face " + std::to_string(face) +
                       " uses vertex index " + buffer + ", outside [0, " + std::to_string(nv) +
                       ")");
  }
}

void check_ply_corner_count(const std::string& path, Where here, int face, double count) {
  if (count < 3) {
    io_error(path, here,
             "face " + std::to_string(face) + " has " +
                 std::to_string(static_cast<std::int64_t>(count)) + " corners, need at least 3");
  }
}

void read_ply_binary(const std::string& path, std::string_view data, const PlyHeader& header,
                     const PlyRoles& roles, RawMesh& raw) {
  raw.binary = true;
  const bool file_big = header.encoding == PlyEncoding::BigEndian;
  const bool swap = file_big != (std::endian::native == std::endian::big);
  std::size_t pos = header.data_start;
  const auto nv = static_cast<int>(header.elements[roles.vertex_element].count);
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    const bool is_vertex = static_cast<int>(e) == roles.vertex_element;
    const bool is_face = static_cast<int>(e) == roles.face_element;
    auto need = [&](std::size_t bytes, std::int64_t item) {
      if (data.size() - pos < bytes) {
        io_error(path, Where{static_cast<std::int64_t>(pos), true},
                 "truncated: the file ends inside " + element.name + " " + std::to_string(item) +
                     " of " + std::to_string(element.count));
      }
    };
    if (is_vertex) {
      const std::size_t plausible = (data.size() - pos) / 3;
      raw.xyz.reserve(
          std::min<std::size_t>(3 * static_cast<std::size_t>(element.count), plausible));
      raw.vertex_where.reserve(std::min<std::size_t>(element.count, plausible));
    }
    for (std::int64_t item = 0; item < element.count; ++item) {
      const std::size_t item_start = pos;
      double x[3] = {0, 0, 0};
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.is_list) {
          const int size = ply_size(property.type);
          need(size, item);
          if (is_vertex) {
            for (int axis = 0; axis < 3; ++axis) {
              if (roles.coordinate[axis] == static_cast<int>(p)) {
                x[axis] = ply_load(property.type, data.data() + pos, swap);
              }
            }
          }
          pos += size;
          continue;
        }
        need(ply_size(property.count_type), item);
        const double count = ply_load(property.count_type, data.data() + pos, swap);
        pos += ply_size(property.count_type);
        if (count < 0) {
          io_error(path, Where{static_cast<std::int64_t>(pos), true},
                   "negative list length in " + element.name + " " + std::to_string(item));
        }
        const int size = ply_size(property.type);
        need(static_cast<std::size_t>(count) * size, item);
        if (is_face && roles.corners == static_cast<int>(p)) {
          const Where here{static_cast<std::int64_t>(item_start), true};
          check_ply_corner_count(path, here, static_cast<int>(item), count);
          for (int k = 0; k < static_cast<int>(count); ++k) {
            const double index = ply_load(property.type, data.data() + pos + k * size, swap);
            check_ply_corner(path, here, static_cast<int>(item), index, nv);
            raw.corners.push_back(static_cast<int>(index));
          }
        }
        pos += static_cast<std::size_t>(count) * size;
      }
      if (is_vertex) raw.add_vertex(x[0], x[1], x[2], static_cast<std::int64_t>(item_start));
      if (is_face) raw.end_polygon(static_cast<std::int64_t>(item_start));
    }
  }
  if (pos != data.size()) {
    io_error(path, Where{static_cast<std::int64_t>(pos), true},
             std::to_string(data.size() - pos) + " unexpected bytes after the last element");
  }
}

void read_ply_ascii(const std::string& path, std::string_view data, const PlyHeader& header,
                    const PlyRoles& roles, RawMesh& raw) {
  TokenReader tokens(data, header.data_start, header.data_line);
  const auto nv = static_cast<int>(header.elements[roles.vertex_element].count);
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    const bool is_vertex = static_cast<int>(e) == roles.vertex_element;
    const bool is_face = static_cast<int>(e) == roles.face_element;
    std::int64_t item = 0;
    std::string_view token;
    auto next_number = [&](bool integer) {
      if (!tokens.next(token)) {
        io_error(path, Where{tokens.line(), false},
                 "truncated: the file ends inside " + element.name + " " + std::to_string(item) +
                     " of " + std::to_string(element.count));
      }
      std::optional<double> value;
      if (!integer) {
        value = parse_double(token);
      } else if (const auto whole = parse_integer(token)) {
        value = static_cast<double>(*whole);
      }
      if (!value) {
        io_error(path, Where{tokens.line(), false},
                 "malformed number " + quote(token) + " in " + element.name + " " +
                     std::to_string(item));
      }
      return *value;
    };
    for (; item < element.count; ++item) {
      double x[3] = {0, 0, 0};
      std::int64_t item_line = -1;
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.is_list) {
          const double value = next_number(ply_is_integer(property.type));
          if (item_line < 0) item_line = tokens.line();
          for (int axis = 0; axis < 3; ++axis) {
            if (is_vertex && roles.coordinate[axis] == static_cast<int>(p)) x[axis] = value;
          }
          continue;
        }
        const double count = next_number(true);
        if (item_line < 0) item_line = tokens.line();
        const Where here{item_line, false};
        if (count < 0) {
          io_error(path, here,
                   "negative list length in " + element.name + " " + std::to_string(item));
        }
        const bool corners = is_face && roles.corners == static_cast<int>(p);
        if (corners) check_ply_corner_count(path, here, static_cast<int>(item), count);
        for (std::int64_t k = 0; k < static_cast<std::int64_t>(count); ++k) {
          const double value = next_number(ply_is_integer(property.type));
          if (corners) {
            check_ply_corner(path, Where{tokens.line(), false}, static_cast<int>(item), value, nv);
            raw.corners.push_back(static_cast<int>(value));
          }
        }
      }
      if (is_vertex) raw.add_vertex(x[0], x[1], x[2], item_line);
      if (is_face) raw.end_polygon(item_line);
    }
  }
  std::string_view token;
  if (tokens.next(token)) {
    io_error(path, Where{tokens.line(), false}, "unexpected data after the last element");
  }
}

RawMesh parse_ply(const std::string& path, std::string_view data) {
  RawMesh raw;
  const PlyHeader header = parse_ply_header(path, data);
  const PlyRoles roles = find_ply_roles(path, header, raw);
  if (header.encoding == PlyEncoding::Ascii) {
    read_ply_ascii(path, data, header, roles, raw);
  } else {
    read_ply_binary(path, data, header, roles, raw);
  }
  return raw;
}

// ---------------------------------------------------------------------------------------------
// STL

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

RawMesh parse_stl_binary(const std::string& path, std::string_view data) {
  RawMesh raw;
  raw.binary = true;
  if (data.size() < 84) {
    io_error(path, Where{static_cast<std::int64_t>(data.size()), true},
             "truncated: a binary STL needs an 84-byte header, the file has " +
                 std::to_string(data.size()) + " bytes");
  }
  const bool swap = std::endian::native == std::endian::big;
  const auto count = static_cast<std::uint64_t>(ply_load(PlyType::UInt32, data.data() + 80, swap));
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
            ply_load(PlyType::Float32, data.data() + at + 4 * axis, swap);
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
  auto expect = [&](std::string_view keyword) {
    if (!tokens.next(token)) {
      io_error(path, Where{tokens.line(), false},
               "truncated: the file ends where '" + std::string(keyword) + "' was expected");
    }
    if (token != keyword) {
      io_error(path, Where{tokens.line(), false},
               "expected '" + std::string(keyword) + "', found " + quote(token));
    }
  };
  auto number = [&](const char* what) {
    if (!tokens.next(token)) {
      io_error(path, Where{tokens.line(), false}, std::string("truncated: ") + what + " expected");
    }
    const auto value = parse_double(token);
    if (!value) {
      io_error(path, Where{tokens.line(), false},
               "malformed number " + quote(token) + " in " + what);
    }
    return *value;
  };
  bool any_solid = false;
  while (tokens.next(token)) {
    if (token != "solid") {
      io_error(path, Where{tokens.line(), false}, "expected 'solid', found " + quote(token));
    }
    any_solid = true;
    tokens.skip_line();  // the solid's name
    while (true) {
      if (!tokens.next(token)) {
        io_error(path, Where{tokens.line(), false}, "truncated: the file ends without 'endsolid'");
      }
      if (token == "endsolid") {
        tokens.skip_line();
        break;
      }
      if (token != "facet") {
        io_error(path, Where{tokens.line(), false},
                 "expected 'facet' or 'endsolid', found " + quote(token));
      }
      const std::int64_t facet_line = tokens.line();
      const std::string facet = "facet " + std::to_string(polygon_size.size());
      expect("normal");
      for (int axis = 0; axis < 3; ++axis) number(("the normal of " + facet).c_str());
      expect("outer");
      expect("loop");
      int corners = 0;
      while (true) {
        if (!tokens.next(token)) {
          io_error(path, Where{tokens.line(), false}, "truncated: the file ends inside " + facet);
        }
        if (token == "endloop") break;
        if (token != "vertex") {
          io_error(path, Where{tokens.line(), false},
                   "expected 'vertex' or 'endloop', found " + quote(token));
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

RawMesh parse_stl(const std::string& path, std::string_view data) {
  // Binary files may also begin with "solid", so the size decides first: a binary STL is exactly
  // 84 + 50 n bytes long.
  if (data.size() >= 84) {
    const auto count = static_cast<std::uint64_t>(
        ply_load(PlyType::UInt32, data.data() + 80, std::endian::native == std::endian::big));
    if (data.size() == 84 + 50 * count) {
      return parse_stl_binary(path, data);
    }
  }
  std::string_view probe = data;
  if (next_token(probe) == "solid") {
    // An ASCII file holds text only.
    const bool text = std::all_of(data.begin(), data.end(), [](char c) {
      return c == '\n' || c == '\t' || c == '\r' || static_cast<unsigned char>(c) >= 32;
    });
    if (text) return parse_stl_ascii(path, data);
  }
  return parse_stl_binary(path, data);
}

// ---------------------------------------------------------------------------------------------
// Triangulation and assembly

/// Triangulates one planar-ish polygon by ear clipping in the plane of its Newell normal.
/// Returns false (leaving `out` untouched) when no ear can be found, e.g. for a self-intersecting
/// polygon.
bool ear_clip(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal,
              std::vector<std::array<int, 3>>& out) {
  const int n = static_cast<int>(points.size());
  Eigen::Vector3d u = normal.unitOrthogonal();
  Eigen::Vector3d w = normal.normalized().cross(u);
  std::vector<Eigen::Vector2d> plane(n);
  for (int i = 0; i < n; ++i) plane[i] = {points[i].dot(u), points[i].dot(w)};
  auto cross = [&](int a, int b, int c) {
    return (plane[b] - plane[a]).x() * (plane[c] - plane[a]).y() -
           (plane[b] - plane[a]).y() * (plane[c] - plane[a]).x();
  };
  std::vector<int> remaining(n);
  std::iota(remaining.begin(), remaining.end(), 0);
  std::vector<std::array<int, 3>> triangles;
  while (remaining.size() > 3) {
    const int m = static_cast<int>(remaining.size());
    bool clipped = false;
    for (int i = 0; i < m && !clipped; ++i) {
      const int a = remaining[(i + m - 1) % m], b = remaining[i], c = remaining[(i + 1) % m];
      if (cross(a, b, c) <= 0) continue;  // reflex or degenerate corner
      bool empty = true;
      for (int j : remaining) {
        if (j == a || j == b || j == c) continue;
        if (cross(a, b, j) >= 0 && cross(b, c, j) >= 0 && cross(c, a, j) >= 0) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      triangles.push_back({a, b, c});
      remaining.erase(remaining.begin() + i);
      clipped = true;
    }
    if (!clipped) return false;
  }
  if (cross(remaining[0], remaining[1], remaining[2]) <= 0) return false;
  triangles.push_back({remaining[0], remaining[1], remaining[2]});
  out = std::move(triangles);
  return true;
}

struct Triangulation {
  Triangles triangles;
  std::vector<int> polygon_of_triangle;
  int polygons_triangulated = 0;
  int ear_clipped = 0;
};

/// Splits polygons into triangles: a fan from the first corner when every fan triangle is
/// non-degenerate and turns like the polygon, otherwise ear clipping.
Triangulation triangulate(const RawMesh& raw) {
  Triangulation out;
  const int np = raw.num_polygons();
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(raw.corners.size() / 3 + 1);
  out.polygon_of_triangle.reserve(triangles.capacity());
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> local;
  auto point = [&](int v) {
    return Eigen::Vector3d(raw.xyz[3 * v], raw.xyz[3 * v + 1], raw.xyz[3 * v + 2]);
  };
  for (int p = 0; p < np; ++p) {
    const int* corner = raw.corners.data() + raw.polygon_start[p];
    const int n = raw.polygon_start[p + 1] - raw.polygon_start[p];
    if (n == 3) {
      triangles.push_back({corner[0], corner[1], corner[2]});
      out.polygon_of_triangle.push_back(p);
      continue;
    }
    ++out.polygons_triangulated;
    points.resize(n);
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // Newell's normal
    for (int i = 0; i < n; ++i) points[i] = point(corner[i]);
    for (int i = 0; i < n; ++i) normal += points[i].cross(points[(i + 1) % n]);
    bool fan = true;
    if (normal.allFinite() && normal.squaredNorm() > 0) {
      for (int i = 1; i + 1 < n && fan; ++i) {
        const Eigen::Vector3d a = points[i] - points[0], b = points[i + 1] - points[0];
        const Eigen::Vector3d c = a.cross(b);
        const double longest = std::max({a.squaredNorm(), b.squaredNorm(), (b - a).squaredNorm()});
        fan = c.dot(normal) > 0 && c.norm() > 1e-12 * longest;
      }
      if (!fan && ear_clip(points, normal, local)) {
        ++out.ear_clipped;
        for (const auto& t : local) {
          triangles.push_back({corner[t[0]], corner[t[1]], corner[t[2]]});
          out.polygon_of_triangle.push_back(p);
        }
        continue;
      }
    }
    for (int i = 1; i + 1 < n; ++i) {  // the fan, also the fallback when ear clipping fails
      triangles.push_back({corner[0], corner[i], corner[i + 1]});
      out.polygon_of_triangle.push_back(p);
    }
  }
  out.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) out.triangles(static_cast<Eigen::Index>(t), k) = triangles[t][k];
  }
  return out;
}

bool element_is_vertex(DefectKind kind) {
  return kind == DefectKind::NonFiniteCoordinate || kind == DefectKind::NonManifoldVertex ||
         kind == DefectKind::UnreferencedVertex;
}

/// Triangulates, validates and drops unreferenced vertices.
ReadResult assemble(const std::string& path, MeshFormat format, RawMesh raw,
                    const ReadOptions& options) {
  ReadResult result;
  result.format = format;
  result.warnings = std::move(raw.warnings);
  const int nv = raw.num_vertices();
  if (raw.num_polygons() == 0) {
    io_error(path, "no faces (the file holds " + std::to_string(nv) + " vertices and no face)");
  }
  // OBJ may name vertices defined further down; now that all are known, check every index.
  for (int p = 0; p < raw.num_polygons(); ++p) {
    for (int i = raw.polygon_start[p]; i < raw.polygon_start[p + 1]; ++i) {
      if (raw.corners[i] < nv) continue;
      throw InvalidInput(
          path + ": " + describe(raw.polygon_at(p)) + ": face " + std::to_string(p) +
          " uses vertex index " +
          std::to_string(static_cast<std::int64_t>(raw.corners[i]) + raw.index_base) +
          ", but the file has only " + std::to_string(nv) + " vertices");
    }
  }

  Triangulation triangulation = triangulate(raw);
  result.polygons_triangulated = triangulation.polygons_triangulated;
  if (triangulation.polygons_triangulated > 0) {
    std::string warning = path + ": " + std::to_string(triangulation.polygons_triangulated) +
                          " polygons with more than 3 corners triangulated";
    if (triangulation.ear_clipped > 0) {
      warning += " (" + std::to_string(triangulation.ear_clipped) +
                 " by ear clipping, where a fan would fold or degenerate)";
    }
    result.warnings.push_back(warning);
  }

  Mesh file_mesh;
  file_mesh.positions = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      raw.xyz.data(), nv, 3);
  file_mesh.triangles = std::move(triangulation.triangles);

  if (options.validate) {
    result.validation = find_defects(file_mesh);
    for (const Defect& defect : result.validation.defects) {
      if (defect.kind == DefectKind::UnreferencedVertex) continue;
      const Where where = element_is_vertex(defect.kind)
                              ? raw.vertex_at(defect.element)
                              : raw.polygon_at(triangulation.polygon_of_triangle[defect.element]);
      throw_first_defect(result.validation, path + ": " + describe(where));
    }
  }

  std::vector<int> new_index(nv, -1);
  for (Eigen::Index f = 0; f < file_mesh.triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) new_index[file_mesh.triangles(f, k)] = 0;
  }
  for (int v = 0; v < nv; ++v) {
    if (new_index[v] < 0) {
      result.dropped_vertices.push_back(v);
    } else {
      new_index[v] = static_cast<int>(result.vertex_map.size());
      result.vertex_map.push_back(v);
    }
  }
  if (result.dropped_vertices.empty()) {
    result.mesh = std::move(file_mesh);
    return result;
  }
  const int first = result.dropped_vertices.front();
  result.warnings.push_back(path + ": " + std::to_string(result.dropped_vertices.size()) +
                            " unreferenced vertices dropped (the first is vertex " +
                            std::to_string(first) + " at " + describe(raw.vertex_at(first)) + ")");
  result.mesh.positions.resize(static_cast<Eigen::Index>(result.vertex_map.size()), 3);
  for (std::size_t v = 0; v < result.vertex_map.size(); ++v) {
    result.mesh.positions.row(static_cast<Eigen::Index>(v)) =
        file_mesh.positions.row(result.vertex_map[v]);
  }
  result.mesh.triangles = file_mesh.triangles;
  for (Eigen::Index f = 0; f < result.mesh.triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      result.mesh.triangles(f, k) = new_index[result.mesh.triangles(f, k)];
    }
  }
  return result;
}

}  // namespace

MeshFormat format_from_path(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".off") return MeshFormat::Off;
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".stl") return MeshFormat::Stl;
  io_error(path, "unknown mesh format " +
                     (extension.empty() ? std::string("(no extension)") : quote(extension)) +
                     ": expected .obj, .off, .ply or .stl");
}

ReadResult read_mesh(const std::string& path, const ReadOptions& options) {
  const std::string data = read_whole_file(path);
  const MeshFormat format = format_from_path(path);
  RawMesh raw;
  switch (format) {
    case MeshFormat::Obj:
      raw = parse_obj(path, data);
      break;
    case MeshFormat::Off:
      raw = parse_off(path, data);
      break;
    case MeshFormat::Ply:
      raw = parse_ply(path, data);
      break;
    case MeshFormat::Stl:
      raw = parse_stl(path, data);
      break;
  }
  return assemble(path, format, std::move(raw), options);
}

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const fs::path temporary =
      folder / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                std::to_string(counter++));
  try {
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) {
        throw std::runtime_error("cannot create the temporary file " + temporary.string() + ": " +
                                 std::strerror(errno));
      }
      write(out);
      out.flush();
      if (!out) throw std::runtime_error("writing " + temporary.string() + " failed");
      out.close();
      if (!out) throw std::runtime_error("closing " + temporary.string() + " failed");
    }
    fs::rename(temporary, target);
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw IoError(path + ": cannot write: " + e.what());
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw IoError(path + ": cannot write: unknown error");
  }
}

void write_obj(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& out) {
    std::string text;
    char buffer[96];
    auto flush_if_large = [&] {
      if (text.size() < (1u << 20)) return;
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    };
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const int n = std::snprintf(buffer, sizeof buffer, "v %.17g %.17g %.17g\n",
                                  mesh.positions(v, 0), mesh.positions(v, 1), mesh.positions(v, 2));
      text.append(buffer, static_cast<std::size_t>(n));
      flush_if_large();
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const int n = std::snprintf(buffer, sizeof buffer, "f %d %d %d\n", mesh.triangles(f, 0) + 1,
                                  mesh.triangles(f, 1) + 1, mesh.triangles(f, 2) + 1);
      text.append(buffer, static_cast<std::size_t>(n));
      flush_if_large();
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

}  // namespace ricci
