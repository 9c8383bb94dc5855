#include "ricci/mesh/io.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ostream>

#include "mesh/io/detail/readers.hpp"
#include "ricci/errors.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;
using io_detail::io_error;

std::string read_whole_file(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) io_error(path, "no such file");
  if (!fs::is_regular_file(status)) io_error(path, "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) io_error(path, std::string("cannot open: ") + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  std::string data(static_cast<std::size_t>(std::max<std::streamoff>(size, 0)), '\0');
  if (size > 0 && !in.read(data.data(), size)) io_error(path, "read failed");
  if (data.empty()) io_error(path, "empty file (0 bytes)");
  return data;
}

/// The raw polygon soup of a file's bytes, by the parser of its format.
io_detail::RawMesh parse(MeshFormat format, const std::string& path, std::string_view data) {
  switch (format) {
    case MeshFormat::Obj:
      return io_detail::parse_obj(path, data);
    case MeshFormat::Off:
      return io_detail::parse_off(path, data);
    case MeshFormat::Ply:
      return io_detail::parse_ply(path, data);
    case MeshFormat::Stl:
      return io_detail::parse_stl(path, data);
    case MeshFormat::Glb:
      io_error(path,
               "glTF binary holds a textured mesh: read_glb (ricci/render/textured_files.hpp) "
               "reads it; read_mesh reads .obj, .off, .ply or .stl");
  }
  io_error(path, "unknown mesh format");
}

/// The temporary files write_file_atomically is writing now, for remove_pending_temporary_files
/// (called from signal handlers): fixed slots of plain char buffers guarded by lock-free atomic
/// states, so that reading them needs neither locks nor allocation.
constexpr std::size_t kPendingSlots = 32;
constexpr std::size_t kPendingPathBytes = 4096;
enum PendingState : int { kSlotFree = 0, kSlotBusy = 1, kSlotPending = 2 };
struct PendingSlot {
  std::atomic<int> state{kSlotFree};
  char path[kPendingPathBytes] = {};
};
static_assert(std::atomic<int>::is_always_lock_free);
PendingSlot pending_slots[kPendingSlots];

/// Registers a temporary path for the lifetime of the guard; a path that is too long or finds no
/// free slot is written unregistered (it is then only removed on ordinary errors).
class PendingTemporary {
 public:
  explicit PendingTemporary(const std::string& path) {
    if (path.size() >= kPendingPathBytes) return;
    for (PendingSlot& slot : pending_slots) {
      int expected = kSlotFree;
      if (!slot.state.compare_exchange_strong(expected, kSlotBusy, std::memory_order_acquire)) {
        continue;
      }
      std::memcpy(slot.path, path.c_str(), path.size() + 1);
      slot.state.store(kSlotPending, std::memory_order_release);
      slot_ = &slot;
      return;
    }
  }
  ~PendingTemporary() {
    if (slot_ == nullptr) return;
    slot_->state.store(kSlotBusy, std::memory_order_release);
    slot_->path[0] = '\0';
    slot_->state.store(kSlotFree, std::memory_order_release);
  }
  PendingTemporary(const PendingTemporary&) = delete;
  PendingTemporary& operator=(const PendingTemporary&) = delete;

 private:
  PendingSlot* slot_ = nullptr;
};

}  // namespace

void remove_pending_temporary_files() noexcept {
  for (PendingSlot& slot : pending_slots) {
    if (slot.state.load(std::memory_order_acquire) == kSlotPending) ::unlink(slot.path);
  }
}

MeshFormat format_from_path(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".off") return MeshFormat::Off;
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".stl") return MeshFormat::Stl;
  if (extension == ".glb") return MeshFormat::Glb;
  io_error(path,
           "unknown mesh format " +
               (extension.empty() ? std::string("(no extension)") : io_detail::quote(extension)) +
               ": expected .obj, .off, .ply, .stl or .glb");
}

ReadResult read_mesh(const std::string& path, const ReadOptions& options) {
  const std::string data = read_whole_file(path);
  const MeshFormat format = format_from_path(path);
  return io_detail::assemble(path, format, parse(format, path, data), options);
}

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const fs::path temporary =
      folder / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                std::to_string(counter++));
  // Registered before the file exists, so that an interrupted process can remove it.
  std::error_code absolute_error;
  const fs::path absolute_temporary = fs::absolute(temporary, absolute_error);
  const PendingTemporary pending(absolute_error ? temporary.string() : absolute_temporary.string());
  try {
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) {
        throw std::runtime_error("cannot create the temporary file " + temporary.string() + ": " +
                                 std::strerror(errno));
      }
      write(out);
      out.flush();
      if (!out) throw std::runtime_error("writing " + temporary.string() + " failed");
      out.close();
      if (!out) throw std::runtime_error("closing " + temporary.string() + " failed");
    }
    fs::rename(temporary, target);
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw IoError(path + ": cannot write: " + e.what());
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw IoError(path + ": cannot write: unknown error");
  }
}

}  // namespace ricci
