// libFuzzer target: one of the mesh readers (the format is chosen at compile time by
// RICCI_FUZZ_EXTENSION, e.g. ".obj"). The input bytes are written to a per-process temporary
// file and read with validation on. A ricci::Error is the documented answer to a bad file; any
// other exception, a crash or a sanitizer report is a finding.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"

#ifndef RICCI_FUZZ_EXTENSION
#error "define RICCI_FUZZ_EXTENSION, e.g. \".obj\""
#endif

namespace {

// One path per process, so that parallel fuzzing jobs (-jobs=N) do not share a file.
const std::string& temp_path() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    std::filesystem::path base = dir != nullptr && *dir != '\0'
                                     ? std::filesystem::path(dir)
                                     : std::filesystem::temp_directory_path();
    return (base / ("ricci-fuzz-" + std::to_string(::getpid()) + RICCI_FUZZ_EXTENSION)).string();
  }();
  return path;
}

struct RemoveAtExit {
  ~RemoveAtExit() { std::remove(temp_path().c_str()); }
};
RemoveAtExit remove_at_exit;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(temp_path(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) {
      std::fprintf(stderr, "fuzz: cannot write %s\n", temp_path().c_str());
      std::abort();
    }
  }
  try {
    ricci::ReadOptions options;
    options.validate = true;
    const ricci::ReadResult result = ricci::read_mesh(temp_path(), options);
    // A mesh that passed validation must be internally consistent.
    const auto& mesh = result.mesh;
    if (mesh.triangles.size() > 0 &&
        (mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= mesh.num_vertices())) {
      std::fprintf(stderr, "fuzz: validated mesh has a face index out of range\n");
      std::abort();
    }
    if (!mesh.positions.allFinite()) {
      std::fprintf(stderr, "fuzz: validated mesh has a non-finite coordinate\n");
      std::abort();
    }
    if (static_cast<int>(result.vertex_map.size()) != mesh.num_vertices()) {
      std::fprintf(stderr, "fuzz: vertex_map has %zu entries for %d vertices\n",
                   result.vertex_map.size(), mesh.num_vertices());
      std::abort();
    }
  } catch (const ricci::Error&) {
    // The documented answer to a malformed or defective file.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: read_mesh threw a non-ricci exception: %s\n", e.what());
    std::abort();
  }
  return 0;
}
