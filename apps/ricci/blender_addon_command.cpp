// `ricci blender-addon`: the Blender add-on ricci_uv as a zip that Blender installs (Preferences >
// Add-ons > Install): the add-on's Python files (blender/ricci_uv, compiled into this program) and
// the compiled ricci module for Blender's Python, found beside this program or in its build tree.
#include <zip.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "numerics/detail/shared_library.hpp"
#include "ricci/errors.hpp"

// The add-on's files (cmake/BlenderAddon.cmake writes them with cmake/embed_files.cmake).
namespace ricci::cli::addon {
extern const unsigned char kInit[], kOperator[], kUnwrap[];
extern const std::size_t kInitSize, kOperatorSize, kUnwrapSize;
}  // namespace ricci::cli::addon

namespace ricci::cli {
namespace {

namespace fs = std::filesystem;

struct AddonFile {
  const char* name;  ///< inside the package ricci_uv
  const unsigned char* bytes;
  std::size_t size;
};
const AddonFile kAddonFiles[] = {
    {"__init__.py", addon::kInit, addon::kInitSize},
    {"operator.py", addon::kOperator, addon::kOperatorSize},
    {"unwrap.py", addon::kUnwrap, addon::kUnwrapSize},
};

struct AddonArgs {
  std::string output = "ricci_uv.zip";
  std::string python_package;  ///< --python-package: the folder of the ricci Python package
};

/// Whether `dir` holds the ricci Python package with its compiled module.
bool is_python_package(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / "__init__.py", ec)) return false;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("_ricci.", 0) == 0 && entry.path().extension() == ".so") return true;
  }
  return false;
}

/// The ricci Python package to ship: --python-package, RICCI_PYTHON_PACKAGE, the installed one
/// (relative to this program), the build tree's, the installed one at the configured prefix.
fs::path find_python_package(const AddonArgs& args, const char* argv0) {
  std::vector<fs::path> candidates;
  std::vector<std::string> tried;
  if (!args.python_package.empty()) {
    if (!is_python_package(args.python_package)) {
      throw InvalidInput("blender-addon: " + args.python_package +
                         " is not the ricci Python package (no __init__.py and _ricci.*.so)");
    }
    return args.python_package;
  }
  if (const char* env = std::getenv("RICCI_PYTHON_PACKAGE")) candidates.emplace_back(env);
#ifdef RICCI_PYTHON_PACKAGE_FROM_BINDIR
  std::error_code ec;
  const fs::path self = fs::canonical("/proc/self/exe", ec);
  const fs::path bindir = ec ? fs::absolute(argv0).parent_path() : self.parent_path();
  candidates.push_back(bindir / RICCI_PYTHON_PACKAGE_FROM_BINDIR);
#else
  (void)argv0;
#endif
#ifdef RICCI_PYTHON_BUILD_PACKAGE
  candidates.emplace_back(RICCI_PYTHON_BUILD_PACKAGE);
#endif
#ifdef RICCI_PYTHON_INSTALLED_PACKAGE
  candidates.emplace_back(RICCI_PYTHON_INSTALLED_PACKAGE);
#endif
  for (const fs::path& c : candidates) {
    if (is_python_package(c)) return c;
    tried.push_back(c.lexically_normal().string());
  }
  std::string list;
  for (const std::string& t : tried) list += (list.empty() ? "" : ", ") + t;
  throw InvalidInput(
      "blender-addon: the compiled ricci Python module was not found (looked in " +
      (list.empty() ? std::string("no folder: ricci was built without its Python module") : list) +
      "): build it (-DRICCI_BUILD_PYTHON=ON) or name its folder with --python-package");
}

/// The libzip functions the command calls, opened when it runs (cmake/BlenderAddon.cmake: the
/// program does not load libzip, nor libcrypto with it, for its other commands).
struct Libzip {
  decltype(&zip_open) open = nullptr;
  decltype(&zip_close) close = nullptr;
  decltype(&zip_discard) discard = nullptr;
  decltype(&zip_strerror) strerror = nullptr;
  decltype(&zip_file_add) file_add = nullptr;
  decltype(&zip_source_buffer) source_buffer = nullptr;
  decltype(&zip_source_file) source_file = nullptr;
  decltype(&zip_source_free) source_free = nullptr;
  decltype(&zip_error_init_with_code) error_init_with_code = nullptr;
  decltype(&zip_error_strerror) error_strerror = nullptr;
  decltype(&zip_error_fini) error_fini = nullptr;
};

/// Opens libzip once (kept open for the process). \throw IoError naming what is missing
const Libzip& libzip() {
  static const Libzip zip = [] {
    std::string why;
    void* handle = shared_library::open({RICCI_LIBZIP_SONAME}, RTLD_NOW | RTLD_LOCAL, why);
    if (handle == nullptr) {
      throw IoError(std::string("blender-addon: cannot open libzip (") + RICCI_LIBZIP_SONAME +
                    "): " + why + "; install it (apt install libzip4)");
    }
    Libzip z;
    const auto find = [&](auto& function, const char* name) {
      if (!shared_library::find(handle, name, function)) {
        throw IoError(std::string("blender-addon: libzip (") + RICCI_LIBZIP_SONAME + ") has no " +
                      name);
      }
    };
    find(z.open, "zip_open");
    find(z.close, "zip_close");
    find(z.discard, "zip_discard");
    find(z.strerror, "zip_strerror");
    find(z.file_add, "zip_file_add");
    find(z.source_buffer, "zip_source_buffer");
    find(z.source_file, "zip_source_file");
    find(z.source_free, "zip_source_free");
    find(z.error_init_with_code, "zip_error_init_with_code");
    find(z.error_strerror, "zip_error_strerror");
    find(z.error_fini, "zip_error_fini");
    return z;
  }();
  return zip;
}

/// Closes a zip archive being written without saving it (unless released).
struct Archive {
  Archive(const Libzip& library, zip_t* archive) : lib(library), zip(archive) {}
  const Libzip& lib;
  zip_t* zip = nullptr;
  ~Archive() {
    if (zip != nullptr) lib.discard(zip);
  }
  Archive(const Archive&) = delete;
  Archive& operator=(const Archive&) = delete;
  [[noreturn]] void fail(const std::string& what) const {
    throw IoError("blender-addon: " + what + ": " + lib.strerror(zip));
  }
  void add(const std::string& name, zip_source_t* source) {
    if (source == nullptr) fail("cannot read " + name);
    if (lib.file_add(zip, name.c_str(), source, ZIP_FL_ENC_UTF_8 | ZIP_FL_OVERWRITE) < 0) {
      lib.source_free(source);
      fail("cannot add " + name);
    }
  }
};

int run_blender_addon(const AddonArgs& args, const char* argv0) {
  const fs::path package = find_python_package(args, argv0);
  const fs::path target(args.output);
  if (target.extension() != ".zip") {
    throw InvalidInput(
        "blender-addon: the output must be a .zip (Blender installs add-ons from "
        "zips), got " +
        args.output);
  }
  // Written beside the target under another name, renamed into place when complete.
  const fs::path temporary = target.string() + ".part";
  std::error_code ec;
  fs::remove(temporary, ec);
  const Libzip& lib = libzip();
  int error = 0;
  Archive archive{lib, lib.open(temporary.c_str(), ZIP_CREATE | ZIP_EXCL, &error)};
  if (archive.zip == nullptr) {
    zip_error_t z;
    lib.error_init_with_code(&z, error);
    const std::string why = lib.error_strerror(&z);
    lib.error_fini(&z);
    throw IoError("blender-addon: cannot write " + temporary.string() + ": " + why);
  }
  int files = 0;
  for (const AddonFile& file : kAddonFiles) {
    archive.add(std::string("ricci_uv/") + file.name,
                lib.source_buffer(archive.zip, file.bytes, file.size, 0));
    ++files;
  }
  std::vector<fs::path> module_files;  // in name order: the same zip from the same files
  for (const auto& entry : fs::directory_iterator(package)) {
    const std::string name = entry.path().filename().string();
    const bool module = entry.path().extension() == ".py" || name.rfind("_ricci.", 0) == 0;
    if (entry.is_regular_file() && module) module_files.push_back(entry.path());
  }
  std::sort(module_files.begin(), module_files.end());
  for (const fs::path& file : module_files) {
    archive.add("ricci_uv/ricci/" + file.filename().string(),
                lib.source_file(archive.zip, file.c_str(), 0, 0 /* to its end */));
    ++files;
  }
  if (lib.close(archive.zip) < 0) archive.fail("cannot write " + temporary.string());
  archive.zip = nullptr;
  fs::rename(temporary, target);
  std::cout << "wrote " << target.string() << ": the add-on ricci_uv (" << files
            << " files, the ricci module from " << package.string() << ")\n"
            << "install: Blender > Edit > Preferences > Add-ons > Install, or\n"
            << "  blender -b --python-expr \"import bpy; bpy.ops.preferences.addon_install("
            << "filepath='" << fs::absolute(target).string()
            << "'); bpy.ops.preferences.addon_enable(module='ricci_uv'); "
            << "bpy.ops.wm.save_userpref()\"\n";
  return kOk;
}

}  // namespace

Subcommand add_blender_addon_command(CLI::App& app, const char* argv0) {
  auto args = std::make_shared<AddonArgs>();
  CLI::App* c = app.add_subcommand(
      "blender-addon",
      "Write the Blender add-on ricci_uv (UV > ricci Unwrap) as a zip to install in Blender");
  c->add_option("-o,--output", args->output, "the zip to write")->capture_default_str();
  c->add_option("--python-package", args->python_package,
                "folder of the ricci Python package to ship (default: the one built or "
                "installed with this program)");
  return {c, [args, argv0] { return run_blender_addon(*args, argv0); }};
}

}  // namespace ricci::cli
