#pragma once
/// \file
/// The picture of a batch's summary (OUTDIR/summary.png of `ricci batch`): three panels side by
/// side, (a) meshes by outcome, (b) a histogram of the seconds per mesh on a log10 axis, (c) a
/// histogram of the angle distortion of the Ok meshes.

#include <string>

#include "ricci/batch/summary.hpp"
#include "ricci/render/image.hpp"

namespace ricci {

/// Options of the batch summary picture.
struct BatchSummaryPictureOptions {
  int width = 1500;   ///< pixels, all three panels (each a third)
  int height = 500;   ///< pixels
  std::string title;  ///< above the panels; empty: none
};

/// The picture in memory. Panel (a) has one bar per outcome with a count above 0, and "ok"
/// always, each labelled with its count; (b) bins BatchSummary::all_seconds (a time <= 0 falls in
/// the first bin), with dashed lines at the median and p90; (c) bins
/// BatchSummary::all_angle_distortion on an axis from 1 (values below 1 fall in the first bin)
/// and says "no Ok mesh" when it is empty.
/// \throw InvalidInput on a picture size outside [150, 16384] x [150, 16384]
Image plot_batch_summary(const BatchSummary& summary,
                         const BatchSummaryPictureOptions& options = {});

/// Writes plot_batch_summary as a PNG file, atomically (write_png).
/// \throw InvalidInput as plot_batch_summary
/// \throw IoError naming the file when it cannot be written
void write_batch_summary_picture(const BatchSummary& summary, const std::string& png_path,
                                 const BatchSummaryPictureOptions& options = {});

}  // namespace ricci
