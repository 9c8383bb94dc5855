// The options of `ricci param`, registered in one place: `ricci batch` checks the options it
// passes on against the same parser.
#include <CLI/CLI.hpp>
#include <set>

#include "param_command.hpp"
#include "ricci/errors.hpp"

namespace ricci::cli {

CLI::App* add_param_subcommand(CLI::App& app, ParamArgs& param) {
  CLI::App* param_cmd = app.add_subcommand(
      "param",
      "Global conformal parameterization: cones, Ricci flow to a flat metric, cut graph, "
      "layout; writes an OBJ with per-corner texture coordinates in the unit square, on the "
      "input's own faces (a quad or polygon mesh keeps its polygons). A mesh "
      "of several components gets one atlas: each component parameterized on its own, the "
      "charts packed into the unit square.");
  param_cmd->add_option("MESH", param.mesh, "mesh file (.obj .off .ply .stl)")->required();
  param_cmd->add_option("-o,--output", param.output, "output .obj with vt coordinates")->required();
  param_cmd
      ->add_option("--cones", param.cones,
                   "needed (none where the topology allows: surfaces with boundary and tori; "
                   "automatic otherwise), auto (automatic until --max-log-scale holds), N (that "
                   "many automatic cones), none, one (all curvature at one cone, genus >= 2), or "
                   "cones as 'V:K,...' or a file")
      ->capture_default_str();
  param_cmd->add_option("--boundary", param.boundary, "free, disk or disk-length")
      ->capture_default_str();
  param_cmd
      ->add_option("--seams", param.seams,
                   "rigid (the flat metric with cones: all curvature at the cones, each seam's "
                   "two copies related by a rigid motion) or free (the cones and cut as chosen, "
                   "then the seams carry the curvature that distorts least, both copies of every "
                   "seam edge one length: texel density continuous across seams, what BFF writes "
                   "on genus >= 1; far fewer cones do on high genus)")
      ->capture_default_str()
      ->check(CLI::IsMember(enum_primary_names<SeamMode>()));
  param_cmd
      ->add_option("--flips", param.flips,
                   "intrinsic Delaunay edge flips (see ricci flow --help); the output keeps the "
                   "input's own faces, each vertex at its image in the final (flat or "
                   "hyperbolic) metric")
      ->capture_default_str();
  param_cmd->add_option("--scheme", param.scheme, "discrete metric (see ricci flow --help)")
      ->capture_default_str();
  param_cmd
      ->add_option("--geometry", param.geometry,
                   "euclidean (flat metric with cones; uv in the unit square) or hyperbolic "
                   "(chi < 0: the uniformization metric, no cones, geodesic boundary; uv in the "
                   "Poincare disk; deck transformations and Fuchsian generators in the report; "
                   "--pictures draws the tiling of the disk)")
      ->capture_default_str();
  param_cmd
      ->add_option("--faces", param.faces,
                   "input: the input's faces (quads and polygons included, one vt per corner, "
                   "no seam inside one) with linear texture coordinates; refinement "
                   "(vertex-scaling): the common refinement of the input and the final intrinsic "
                   "triangulation with homogeneous texture coordinates 'vt u v w' (divided by w "
                   "per pixel they give the exact map), written to -o, beside it STEM.linear.obj "
                   "(the same with linear uv), STEM.vertex_map.txt and STEM.spmat (the "
                   "interpolation matrix); docs/parameterization.md")
      ->capture_default_str()
      ->check(CLI::IsMember({"input", "refinement"}));
  param_cmd->add_flag("--quantize", param.quantize, "round cone curvatures to multiples of pi/2");
  param_cmd
      ->add_option("--max-log-scale", param.max_log_scale,
                   "automatic cones: add cones until max |log area scale| away from the cones "
                   "is below this (on a closed genus-0 surface also until the area distortion "
                   "E is below 0.5)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  param_cmd
      ->add_option("--max-cones", param.max_cones,
                   "automatic cones: at most this many (0: no cap; --cones auto stops at "
                   "--max-log-scale, or once doubling the cones helps by less than 5 %)")
      ->capture_default_str();
  param_cmd
      ->add_option("--cone-smoothness", param.cone_smoothness,
                   "automatic cones: weight of angle distortion against area distortion when "
                   "curvatures are chosen (they minimise log(1 + E) + W D / #F, D the Dirichlet "
                   "energy of the log scale; 0: area distortion alone; docs/cones.md)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  param_cmd
      ->add_option("--polish", param.polish,
                   "angles: after the layout, move the vertices on no seam and no boundary to "
                   "lower the mean angle distortion (seams, cones and boundary stay exact); none: "
                   "the discrete conformal map itself, every edge as long as the flat metric says "
                   "(--faces refinement always is); docs/cones.md")
      ->capture_default_str()
      ->check(CLI::IsMember({"angles", "none"}));
  param_cmd
      ->add_option("--fold-free", param.fold_free,
                   "where the exact map draws faces flipped: charts (untangle them, seams, cones "
                   "and boundary kept exact; a component that still folds, whose layout does "
                   "not close up or whose automatic cones cannot carry the curvature is cut into "
                   "charts flattened with free boundary, every seam its 3D length), untangle "
                   "(untangle only), none (the exact map as it is); a layout that still folds "
                   "exits 3; docs/parameterization.md")
      ->capture_default_str()
      ->check(CLI::IsMember({"charts", "untangle", "none"}));
  param_cmd
      ->add_option("--gutter", param.gutter,
                   "several components: space between packed charts, in uv units")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.25));
  param_cmd->add_option("--tol", param.tolerance, "flow tolerance on max |K-bar - K|")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  param_cmd->add_option("--report", param.report,
                        "write a JSON report: cones, cut, layout, atlas, distortion, flow");
  param_cmd->add_flag("--json", param.json, "print the report as JSON");
  param_cmd->add_flag("--progress", param.progress, "print flow iterations on stderr");
  add_input_options(param_cmd, param.input);
#ifdef RICCI_HAVE_RENDER
  param_cmd->add_option("--pictures", param.pictures,
                        "write render.png, uv.svg, uv.png, convergence.png and convergence.svg "
                        "into this folder (created when missing)");
#endif
  param_cmd
      ->add_option("--texture", param.texture,
                   "the OBJ's material: checker (STEM.mtl and a checkerboard STEM.png beside "
                   "the OBJ, which Blender and MeshLab show textured), none (no material), or "
                   "an image file (PNG or JPEG) the material refers to; glb embeds it")
      ->capture_default_str();
  param_cmd
      ->add_option("--format", param.format,
                   "obj (texture coordinates per corner, with its material) or glb (glTF 2.0 "
                   "binary with the texture inside); default: glb when -o ends with .glb")
      ->check(CLI::IsMember({"obj", "glb"}));
  param_cmd->add_option("--fault", param.fault)->group("");  // tests only (kFaultHelp)
  return param_cmd;
}

void check_param_options(const std::vector<std::string>& options, const std::string& where,
                         const std::string& outputs) {
  // Set by batch for every mesh: its outputs' paths, and what would print per mesh.
  static const std::set<std::string> owned = {"-o",         "--output",   "--report", "--json",
                                              "--progress", "--pictures", "-h",       "--help"};
  for (const std::string& o : options) {
    const std::string name = o.substr(0, o.find('='));
    if (owned.count(name) > 0) {
      throw InvalidInput(where + ": " + name +
                         " is set by ricci batch for every mesh (outputs go to " + outputs + ")");
    }
  }
  CLI::App app;
  ParamArgs scratch;
  add_param_subcommand(app, scratch);
  std::vector<std::string> words = {"ricci", "param", "MESH", "-o", "OUT.obj"};
  words.insert(words.end(), options.begin(), options.end());
  std::vector<const char*> argv;
  argv.reserve(words.size());
  for (const std::string& w : words) argv.push_back(w.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    throw InvalidInput(where + ": not an option of ricci param: " + e.what());
  }
}

}  // namespace ricci::cli
