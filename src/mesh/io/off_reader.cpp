#include <algorithm>
#include <limits>

#include "mesh/io/detail/readers.hpp"

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

/// \throw IoError: the file ends before the `index`-th of the `declared` vertices or faces
///        (`what`) the header announced
[[noreturn]] void ends_before(const std::string& path, const LineReader& lines, int declared,
                              int index, const char* what) {
  io_error(path, "truncated: the header declares " + std::to_string(declared) + " " + what +
                     " but the file ends after " + std::to_string(index) + " (line " +
                     std::to_string(lines.line_number()) + ")");
}

/// What the header keyword [ST][C][N]OFF announces: the numbers each vertex has after x y z,
/// and whether the data is binary (`OFF BINARY`).
struct OffHeader {
  int extra_per_vertex = 0;  ///< binary: the floats after x y z (normal 3, colour 4, texture 2)
  bool binary = false;
};

/// Checks the header keyword [ST][C][N][4][n]OFF: texture coordinates, colours and normals only
/// add per-vertex numbers after x y z, which are skipped; 4D and n-dimensional vertices are not
/// surfaces in R^3.
OffHeader check_off_header(const std::string& path, Where here, std::string_view header) {
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
  OffHeader out;
  if (prefix.starts_with("ST")) {
    prefix.remove_prefix(2);
    out.extra_per_vertex += 2;
  }
  if (prefix.starts_with("C")) {
    prefix.remove_prefix(1);
    out.extra_per_vertex += 4;
  }
  if (prefix.starts_with("N")) {
    prefix.remove_prefix(1);
    out.extra_per_vertex += 3;
  }
  if (!prefix.empty()) io_error(path, here, "unknown OFF header " + quote(header));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Text OFF

/// The text after the OFF keyword as records (the counts, each vertex, each face), each token
/// knowing its line. A record begins on a fresh content line and, when that line ends before the
/// record is complete, continues on the next ones: some writers put a face's corner count on one
/// line and its corners on the following lines. What a record's last line holds after it are
/// extra numbers (normals, colours).
class OffRecords {
 public:
  /// `rest` is what the header line holds after the keyword.
  OffRecords(LineReader& lines, std::string_view rest)
      : lines_(lines), rest_(rest), first_line_(lines.line_number()), line_(first_line_) {}
  /// Starts the next record on the next content line; false at the end of the data.
  bool begin() {
    std::string_view line;
    if (!next_content_line(lines_, line)) return false;
    rest_ = line;
    first_line_ = line_ = lines_.line_number();
    return true;
  }
  /// The record's next token, read on from the next content line when its line is used up;
  /// empty at the end of the data.
  std::string_view next() {
    for (std::string_view token = next_token(rest_);; token = next_token(rest_)) {
      if (!token.empty()) return token;
      std::string_view line;
      if (!next_content_line(lines_, line)) return {};
      rest_ = line;
      line_ = lines_.line_number();
    }
  }
  /// The next token on the current line only; empty at its end.
  std::string_view next_on_line() { return next_token(rest_); }
  /// The line where the record begins.
  Where first() const { return {first_line_, false}; }
  /// The line of the last token read.
  Where here() const { return {line_, false}; }
  /// Whether the record has continued past its first line.
  bool wrapped() const { return line_ != first_line_; }

 private:
  LineReader& lines_;
  std::string_view rest_;
  std::int64_t first_line_;
  std::int64_t line_;
};

/// Checks what follows a record (the `index`-th `kind`: "vertex", 3) on its last line: numbers on
/// the record's own line; nothing after a record that continued onto further lines, where a
/// record that lists too few numbers would otherwise swallow the start of the next one unnoticed.
void check_record_extras(const std::string& path, OffRecords& records, const char* kind,
                         int index) {
  for (std::string_view token = records.next_on_line(); !token.empty();
       token = records.next_on_line()) {
    auto what = [&] { return kind + (" " + std::to_string(index)); };
    if (records.wrapped()) {
      io_error(path, records.here(),
               what() + " continues from " + describe(records.first()) +
                   " onto this line, which holds more after it: " + quote(token) +
                   " (a record spread over several lines must end its last line; does " +
                   describe(records.first()) + " list too few numbers?)");
    }
    if (!parse_double(token)) {
      io_error(path, records.here(), "malformed number " + quote(token) + " after " + what());
    }
  }
}

/// The counts "vertices faces [edges]": vertices and faces may follow the keyword on its line
/// or start on a later line, the edge count (ignored) is optional.
void read_off_counts(const std::string& path, OffRecords& records, std::int64_t counts[2],
                     Where& faces_at) {
  for (int i = 0; i < 2; ++i) {
    const std::string_view token = records.next();
    if (token.empty()) {
      io_error(path, "truncated: the OFF counts (vertices faces edges) are missing");
    }
    const auto value = parse_integer(token);
    if (!value || *value < 0) {
      io_error(path, records.here(),
               "malformed OFF counts: " + quote(token) + " (expected: vertices faces edges)");
    }
    if (*value > std::numeric_limits<int>::max()) {
      io_error(path, records.here(), "OFF counts too large");
    }
    counts[i] = *value;
  }
  faces_at = records.here();
  for (int i = 0;; ++i) {
    const std::string_view token = records.next_on_line();
    if (token.empty()) break;
    const auto value = parse_integer(token);
    if (i > 0 || !value || *value < 0) {
      io_error(path, records.here(),
               "malformed OFF counts: " + quote(token) + " (expected: vertices faces edges)");
    }
  }
}

/// Reads the next vertex record "x y z [extras]" into `raw`.
void add_off_vertex(const std::string& path, const LineReader& lines, OffRecords& records, int nv,
                    RawMesh& raw) {
  const int v = raw.num_vertices();
  if (!records.begin()) ends_before(path, lines, nv, v, "vertices");
  double x[3];
  for (double& coordinate : x) {
    const std::string_view token = records.next();
    if (token.empty()) {
      io_error(path, records.here(),
               "truncated: the file ends inside vertex " + std::to_string(v) + " (begun at " +
                   describe(records.first()) + ")");
    }
    const auto value = parse_double(token);
    if (!value) {
      io_error(path, records.here(),
               "malformed number " + quote(token) + " in vertex " + std::to_string(v));
    }
    coordinate = *value;
  }
  check_record_extras(path, records, "vertex", v);
  raw.add_vertex(x[0], x[1], x[2], records.first().value);
}

/// Reads the next face record "n i_1 ... i_n [colour]" (the `f`-th face) into `raw`.
void add_off_face(const std::string& path, const LineReader& lines, OffRecords& records, int f,
                  int nf, int nv, RawMesh& raw) {
  if (!records.begin()) ends_before(path, lines, nf, f, "faces");
  const std::string_view count_token = records.next();
  const auto count = parse_integer(count_token);
  if (!count) {
    io_error(path, records.here(),
             "malformed corner count " + quote(count_token) + " of face " + std::to_string(f));
  }
  if (*count < 3) too_few_corners(path, records.here(), f, *count);
  for (std::int64_t k = 0; k < *count; ++k) {
    const std::string_view token = records.next();
    if (token.empty()) {
      io_error(path, records.here(),
               "truncated: the file ends inside face " + std::to_string(f) + " (begun at " +
                   describe(records.first()) + "), which declares " + std::to_string(*count) +
                   " corners and lists " + std::to_string(k));
    }
    const auto index = parse_integer(token);
    if (!index) {
      io_error(path, records.here(),
               "malformed vertex index " + quote(token) + " in face " + std::to_string(f));
    }
    if (*index < 0 || *index >= nv) {
      bad_vertex_index(path, records.here(), f, token, "outside [0, " + std::to_string(nv) + ")");
    }
    raw.corners.push_back(static_cast<int>(*index));
  }
  check_record_extras(path, records, "face", f);  // a colour
  raw.end_polygon(records.first().value);
}

RawMesh parse_off_text(const std::string& path, LineReader& lines, std::string_view rest,
                       std::size_t data_size) {
  RawMesh raw;
  OffRecords records(lines, rest);
  std::int64_t counts[2] = {0, 0};
  Where counts_at;
  read_off_counts(path, records, counts, counts_at);
  const int nv = static_cast<int>(counts[0]);
  const int nf = static_cast<int>(counts[1]);
  if (nf == 0) io_error(path, counts_at, "no faces (the header declares 0)");
  const std::size_t plausible = data_size / 4;  // never reserve beyond what the file can hold
  raw.xyz.reserve(std::min<std::size_t>(3 * static_cast<std::size_t>(nv), plausible));
  raw.vertex_where.reserve(std::min<std::size_t>(nv, plausible));

  for (int v = 0; v < nv; ++v) add_off_vertex(path, lines, records, nv, raw);
  for (int f = 0; f < nf; ++f) add_off_face(path, lines, records, f, nf, nv, raw);
  if (records.begin()) {
    io_error(path, records.first(),
             "unexpected data after the last of the " + std::to_string(nf) + " declared faces");
  }
  return raw;
}

// ---------------------------------------------------------------------------------------------
// Binary OFF

/// One way to read a binary OFF. Geomview's documentation says big-endian, each face followed by
/// a colour count and that many floats; some writers (pmp-library's) write little-endian and
/// end each face after its corners.
struct BinaryOffLayout {
  bool big_endian = true;
  bool face_colours = true;  ///< each face ends with an int32 colour count and its floats
};

std::string describe_layout(BinaryOffLayout layout) {
  return std::string(layout.big_endian ? "big-endian" : "little-endian") +
         (layout.face_colours ? ", faces with colour counts" : ", faces without colour counts");
}

/// Where and why one reading of a binary OFF went wrong.
struct BinaryOffFailure {
  std::int64_t byte = 0;  ///< where the reading went wrong
  std::string what;
  /// How far the reading got: the byte where it went wrong; for counts too large for the file the
  /// end of the counts (beyond counts that make no sense at all, below any face read); for bytes
  /// left after the last face, beyond any other failure.
  std::int64_t progress = 0;
  /// Whether the faces' layout played a part (else only the byte order did).
  bool in_faces = false;
  /// A vertex index out of range (InvalidInput) in a reading whose structure (counts, corner
  /// and colour counts, file size) holds: its face and the index.
  std::int64_t face = -1;
  std::string index;
};

/// Reads the binary data from `start` (the counts, then the vertices of `floats_per_vertex`
/// float32 each, then the faces) with the given layout into `raw`; nullopt when the whole file
/// reads as a mesh. A vertex index out of range is reported only once the rest of the file has
/// read in this layout: in a wrong layout the structure breaks too.
std::optional<BinaryOffFailure> read_off_binary(std::string_view data, std::size_t start,
                                                int floats_per_vertex, BinaryOffLayout layout,
                                                RawMesh& raw) {
  const bool swap = layout.big_endian != native_big_endian;
  const std::size_t size = data.size();
  std::optional<BinaryOffFailure> bad_index;
  std::size_t pos = start;
  auto fail = [&](std::size_t at, std::string what) {
    BinaryOffFailure failure;
    failure.byte = failure.progress = static_cast<std::int64_t>(at);
    failure.what = std::move(what);
    failure.in_faces = at >= start + 12;
    return failure;
  };
  auto int_at = [&](std::size_t at) { return load_binary<std::int32_t>(data.data() + at, swap); };
  if (size - pos < 12) {
    return fail(pos, "truncated: the counts (vertices faces edges, 3 int32) need 12 bytes, " +
                         std::to_string(size - pos) + " follow the header line");
  }
  const std::int64_t nv = int_at(pos), nf = int_at(pos + 4);
  if (nv < 0 || nf < 0) {
    return fail(pos, "negative counts (" + std::to_string(nv) + " vertices, " + std::to_string(nf) +
                         " faces)");
  }
  if (nf == 0) return fail(pos + 4, "no faces (the header declares 0)");
  pos += 12;
  const std::uint64_t vertex_bytes = 4ULL * static_cast<std::uint64_t>(floats_per_vertex) * nv;
  const std::uint64_t least_face_bytes = 16ULL * nf;  // triangles without colour counts
  if (vertex_bytes + least_face_bytes > size - pos) {
    BinaryOffFailure failure =
        fail(pos - 12, "truncated: the counts (" + std::to_string(nv) + " vertices, " +
                           std::to_string(nf) + " faces) need at least " +
                           std::to_string(vertex_bytes + least_face_bytes) +
                           " bytes after them, the file has " + std::to_string(size - pos));
    failure.progress = static_cast<std::int64_t>(pos);
    return failure;
  }
  raw.binary = true;
  raw.xyz.reserve(3 * static_cast<std::size_t>(nv));
  raw.vertex_where.reserve(static_cast<std::size_t>(nv));
  for (std::int64_t v = 0; v < nv; ++v) {
    const char* p = data.data() + pos;
    raw.add_vertex(load_binary<float>(p, swap), load_binary<float>(p + 4, swap),
                   load_binary<float>(p + 8, swap), static_cast<std::int64_t>(pos));
    pos += 4 * static_cast<std::size_t>(floats_per_vertex);
  }
  for (std::int64_t f = 0; f < nf; ++f) {
    const std::size_t face_start = pos;
    auto face = [f] { return "face " + std::to_string(f); };
    if (size - pos < 4) {
      return fail(pos, "truncated: the file ends before " + face() + " of " + std::to_string(nf));
    }
    const std::int64_t count = int_at(pos);
    pos += 4;
    if (count < 3) {
      return fail(face_start,
                  face() + " has " + std::to_string(count) + " corners, need at least 3");
    }
    if ((size - pos) / 4 < static_cast<std::uint64_t>(count)) {
      return fail(face_start, "truncated: the file ends inside " + face() + " (" +
                                  std::to_string(count) + " corners)");
    }
    for (std::int64_t k = 0; k < count; ++k, pos += 4) {
      const std::int64_t index = int_at(pos);
      if ((index < 0 || index >= nv) && !bad_index) {
        bad_index = fail(pos, "outside [0, " + std::to_string(nv) + ")");
        bad_index->face = f;
        bad_index->index = std::to_string(index);
      }
      raw.corners.push_back(static_cast<int>(index));
    }
    if (layout.face_colours) {
      if (size - pos < 4)
        return fail(pos, "truncated: the file ends before the colour of " + face());
      const std::int64_t colours = int_at(pos);
      if (colours < 0 || colours > 4) {
        return fail(pos, face() + " has a colour count of " + std::to_string(colours) +
                             " (0 to 4 expected)");
      }
      pos += 4;
      if ((size - pos) / 4 < static_cast<std::uint64_t>(colours)) {
        return fail(pos, "truncated: the file ends inside the colour of " + face());
      }
      pos += 4 * static_cast<std::size_t>(colours);
    }
    raw.end_polygon(static_cast<std::int64_t>(face_start));
  }
  if (pos != size) {
    BinaryOffFailure failure =
        fail(pos, std::to_string(size - pos) + " unexpected bytes after the last of the " +
                      std::to_string(nf) + " declared faces");
    failure.progress = std::numeric_limits<std::int64_t>::max();  // every face read
    return failure;
  }
  return bad_index;
}

/// Reads `OFF BINARY` data from `start`. Writers disagree on the byte order and on whether faces
/// carry a colour count, so every combination is tried, the documented one (big-endian, colour
/// counts) first: the wrong ones give counts that do not match the file's size, corner or colour
/// counts out of range, or end elsewhere than the file. The first that reads the whole file
/// wins. When none does, the first whose structure holds reports its index out of range;
/// failing that, the one that got furthest reports its error.
RawMesh parse_off_binary(const std::string& path, std::string_view data, std::size_t start,
                         int floats_per_vertex) {
  std::optional<BinaryOffFailure> furthest;
  BinaryOffLayout furthest_layout;
  for (const bool face_colours : {true, false}) {
    for (const bool big_endian : {true, false}) {
      const BinaryOffLayout layout{big_endian, face_colours};
      RawMesh raw;
      std::optional<BinaryOffFailure> failure =
          read_off_binary(data, start, floats_per_vertex, layout, raw);
      if (!failure) return raw;
      const bool structure_holds = failure->face >= 0;
      if (!furthest || (structure_holds && furthest->face < 0) ||
          (furthest->face < 0 && failure->progress > furthest->progress)) {
        furthest = std::move(failure);
        furthest_layout = layout;
      }
    }
  }
  const Where where{furthest->byte, true};
  if (furthest->face >= 0) {
    bad_vertex_index(path, where, furthest->face, furthest->index,
                     furthest->what + " (binary OFF read " + describe_layout(furthest_layout) +
                         ", a layout whose structure the file fits)");
  }
  const std::string read_as = furthest->in_faces
                                  ? describe_layout(furthest_layout)
                                  : (furthest_layout.big_endian ? "big-endian" : "little-endian");
  io_error(path, where,
           furthest->what + " (binary OFF read " + read_as +
               ", which got furthest of the byte orders and face layouts tried)");
}

}  // namespace

RawMesh parse_off(const std::string& path, std::string_view data) {
  LineReader lines(data);
  std::string_view line;
  if (!next_content_line(lines, line)) io_error(path, "no OFF header (file holds only comments)");
  std::string_view rest = line;
  const Where header_at{lines.line_number(), false};
  const OffHeader header = check_off_header(path, header_at, next_token(rest));
  std::string_view after = rest;
  if (next_token(after) == "BINARY") {
    if (const std::string_view more = next_token(after); !more.empty()) {
      io_error(path, header_at, "unexpected " + quote(more) + " after 'BINARY'");
    }
    // The binary data begins right after the header line.
    return parse_off_binary(path, data, lines.position(), 3 + header.extra_per_vertex);
  }
  return parse_off_text(path, lines, rest, data.size());
}

}  // namespace ricci::io_detail
