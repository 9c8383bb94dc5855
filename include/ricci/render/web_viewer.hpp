#pragma once
/// \file
/// An interactive viewer of a texture layout as one self-contained HTML file (`ricci view`,
/// `ricci param --pictures`): the textured surface on the left (orbit controls, a checkerboard
/// whose scale the page changes, seams, cones, colouring by area or angle distortion), the
/// texture layout on the right; hovering a face shows its distortion and highlights it in both
/// views. three.js (Debian's libjs-three, MIT licence, its notice kept) is inlined, so the page
/// needs no network; the mesh travels as base64 typed arrays in a JSON block (one draw call per
/// view, about 60 bytes of file per face).

#include <array>
#include <cstddef>
#include <string>

#include <Eigen/Core>

#include "ricci/enum_names.hpp"
#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// What the faces are coloured by when the page opens (the page's menu changes it).
enum class ViewerColouring {
  Checker,  ///< the checkerboard of the texture coordinates
  Area,     ///< ln(A_uv / A_3d), both normalised to total 1: blue (shrunk) .. white .. red
  Angle,    ///< sigma_max / sigma_min of the map from the 3D triangle to its layout: white .. red
};

/// "checker", "area", "angle": what `ricci view --colour` parses and the page's menu shows.
template <>
struct EnumNames<ViewerColouring> {
  static constexpr const char* noun = "colouring";
  static constexpr std::array<EnumName<ViewerColouring>, 3> names{{
      {ViewerColouring::Checker, "checker"},
      {ViewerColouring::Area, "area"},
      {ViewerColouring::Angle, "angle"},
  }};
};

/// Options of web_viewer_html and write_web_viewer.
struct WebViewerOptions {
  std::string title;  ///< the page's title and heading; empty: "ricci viewer"
  /// #UV homogeneous weights w > 0 (TexturedMesh::uv_weights): the surface's checker follows
  /// (w u, w v, w) interpolated over each face and divided by w per pixel (the common
  /// refinement's projective map); empty: linear interpolation of uv. The layout view and the
  /// per-face figures use the corners' uv either way.
  Eigen::VectorXd uv_weights;
  double checker = 16;  ///< checker squares per unit of texture coordinate when the page opens
  ViewerColouring colouring = ViewerColouring::Checker;  ///< colouring when the page opens
  double cone_tolerance = 1e-6;                          ///< see analyse_uv_chart
};

/// What the page holds.
struct WebViewerInfo {
  int vertices = 0;             ///< #V
  int faces = 0;                ///< #F
  int texture_coordinates = 0;  ///< #UV
  bool projective = false;      ///< uv_weights were given
  int seam_edges = 0;           ///< UvChart::seam_edges
  int seam_halfedges = 0;       ///< UvChart::seam_halfedges.size()
  int cones = 0;                ///< UvChart::cones.size()
  int flipped_faces = 0;        ///< layout triangles with negative signed area
  int degenerate_faces = 0;     ///< faces whose distortion is not defined (NaN), e.g. zero area
  /// Colour ranges the page opens with: |ln area ratio| mapped onto full blue or red
  /// (min(2, largest)), and sigma_max / sigma_min - 1 mapped onto full red (min(2, largest)).
  double log_area_range = 0, angle_range = 0;
  std::size_t bytes = 0;  ///< size of the page
};

/// True when this build carries three.js (found at configure time in
/// /usr/share/javascript/three, Debian's libjs-three); web_viewer_html throws otherwise.
bool web_viewer_available();

/// The page as text.
/// \param mesh positions (#V by 3) and triangles (#F by 3)
/// \param uv_triangles #F by 3 indices into uv (per-corner texture coordinates)
/// \param uv #UV by 2 texture coordinates (for homogeneous ones: divided by w)
/// \param info when given, receives the counts and the page's size
/// \pre every face has a finite, positive total 3D area (faces of zero area are shown without
///      distortion figures)
/// \throw InvalidInput as check_uv_layout, on non-finite positions or uv, on uv_weights of
///        the wrong size or not finite and positive, on a mesh without faces or of zero area
/// \throw IoError when this build has no three.js (web_viewer_available)
std::string web_viewer_html(const Mesh& mesh, const Triangles& uv_triangles,
                            const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                            const WebViewerOptions& options = {}, WebViewerInfo* info = nullptr);

/// Writes the page to `path` atomically (write_file_atomically), streamed: a mesh of a million
/// faces never sits in memory as text.
/// \throw InvalidInput, IoError as web_viewer_html; IoError naming the file when it cannot be
///        written
WebViewerInfo write_web_viewer(const std::string& path, const Mesh& mesh,
                               const Triangles& uv_triangles,
                               const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                               const WebViewerOptions& options = {});

}  // namespace ricci
