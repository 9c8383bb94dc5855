#include "render/detail/indexed_png.hpp"

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <vector>

#ifdef RICCI_LIBPNG_SONAME
#include <png.h>

#include "numerics/detail/shared_library.hpp"
#endif

namespace ricci::render_detail {

#ifdef RICCI_LIBPNG_SONAME
namespace {

/// libpng's simplified writing API (1.6), the two functions it takes.
struct PngLibrary {
  decltype(&png_image_write_to_memory) write_to_memory = nullptr;
  decltype(&png_image_free) free = nullptr;
};

/// libpng, opened at the first call; nullptr members when it cannot be (the caller falls back).
const PngLibrary& png_api() {
  static std::once_flag once;
  static PngLibrary library;
  std::call_once(once, [] {
    std::string why;
    void* handle =
        shared_library::open({RICCI_LIBPNG_SONAME, RICCI_LIBPNG_PATH}, RTLD_NOW | RTLD_LOCAL, why);
    if (handle == nullptr) return;
    PngLibrary l;
    if (shared_library::find(handle, "png_image_write_to_memory", l.write_to_memory) &&
        shared_library::find(handle, "png_image_free", l.free)) {
      library = l;
    }
  });
  return library;
}

/// The image's colours (as 0xRRGGBB, in the order they first appear) and each pixel's index
/// among them; nullopt when a pixel is not opaque or there are more than kMaxPaletteColours
/// colours.
struct Indexed {
  std::vector<std::uint32_t> colours;
  std::vector<png_byte> index;
};
std::optional<Indexed> index_colours(const Image& image) {
  Indexed out;
  out.index.resize(image.pixels.size());
  // Pictures with few colours come in runs: one comparison per pixel of a run, a search of the
  // palette where a run starts.
  std::uint32_t last = 0;
  png_byte last_index = 0;
  bool have_last = false;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const std::uint32_t p = image.pixels[i];
    if (!have_last || p != last) {
      if ((p >> 24) != 0xFFu) return std::nullopt;
      const std::uint32_t rgb = p & 0xFFFFFFu;
      const auto at = std::find(out.colours.begin(), out.colours.end(), rgb);
      const auto found = static_cast<int>(at - out.colours.begin());
      if (found == static_cast<int>(out.colours.size())) {
        if (found == kMaxPaletteColours) return std::nullopt;
        out.colours.push_back(rgb);
      }
      last = p;
      last_index = static_cast<png_byte>(found);
      have_last = true;
    }
    out.index[i] = last_index;
  }
  return out;
}

}  // namespace

std::optional<std::string> encode_indexed_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height) {
    return std::nullopt;
  }
  std::optional<Indexed> indexed = index_colours(image);
  if (!indexed) return std::nullopt;
  const PngLibrary& png = png_api();
  if (png.write_to_memory == nullptr) return std::nullopt;
  std::vector<png_byte> palette;
  for (const std::uint32_t c : indexed->colours) {
    palette.push_back(static_cast<png_byte>(c >> 16));
    palette.push_back(static_cast<png_byte>(c >> 8));
    palette.push_back(static_cast<png_byte>(c));
  }
  png_image description{};
  description.version = PNG_IMAGE_VERSION;
  description.width = static_cast<png_uint_32>(image.width);
  description.height = static_cast<png_uint_32>(image.height);
  description.format = PNG_FORMAT_RGB_COLORMAP;
  description.colormap_entries = static_cast<png_uint_32>(indexed->colours.size());
  // The size first (no memory), then the bytes; libpng picks the bit depth from the entries.
  png_alloc_size_t size = 0;
  if (png.write_to_memory(&description, nullptr, &size, 0, indexed->index.data(), 0,
                          palette.data()) == 0) {
    png.free(&description);
    return std::nullopt;
  }
  std::string bytes(size, '\0');
  const int written = png.write_to_memory(&description, bytes.data(), &size, 0,
                                          indexed->index.data(), 0, palette.data());
  png.free(&description);
  if (written == 0) return std::nullopt;
  bytes.resize(size);
  return bytes;
}

#else

std::optional<std::string> encode_indexed_png(const Image&) {
  return std::nullopt;
}

#endif

}  // namespace ricci::render_detail
