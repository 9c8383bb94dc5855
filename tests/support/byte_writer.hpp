#pragma once
/// \file
/// Builds binary mesh files (PLY, STL, binary OFF) in tests, in a chosen byte order.

#include <algorithm>
#include <bit>
#include <cstring>
#include <string>

namespace ricci::testing {

/// Appends binary values in a chosen byte order, and text, to a byte string.
class ByteWriter {
 public:
  explicit ByteWriter(bool big_endian)
      : swap_(big_endian != (std::endian::native == std::endian::big)) {}
  /// Appends `value`'s bytes in the writer's byte order.
  template <class T>
  ByteWriter& put(T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (swap_) std::reverse(bytes, bytes + sizeof(T));
    data_.append(bytes, sizeof(T));
    return *this;
  }
  /// Appends `s` as it is.
  ByteWriter& text(const std::string& s) {
    data_ += s;
    return *this;
  }
  /// The bytes so far.
  const std::string& data() const { return data_; }

 private:
  bool swap_;
  std::string data_;
};

}  // namespace ricci::testing
