#pragma once
/// \file
/// The library's version, as CMake's project() declares it ("0.1.0").

namespace ricci {

/// The version this library was built as.
const char* version();

}  // namespace ricci
