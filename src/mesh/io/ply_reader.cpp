#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <tuple>
#include <type_traits>

#include "mesh/io/detail/readers.hpp"

namespace ricci::io_detail {
namespace {

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

/// The C++ type of each PlyType, in the enum's order: the one table that the size, integrality,
/// loading and strip separator below all read.
using PlyCppTypes = std::tuple<std::int8_t, std::uint8_t, std::int16_t, std::uint16_t, std::int32_t,
                               std::uint32_t, float, double>;
static_assert(std::tuple_size_v<PlyCppTypes> == static_cast<std::size_t>(PlyType::Float64) + 1);

/// f(T{}) for the C++ type T that `type` names.
template <std::size_t I = 0, class F>
auto with_ply_type(PlyType type, F&& f) {
  if constexpr (I + 1 < std::tuple_size_v<PlyCppTypes>) {
    if (static_cast<std::size_t>(type) != I) return with_ply_type<I + 1>(type, f);
  }
  return f(std::tuple_element_t<I, PlyCppTypes>{});
}

int ply_size(PlyType type) {
  return with_ply_type(type, [](auto value) { return static_cast<int>(sizeof(value)); });
}

bool ply_is_integer(PlyType type) {
  return with_ply_type(type, [](auto value) { return std::is_integral_v<decltype(value)>; });
}

/// Reads one binary value of the given type as a double; `swap` reverses the byte order.
double ply_load(PlyType type, const char* p, bool swap) {
  return with_ply_type(
      type, [&](auto value) { return static_cast<double>(load_binary<decltype(value)>(p, swap)); });
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

/// Which properties of the vertex, face and tristrips elements carry the mesh.
struct PlyRoles {
  int vertex_element = -1, face_element = -1, strip_element = -1;
  int coordinate[3] = {-1, -1, -1};  ///< property indices of x, y, z in the vertex element
  int corners = -1;                  ///< property index of vertex_indices in the face element
  int strip_corners = -1;            ///< property index of vertex_indices in the tristrips element
};

/// What element e is for: the binary and the ASCII reader both read it off PlyRoles.
struct ElementRole {
  bool is_vertex = false, is_face = false, is_strip = false;
};

ElementRole role_of(const PlyRoles& roles, std::size_t e) {
  const int element = static_cast<int>(e);
  return {element == roles.vertex_element, element == roles.face_element,
          element == roles.strip_element};
}

/// The property of `element` that lists its corners (vertex_indices or vertex_index), or -1.
/// \throw IoError when that property is not a list of integers
int corner_property(const std::string& path, const PlyElement& element) {
  int found = -1;
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    const PlyProperty& property = element.properties[p];
    if (property.name != "vertex_indices" && property.name != "vertex_index") continue;
    if (!property.is_list || !ply_is_integer(property.type)) {
      io_error(path, element.name + " property " + property.name + " must be a list of integers");
    }
    found = static_cast<int>(p);
  }
  return found;
}

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
      roles.corners = corner_property(path, element);
    } else if (element.name == "tristrips" && roles.strip_element < 0) {
      roles.strip_element = static_cast<int>(e);
      roles.strip_corners = corner_property(path, element);
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
  auto items = [&](int element) { return element < 0 ? 0 : header.elements[element].count; };
  if (items(roles.face_element) == 0 && items(roles.strip_element) == 0) {
    io_error(path, "no faces (the PLY header declares no face or tristrips element, or 0 items)");
  }
  if (items(roles.face_element) > 0 && roles.corners < 0) {
    io_error(path, "PLY face element has no vertex_indices property");
  }
  if (items(roles.strip_element) > 0 && roles.strip_corners < 0) {
    io_error(path, "PLY tristrips element has no vertex_indices property");
  }
  return roles;
}

// The checks and messages the ASCII and binary readers share.

/// "vertex 3": an item of an element, for error messages.
std::string item_name(const PlyElement& element, std::int64_t item) {
  return element.name + " " + std::to_string(item);
}

[[noreturn]] void ends_inside(const std::string& path, Where where, const PlyElement& element,
                              std::int64_t item) {
  io_error(path, where,
           "truncated: the file ends inside " + item_name(element, item) + " of " +
               std::to_string(element.count));
}

void check_list_length(const std::string& path, Where where, const PlyElement& element,
                       std::int64_t item, const PlyProperty& property, double count) {
  if (count < 0) io_error(path, where, "negative list length in " + item_name(element, item));
  // An ASCII length is not bounded by its storage: one beyond its type's range is malformed
  // (a 100-digit length read as the largest integer overflowed the count's conversion).
  const double largest = with_ply_type(property.count_type, [](auto stored) {
    return static_cast<double>(std::numeric_limits<decltype(stored)>::max());
  });
  if (count > largest) {
    // (Integers past 2^63 were read as 2^63: not the file's digits, so not quoted.)
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.0f", count);
    io_error(path, where,
             "list length " + (count < 9e18 ? std::string(buffer) : std::string("beyond 2^63")) +
                 " in " + item_name(element, item) + " exceeds the largest value of its type (" +
                 std::to_string(static_cast<long long>(largest)) + ")");
  }
}

void check_ply_corner_count(const std::string& path, Where here, int face, double count) {
  if (count < 3) too_few_corners(path, here, face, static_cast<std::int64_t>(count));
}

void check_ply_corner(const std::string& path, Where here, int face, double index, int nv) {
  if (index < 0 || index >= nv) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.0f", index);
    bad_vertex_index(path, here, face, buffer, "outside [0, " + std::to_string(nv) + ")");
  }
}

/// Whether a tristrips list value separates two strips: -1, which an unsigned list type stores
/// as its largest value.
bool is_strip_separator(PlyType type, double value) {
  if (value == -1) return true;
  return with_ply_type(type, [&](auto stored) {
    using T = decltype(stored);
    return std::is_unsigned_v<T> && value == static_cast<double>(std::numeric_limits<T>::max());
  });
}

/// Adds the triangles of one tristrips item (`strips`: its vertex_indices list, strips separated
/// by -1) to `raw`. Triangle i of a strip s is (s_i, s_i+1, s_i+2), its first two corners swapped
/// when i is odd so that every triangle turns like the first; triangles with a repeated corner
/// (the degenerate ones that join strips) are skipped.
/// \throw InvalidInput naming the item when an index is out of range
void add_triangle_strips(const std::string& path, Where here, const PlyElement& element,
                         std::int64_t item, PlyType type, const std::vector<double>& strips, int nv,
                         RawMesh& raw) {
  std::size_t begin = 0;
  for (std::size_t end = 0; end <= strips.size(); ++end) {
    if (end < strips.size() && !is_strip_separator(type, strips[end])) {
      if (strips[end] < 0 || strips[end] >= nv) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%.0f", strips[end]);
        bad_vertex_index(path, here, raw.num_polygons(), buffer,
                         "outside [0, " + std::to_string(nv) + ") (in " + item_name(element, item) +
                             ", value " + std::to_string(end) + " of its list)");
      }
      continue;
    }
    for (std::size_t i = begin; i + 2 < end; ++i) {
      int a = static_cast<int>(strips[i]), b = static_cast<int>(strips[i + 1]);
      const int c = static_cast<int>(strips[i + 2]);
      if (a == b || b == c || a == c) continue;
      if ((i - begin) % 2 == 1) std::swap(a, b);
      raw.corners.insert(raw.corners.end(), {a, b, c});
      raw.end_polygon(here.value);
    }
    begin = end + 1;
  }
}

void read_ply_binary(const std::string& path, std::string_view data, const PlyHeader& header,
                     const PlyRoles& roles, RawMesh& raw) {
  raw.binary = true;
  const bool file_big = header.encoding == PlyEncoding::BigEndian;
  const bool swap = file_big != native_big_endian;
  std::size_t pos = header.data_start;
  const auto nv = static_cast<int>(header.elements[roles.vertex_element].count);
  std::vector<double> strips;  // a tristrips item's list
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    const auto [is_vertex, is_face, is_strip] = role_of(roles, e);
    auto need = [&](std::size_t bytes, std::int64_t item) {
      if (data.size() - pos < bytes) {
        ends_inside(path, Where{static_cast<std::int64_t>(pos), true}, element, item);
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
        check_list_length(path, Where{static_cast<std::int64_t>(pos), true}, element, item,
                          property, count);
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
        if (is_strip && roles.strip_corners == static_cast<int>(p)) {
          strips.resize(static_cast<std::size_t>(count));
          for (std::size_t k = 0; k < strips.size(); ++k) {
            strips[k] = ply_load(property.type, data.data() + pos + k * size, swap);
          }
          add_triangle_strips(path, Where{static_cast<std::int64_t>(item_start), true}, element,
                              item, property.type, strips, nv, raw);
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
  std::vector<double> strips;  // a tristrips item's list
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    const auto [is_vertex, is_face, is_strip] = role_of(roles, e);
    std::int64_t item = 0;
    std::string_view token;
    auto next_number = [&](bool integer) {
      if (!tokens.next(token)) ends_inside(path, Where{tokens.line(), false}, element, item);
      std::optional<double> value;
      if (!integer) {
        value = parse_double(token);
      } else if (const auto whole = parse_integer(token)) {
        value = static_cast<double>(*whole);
      }
      if (!value) {
        io_error(path, Where{tokens.line(), false},
                 "malformed number " + quote(token) + " in " + item_name(element, item));
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
        check_list_length(path, here, element, item, property, count);
        const bool corners = is_face && roles.corners == static_cast<int>(p);
        const bool strip = is_strip && roles.strip_corners == static_cast<int>(p);
        if (corners) check_ply_corner_count(path, here, static_cast<int>(item), count);
        strips.clear();
        for (std::int64_t k = 0; k < static_cast<std::int64_t>(count); ++k) {
          const double value = next_number(ply_is_integer(property.type));
          if (corners) {
            check_ply_corner(path, Where{tokens.line(), false}, static_cast<int>(item), value, nv);
            raw.corners.push_back(static_cast<int>(value));
          }
          if (strip) strips.push_back(value);
        }
        if (strip) add_triangle_strips(path, here, element, item, property.type, strips, nv, raw);
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

}  // namespace

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

}  // namespace ricci::io_detail
