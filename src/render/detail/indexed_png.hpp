#pragma once
/// \file
/// Private to image.cpp: PNG files of pictures with few colours, written as palette images.
///
/// Cairo writes every picture as 8-bit RGB (RGBA where a pixel is translucent): the default
/// texture of `ricci param` (a 1024 x 1024 checkerboard of two colours) is 3 MB of samples to
/// filter and deflate, 25-30 ms of a run whose parameterization of a small mesh takes 10. As a
/// palette image of two entries (one bit a pixel, 128 KB) libpng writes it in about a millisecond.
/// libpng is opened when first needed (dlopen), as Cairo is; where it cannot be, pictures go
/// through Cairo as before.

#include <optional>
#include <string>

#include "ricci/render/image.hpp"

namespace ricci::render_detail {

/// Palette images hold at most this many colours.
constexpr int kMaxPaletteColours = 256;

/// The PNG file's bytes of `image` as a palette image, when every pixel is opaque and the image
/// has at most kMaxPaletteColours distinct colours (the smallest bit depth that holds them:
/// 1, 2, 4 or 8). Decoded, the file gives back every pixel exactly. nullopt when the image does
/// not qualify, or libpng cannot be opened or fails: the caller writes it some other way.
std::optional<std::string> encode_indexed_png(const Image& image);

}  // namespace ricci::render_detail
