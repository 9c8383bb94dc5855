#pragma once
/// \file
/// Access to the real meshes of ../shared/meshes for tests that run only where it exists.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ricci::testing {

/// One row of shared/meshes/MANIFEST.tsv.
struct SharedMesh {
  std::string file;  ///< file name, e.g. "bunny.obj"
  std::string path;  ///< full path
  int faces = 0, vertices = 0, boundary_loops = 0, euler_characteristic = 0;
  int genus = -1;         ///< -1 where the manifest says n/a
  bool manifold = false;  ///< manifold and orientable (the manifest's "manifold" and notes)
  bool orientable = true;
  std::string notes;
};

/// The shared meshes folder: $RICCI_SHARED_MESHES, else ../shared/meshes beside the checkout;
/// nullopt when it does not exist.
std::optional<std::string> shared_meshes_dir();

/// Every mesh listed in MANIFEST.tsv whose file exists; empty when the folder is missing.
std::vector<SharedMesh> shared_meshes();

/// The shared meshes that carry a hyperbolic metric without cones: manifold, closed, genus >= 2.
std::vector<SharedMesh> closed_hyperbolic_shared_meshes();

/// A folder for test outputs ($RICCI_TEST_TMP or the system temporary folder), created on demand.
std::string test_tmp_dir();

/// The folder `name` under test_tmp_dir(), created on demand: one per suite, so that file names
/// cannot clash with suites that ctest runs at the same time.
std::filesystem::path suite_tmp_dir(const std::string& name);

/// The same folder emptied first: a fresh folder for one test.
std::filesystem::path fresh_tmp_dir(const std::string& name);

/// Writes `content` to `path` (bytes as given, the file truncated), creating its folder; returns
/// the path as a string.
std::string write_text_file(const std::filesystem::path& path, const std::string& content);

/// The bytes of the file at `path` (empty when it cannot be read).
std::string read_text_file(const std::filesystem::path& path);

}  // namespace ricci::testing

/// Skips the current test when the shared meshes folder is missing.
#define RICCI_REQUIRE_SHARED_MESHES()                                        \
  do {                                                                       \
    if (!::ricci::testing::shared_meshes_dir())                              \
      GTEST_SKIP() << "../shared/meshes not found: skipping real-mesh test"; \
  } while (0)
