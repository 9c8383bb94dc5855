#pragma once
/// \file
/// Private to the picture writers: Cairo's functions, opened when a picture is first drawn.
///
/// Cairo brings some 20 libraries (pixman, fontconfig, freetype, X11, xcb, png: 1.7 ms of every
/// start of the program) which a run without pictures never uses (`ricci param --texture none`,
/// `flow`, `info`, a batch's children without pictures). So ricci_render does not link Cairo: the
/// first drawing opens it (dlopen) and takes the functions below from it; where it is missing,
/// drawing throws an error that names it. The calls read cairo_api().create(...) where Cairo's
/// own read cairo_create(...).

#include <cairo-svg.h>
#include <cairo.h>

namespace ricci::render_detail {

/// X(name) for every cairo_name the picture writers call.
#define RICCI_CAIRO_FUNCTIONS(X)   \
  X(arc)                           \
  X(clip)                          \
  X(close_path)                    \
  X(create)                        \
  X(destroy)                       \
  X(fill)                          \
  X(fill_preserve)                 \
  X(format_stride_for_width)       \
  X(image_surface_create_for_data) \
  X(image_surface_create_from_png) \
  X(image_surface_get_data)        \
  X(image_surface_get_format)      \
  X(image_surface_get_height)      \
  X(image_surface_get_stride)      \
  X(image_surface_get_width)       \
  X(line_to)                       \
  X(move_to)                       \
  X(new_path)                      \
  X(new_sub_path)                  \
  X(paint)                         \
  X(pattern_add_color_stop_rgb)    \
  X(pattern_create_linear)         \
  X(pattern_destroy)               \
  X(rectangle)                     \
  X(restore)                       \
  X(rotate)                        \
  X(save)                          \
  X(select_font_face)              \
  X(set_dash)                      \
  X(set_fill_rule)                 \
  X(set_font_size)                 \
  X(set_line_cap)                  \
  X(set_line_join)                 \
  X(set_line_width)                \
  X(set_source)                    \
  X(set_source_rgba)               \
  X(set_source_surface)            \
  X(show_text)                     \
  X(status)                        \
  X(status_to_string)              \
  X(stroke)                        \
  X(surface_destroy)               \
  X(surface_finish)                \
  X(surface_flush)                 \
  X(surface_status)                \
  X(surface_write_to_png_stream)   \
  X(svg_surface_create_for_stream) \
  X(svg_surface_set_document_unit) \
  X(text_extents)                  \
  X(translate)

/// Cairo's functions, by their names without the cairo_ prefix.
struct CairoLibrary {
// A member's name cannot be parenthesised.
// NOLINTNEXTLINE(bugprone-macro-parentheses)
#define RICCI_CAIRO_MEMBER(name) decltype(&cairo_##name) name = nullptr;
  RICCI_CAIRO_FUNCTIONS(RICCI_CAIRO_MEMBER)
#undef RICCI_CAIRO_MEMBER
};

/// Cairo, opened at the first call (once per process, thread-safe).
/// \throw IoError naming the library when it or one of its functions cannot be found
const CairoLibrary& cairo_api();

}  // namespace ricci::render_detail
