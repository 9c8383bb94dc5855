#include "ricci/render/param_pictures.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>

#include "ricci/errors.hpp"

namespace ricci {

ParamPicturesResult write_parameterization_pictures(const std::string& folder,
                                                    const MeshParamResult& result,
                                                    const ParamPicturesOptions& options) {
  namespace fs = std::filesystem;
  if (result.uv.rows() == 0 || result.cut_mesh.triangles.rows() != result.mesh.num_faces()) {
    throw InvalidInput("write_parameterization_pictures: the parameterization has no layout");
  }
  std::error_code error;
  fs::create_directories(folder, error);
  if (error || !fs::is_directory(folder)) {
    throw IoError(folder + ": cannot create the pictures folder" +
                  (error ? ": " + error.message() : std::string()));
  }
  ParamPicturesResult written;
  auto path = [&](const char* name) {
    written.files.push_back((fs::path(folder) / name).string());
    return written.files.back();
  };

  const Mesh& mesh = result.mesh;
  const Triangles& uv_triangles = result.cut_mesh.triangles;
  write_png(path("render.png"),
            render_textured_mesh(mesh, uv_triangles, result.uv, options.render).image);
  write_svg(path("uv.svg"), plot_uv_layout_svg(mesh, uv_triangles, result.uv, options.uv));
  write_png(path("uv.png"), plot_uv_layout(mesh, uv_triangles, result.uv, options.uv));

  // Newton's history, and the gradient flow from the same start to the same target.
  std::vector<ConvergenceCurve> curves;
  if (!result.components.empty()) {
    // Several components: Newton on the (up to four) largest that went by the flow.
    std::vector<int> order;
    for (std::size_t c = 0; c < result.components.size(); ++c) {
      const ComponentParam& comp = result.components[c];
      if (comp.method == ComponentMethod::Flow && !comp.param.flow.components.empty()) {
        order.push_back(static_cast<int>(c));
      }
    }
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return result.components[a].faces.size() > result.components[b].faces.size();
    });
    const std::array<Rgb, 4> colours{
        {{0.12, 0.35, 0.75}, {0.80, 0.15, 0.10}, {0.10, 0.55, 0.20}, {0.55, 0.30, 0.65}}};
    for (std::size_t i = 0; i < std::min<std::size_t>(order.size(), 4); ++i) {
      const ComponentParam& comp = result.components[order[i]];
      curves.push_back(convergence_curve("Newton, component " + std::to_string(order[i]),
                                         comp.param.flow.components.front().flow.history,
                                         colours[i]));
    }
  } else if (!result.flow.components.empty()) {
    curves.push_back(convergence_curve("Newton", result.flow.components.front().flow.history,
                                       {0.12, 0.35, 0.75}));
  }
  if (result.components.empty() && result.flow.components.size() == 1 &&
      mesh.num_vertices() < options.gradient_max_vertices) {
    FlowOptions gradient;
    gradient.solver = FlowSolver::Gradient;
    gradient.tolerance = options.gradient_tolerance;
    gradient.max_iterations = options.gradient_max_iterations;
    const auto start = std::chrono::steady_clock::now();
    gradient.progress = [&](const IterationRecord&) {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() <
             options.gradient_max_seconds;
    };
    const FlowResult flow =
        ricci_flow(result.flow.intrinsic.topology(), result.flow.structure.structure,
                   result.flow.target, gradient);
    curves.push_back(convergence_curve("gradient flow", flow.history, {0.80, 0.15, 0.10}));
    written.gradient_ran = true;
    written.gradient_iterations = flow.iterations;
    written.gradient_max_error = flow.max_error;
    written.gradient_status = flow_status_name(flow.status);
  }
  ConvergencePlotOptions plot = options.convergence;
  if (plot.title.empty()) {
    plot.title = "Ricci flow to the flat metric: " + std::to_string(mesh.num_vertices()) +
                 " vertices, " + std::to_string(result.cones.size()) + " cones";
  }
  // A flow that started converged (every error exactly 0) has nothing to show on a log axis.
  const bool something_to_plot = std::any_of(curves.begin(), curves.end(), [](const auto& c) {
    return std::any_of(c.max_error.begin(), c.max_error.end(),
                       [](double e) { return std::isfinite(e) && e > 0; });
  });
  if (something_to_plot) {
    write_png(path("convergence.png"), plot_convergence(curves, plot));
    write_svg(path("convergence.svg"), plot_convergence_svg(curves, plot));
  }
  if (options.web_viewer && web_viewer_available()) {
    WebViewerOptions viewer = options.viewer;
    if (viewer.title.empty()) {
      viewer.title = "parameterization: " + std::to_string(mesh.num_vertices()) + " vertices, " +
                     std::to_string(result.cones.size()) + " cones";
    }
    write_web_viewer(path("view.html"), mesh, uv_triangles, result.uv, viewer);
  }
  return written;
}

}  // namespace ricci
