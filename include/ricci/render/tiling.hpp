#pragma once
/// \file
/// The tiling of the Poincare disk by a fundamental domain and its images under a Fuchsian group:
/// the unit circle, the domain (a triangle mesh in the disk) filled in one colour with its mesh
/// edges faint, and its images g(D) for the group elements g enumerated breadth first by word
/// length in the generators and their inverses, each filled with a colour of its word length (or
/// of its last generator) and outlined. PNG through an Image, SVG as text.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/numerics/mobius.hpp"
#include "ricci/render/image.hpp"

namespace ricci {

/// Options of the tiling pictures.
struct TilingOptions {
  int size = 1024;          ///< width and height, pixels (SVG: px)
  int max_word_length = 8;  ///< longest word in the generators (inverses included) drawn
  /// Images whose Euclidean diameter is below this many pixels are neither drawn nor used to
  /// reach longer words (they only get smaller towards the circle).
  double min_image_pixels = 3.0;
  int max_images = 20000;                 ///< stop after drawing this many images
  bool colour_by_last_generator = false;  ///< otherwise by word length
  bool draw_mesh_edges = true;            ///< the domain's triangle edges, faint
  double edge_width = 0.4;                ///< pixels, the domain's mesh edges
  double outline_width = 1.0;             ///< pixels, the outlines (thinner on small images)
  Rgb domain_colour{0.93, 0.45, 0.13};
  Rgb background{1.0, 1.0, 1.0};      ///< outside the unit disk
  Rgb disk_colour{0.96, 0.96, 0.96};  ///< inside the disk, where no image is drawn
};

/// What the tiling pictures return besides the picture.
struct TilingInfo {
  int images_drawn = 0;      ///< images g(D) drawn, g not the identity (the domain is extra)
  int images_too_small = 0;  ///< images below min_image_pixels, not drawn
  int duplicates = 0;    ///< words reaching an element already found (same image of the reference)
  int longest_word = 0;  ///< word length of the last image drawn
  bool reached_max_images = false;
  int boundary_loops = 0;  ///< closed boundary loops of the domain (1 for a disk)
};

/// The tiling as a raster picture.
/// \param positions #V by 2 points of the open unit disk (the fundamental domain's layout)
/// \param triangles #F by 3 vertex indices, counter-clockwise
/// \param generators maps of the group (e.g. the segment maps, which pair the domain's sides, so
///        that breadth first search grows the tiling through neighbouring tiles; canonical
///        generators work too); their inverses are added
/// \throw InvalidInput on a picture size outside [16, 16384], an option out of range, a position
///        not finite or not inside the unit circle, a vertex index out of range, no triangles, or
///        a generator whose determinant is not positive
Image draw_tiling(const Eigen::Matrix<double, Eigen::Dynamic, 2>& positions,
                  const Triangles& triangles, const std::vector<Mobius>& generators,
                  const TilingOptions& options = {}, TilingInfo* info = nullptr);

/// The same picture as SVG text: one `<path>` element for the disk, one per image (fill and
/// outline together), one for the domain (fill and outline), one for its mesh edges (when
/// drawn) and one for the unit circle.
/// \throw InvalidInput as draw_tiling
std::string draw_tiling_svg(const Eigen::Matrix<double, Eigen::Dynamic, 2>& positions,
                            const Triangles& triangles, const std::vector<Mobius>& generators,
                            const TilingOptions& options = {}, TilingInfo* info = nullptr);

}  // namespace ricci
