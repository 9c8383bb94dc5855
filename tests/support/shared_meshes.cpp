#include "support/shared_meshes.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ricci::testing {

std::optional<std::string> shared_meshes_dir() {
  std::string dir = RICCI_DEFAULT_SHARED_MESHES;
  if (const char* env = std::getenv("RICCI_SHARED_MESHES")) dir = env;
  if (std::filesystem::is_regular_file(std::filesystem::path(dir) / "MANIFEST.tsv")) return dir;
  return std::nullopt;
}

std::vector<SharedMesh> shared_meshes() {
  std::vector<SharedMesh> out;
  const auto dir = shared_meshes_dir();
  if (!dir) return out;
  std::ifstream in(std::filesystem::path(*dir) / "MANIFEST.tsv");
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cols;
    std::stringstream ss(line);
    std::string col;
    while (std::getline(ss, col, '\t')) cols.push_back(col);
    if (cols.size() < 11) continue;
    SharedMesh m;
    m.file = cols[0];
    m.path = (std::filesystem::path(*dir) / m.file).string();
    m.faces = std::stoi(cols[5]);
    m.vertices = std::stoi(cols[6]);
    m.boundary_loops = std::stoi(cols[7]);
    m.euler_characteristic = std::stoi(cols[8]);
    m.genus = (cols[9].find("n/a") == std::string::npos) ? std::stoi(cols[9]) : -1;
    m.notes = cols.size() > 11 ? cols[11] : "";
    m.orientable = m.notes.find("orientable=no") == std::string::npos;
    m.manifold = cols[10] == "yes" && m.orientable;
    if (std::filesystem::exists(m.path)) out.push_back(m);
  }
  return out;
}

std::vector<SharedMesh> closed_hyperbolic_shared_meshes() {
  std::vector<SharedMesh> out;
  for (const SharedMesh& m : shared_meshes()) {
    if (m.manifold && m.genus >= 2 && m.boundary_loops == 0) out.push_back(m);
  }
  return out;
}

std::string test_tmp_dir() {
  std::filesystem::path dir;
  if (const char* env = std::getenv("RICCI_TEST_TMP")) {
    dir = env;
  } else {
    dir = std::filesystem::temp_directory_path() / "ricci_tests";
  }
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::filesystem::path suite_tmp_dir(const std::string& name) {
  std::filesystem::path dir = std::filesystem::path(test_tmp_dir()) / name;
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path fresh_tmp_dir(const std::string& name) {
  std::filesystem::path dir = std::filesystem::path(test_tmp_dir()) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string write_text_file(const std::filesystem::path& path, const std::string& content) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  return path.string();
}

std::string read_text_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream content;
  content << in.rdbuf();
  return content.str();
}

}  // namespace ricci::testing
