#pragma once
/// \file
/// Private to write_mesh: one writer per format that holds positions and triangles only (OBJ's
/// writer is the public write_obj). Each writes atomically (write_file_atomically); write_mesh has
/// checked the indices and coordinates before.

#include <Eigen/Core>
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "numerics/detail/parallel.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/textured_mesh.hpp"

namespace ricci::io_detail {

/// Appends x in the shortest text that reads back as the same double (std::to_chars: at most 17
/// significant digits, like %.17g, but several times faster and often shorter).
inline void append_number(std::string& bytes, double x) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, x).ptr;
  bytes.append(text, static_cast<std::size_t>(end - text));
}
/// Appends i in decimal.
inline void append_integer(std::string& bytes, long long i) {
  char text[24];
  const auto end = std::to_chars(text, text + sizeof text, i).ptr;
  bytes.append(text, static_cast<std::size_t>(end - text));
}
/// Appends `prefix`, the row's numbers separated by spaces and a newline.
template <class Row>
void append_number_line(std::string& bytes, std::string_view prefix, const Row& row) {
  bytes.append(prefix);
  for (Eigen::Index c = 0; c < row.size(); ++c) {
    if (c > 0) bytes.push_back(' ');
    append_number(bytes, row(c));
  }
  bytes.push_back('\n');
}

/// A writer's output handed to the stream in blocks of about 1 MiB: one write per block rather
/// than per line, without holding the whole file in memory.
class BlockOutput {
 public:
  explicit BlockOutput(std::ostream& out) : out_(out) {}
  BlockOutput(const BlockOutput&) = delete;
  BlockOutput& operator=(const BlockOutput&) = delete;
  /// Writes what is left.
  ~BlockOutput() { write(); }

  /// Appends `count` characters (e.g. what snprintf wrote into a line buffer).
  void append(const char* data, int count) {
    bytes_.append(data, static_cast<std::size_t>(count));
    end_of_item();
  }
  /// Appends x in the shortest text that reads back as the same double (append_number).
  void number(double x) { append_number(bytes_, x); }
  /// Appends i in decimal.
  void integer(long long i) { append_integer(bytes_, i); }
  /// One line: `prefix` (e.g. "v "; may be empty), the row's numbers separated by spaces, a
  /// newline (an item).
  template <class Row>
  void number_line(std::string_view prefix, const Row& row) {
    append_number_line(bytes_, prefix, row);
    end_of_item();
  }
  /// Appends a piece of text (no end_of_item: a line's pieces end with one).
  void text(std::string_view s) { bytes_.append(s); }
  /// The block being filled, for binary values appended directly; call end_of_item after each.
  std::string& bytes() { return bytes_; }
  /// Writes what is held, then `text` (a block formatted elsewhere) without copying it.
  void write_through(std::string_view text) {
    write();
    out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  }
  /// Writes the block once it is large.
  void end_of_item() {
    if (bytes_.size() >= (1u << 20)) write();
  }

 private:
  void write() {
    out_.write(bytes_.data(), static_cast<std::streamsize>(bytes_.size()));
    bytes_.clear();
  }
  std::ostream& out_;
  std::string bytes_;
};

/// Lines 0 .. count - 1, line(i, bytes) appending line i to `bytes`, formatted on several threads
/// a batch at a time and written in order: formatting numbers is most of a writer's time (an
/// OBJ of bunny's 14k vertices and 28k faces: 5 ms on one thread).
template <class Line>
void append_lines(BlockOutput& out, int count, Line&& line) {
  constexpr int kBatch = 1 << 16;           // lines in memory at once
  constexpr int kMinLinesPerThread = 2048;  // a line takes 50-100 ns
  constexpr std::size_t kLineBytes =
      64;  // room reserved per line (a v line of 17-digit numbers: 56)
  std::vector<std::string> parts;
  for (int start = 0; start < count; start += kBatch) {
    const int n = std::min(kBatch, count - start);
    const int chunks = parallel::num_chunks(n, kMinLinesPerThread);
    parts.assign(static_cast<std::size_t>(chunks), std::string());
    parallel::run_chunks(n, chunks, [&](std::int64_t begin, std::int64_t end, int c) {
      std::string& bytes = parts[static_cast<std::size_t>(c)];
      bytes.reserve(static_cast<std::size_t>(end - begin) * kLineBytes);
      for (std::int64_t i = begin; i < end; ++i) line(start + static_cast<int>(i), bytes);
    });
    for (const std::string& part : parts) out.write_through(part);
  }
}

/// The checks of the writers before anything is written: every vertex index of a face in range;
/// with uv_triangles (not null) one row per face, every uv index in range, every uv row finite.
/// \throw InvalidInput "function: path: ..." naming the face and corner, or the uv row
void check_faces(const std::string& function, const std::string& path, const Mesh& mesh,
                 const Triangles* uv_triangles, const Eigen::Ref<const Eigen::MatrixXd>& uv);

/// OBJ: write_mesh's writer (write_obj's bytes), with mesh.polygons one `f` per polygon.
void write_obj_faces(const std::string& path, const TexturedMesh& mesh,
                     const ObjMaterial& material);

/// ASCII OFF: `OFF`, the counts, `x y z` per vertex (shortest round-trip digits: the doubles read
/// back exactly), `3 a b c` per face (0-based), or `n a b c ...` per polygon when polygons is not
/// empty.
void write_off(const std::string& path, const Mesh& mesh, const Polygons& polygons);

/// Binary little-endian PLY: double x, y, z per vertex and a counted int list per face (or per
/// polygon when polygons is not empty); the count is a uchar unless a polygon has more than 255
/// corners (then an int).
void write_ply(const std::string& path, const Mesh& mesh, const Polygons& polygons);

/// Binary STL: per face its unit normal (zero for a degenerate face) and three corners, as float;
/// the format has no shared vertices.
void write_stl(const std::string& path, const Mesh& mesh);

}  // namespace ricci::io_detail
