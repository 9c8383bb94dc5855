#pragma once
/// \file
/// Private to the binary writers (PLY, STL): little-endian values appended to a byte buffer,
/// whatever the host's byte order.

#include <bit>
#include <cstring>
#include <string>

namespace ricci::io_detail {

/// Appends `value` to `bytes` in little-endian byte order.
template <typename T>
void append_little_endian(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  }
  bytes.append(raw, sizeof(T));
}

}  // namespace ricci::io_detail
