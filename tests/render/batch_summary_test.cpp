// The batch summary picture of synthetic summaries: its size, something drawn in each panel in
// that panel's colour, the empty distortion panel, and what it refuses.

#include "ricci/render/batch_summary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"

namespace ricci {
namespace {

/// 40 Ok meshes (seconds 0.05 .. 200 spread over the decades, angle distortion 1 .. 1.8), 3
/// crashed, 2 timed out.
BatchSummary synthetic_summary() {
  BatchSummary s;
  s.total = 45;
  s.counts = {{"ok", 40},           {"bad_input", 0}, {"not_converged", 0}, {"internal_error", 0},
              {"out_of_memory", 0}, {"crashed", 3},   {"timed_out", 2},     {"spawn_failed", 0}};
  for (int i = 0; i < 45; ++i) {
    s.all_seconds.push_back(0.05 * std::pow(4000.0, i / 44.0));
    if (i < 40) s.all_angle_distortion.push_back(1.0 + 0.8 * std::sqrt(i / 39.0));
  }
  s.seconds = percentiles(s.all_seconds);
  s.angle_distortion = percentiles(s.all_angle_distortion);
  s.wall_seconds = 120;
  return s;
}

/// Pixels of each third of the picture (panels a, b, c) by what they look like.
struct PanelPixels {
  int drawn = 0;        ///< not white
  int green = 0;        ///< the Ok bar
  int red = 0;          ///< failure bars
  int blue = 0;         ///< seconds histogram
  int orange = 0;       ///< distortion histogram
  int dark_centre = 0;  ///< dark pixels in the panel's middle third across and down (text)
};

std::vector<PanelPixels> panel_pixels(const Image& image) {
  std::vector<PanelPixels> panels(3);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      PanelPixels& p = panels[std::min(2, 3 * x / image.width)];
      const Rgb c = unpack_rgb(image.at(x, y));
      p.drawn += c.r < 0.95 || c.g < 0.95 || c.b < 0.95;
      p.green += c.g > 0.5 && c.r < 0.35 && c.b < 0.45;
      p.red += c.r > 0.7 && c.g < 0.35 && c.b < 0.35;
      p.blue += c.b > 0.6 && c.r < 0.3 && c.g < 0.5;
      p.orange += c.r > 0.75 && c.g > 0.4 && c.g < 0.6 && c.b < 0.2;
      const int panel_x = 9 * x / image.width % 3;  // 1: the middle third of the panel
      p.dark_centre += panel_x == 1 && y > image.height / 3 && y < 2 * image.height / 3 &&
                       c.r < 0.3 && c.g < 0.3 && c.b < 0.3;
    }
  }
  return panels;
}

TEST(BatchSummaryPicture, PngHasThreePanels) {
  const auto path = testing::render_tmp_dir() / "batch_summary.png";
  write_batch_summary_picture(synthetic_summary(), path.string());
  const Image back = read_png(path.string());
  EXPECT_EQ(back.width, 1500);
  EXPECT_EQ(back.height, 500);
  const std::vector<PanelPixels> p = panel_pixels(back);
  for (int i = 0; i < 3; ++i) EXPECT_GT(p[i].drawn, 2000) << "panel " << i;
  // (a): the ok bar is 40 of 40 units long, the crash and timeout bars shorter but visible.
  EXPECT_GT(p[0].green, 5000);
  EXPECT_GT(p[0].red, 500);
  EXPECT_EQ(p[0].blue + p[0].orange, 0);
  // (b) and (c): each histogram in its own colour, in its own panel only.
  EXPECT_GT(p[1].blue, 5000);
  EXPECT_EQ(p[1].orange + p[1].green, 0);
  EXPECT_GT(p[2].orange, 5000);
  EXPECT_EQ(p[2].blue + p[2].green, 0);
}

TEST(BatchSummaryPicture, SizeFromOptions) {
  BatchSummaryPictureOptions options;
  options.width = 900;
  options.height = 300;
  options.title = "synthetic batch";
  const Image image = plot_batch_summary(synthetic_summary(), options);
  EXPECT_EQ(image.width, 900);
  EXPECT_EQ(image.height, 300);
  const std::vector<PanelPixels> p = panel_pixels(image);
  EXPECT_GT(p[0].green, 500);
  EXPECT_GT(p[1].blue, 500);
  EXPECT_GT(p[2].orange, 500);
}

TEST(BatchSummaryPicture, NoOkMesh) {
  BatchSummary s;
  s.total = 2;
  s.counts = {{"ok", 0},
              {"bad_input", 1},
              {"not_converged", 0},
              {"internal_error", 0},
              {"out_of_memory", 0},
              {"crashed", 0},
              {"timed_out", 0},
              {"spawn_failed", 1}};
  s.all_seconds = {0.0, 3.0};  // a spawn failure takes no time: the first bin
  s.seconds = percentiles(s.all_seconds);
  s.angle_distortion = percentiles({});
  const auto path = testing::render_tmp_dir() / "batch_summary_no_ok.png";
  write_batch_summary_picture(s, path.string());
  const std::vector<PanelPixels> p = panel_pixels(read_png(path.string()));
  EXPECT_EQ(p[0].green, 0);  // "ok" is listed with a bar of length 0
  EXPECT_GT(p[0].red, 500);
  EXPECT_GT(p[1].blue, 1000);
  // (c): no histogram, the "no Ok mesh" text in the middle of the plot.
  EXPECT_EQ(p[2].orange, 0);
  EXPECT_GT(p[2].dark_centre, 100);
}

TEST(BatchSummaryPicture, EmptySummaryStillDraws) {
  const Image image = plot_batch_summary(BatchSummary{});
  const std::vector<PanelPixels> p = panel_pixels(image);
  for (int i = 0; i < 3; ++i) EXPECT_GT(p[i].drawn, 500) << "panel " << i;
  EXPECT_GT(p[1].dark_centre, 50);  // "no mesh"
  EXPECT_GT(p[2].dark_centre, 50);  // "no Ok mesh"
}

TEST(BatchSummaryPicture, Refuses) {
  BatchSummaryPictureOptions tiny;
  tiny.width = 100;
  EXPECT_THROW(plot_batch_summary(synthetic_summary(), tiny), InvalidInput);
  const auto missing = testing::render_tmp_dir() / "no such folder" / "summary.png";
  EXPECT_THROW(write_batch_summary_picture(synthetic_summary(), missing.string()), IoError);
}

}  // namespace
}  // namespace ricci
