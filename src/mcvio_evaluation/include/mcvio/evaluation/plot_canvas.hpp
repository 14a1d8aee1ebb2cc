#pragma once
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace mcvio::evaluation {

/// Looks of a plot. Colours are BGR (OpenCV).
struct PlotStyle {
  int width = 1000;   ///< image size [px]
  int height = 700;
  double font_scale = 0.5;  ///< tick labels; axis labels x1.15, title x1.35
  cv::Scalar background{255, 255, 255};
  cv::Scalar axis_color{40, 40, 40};
  cv::Scalar grid_color{225, 225, 225};
};

/// A small 2D line chart drawn with OpenCV: white background, title, axes with "nice" ticks
/// (1, 2, 5 x 10^k), grid, axis labels, shaded x-intervals and a legend outside the data area so
/// it never hides a curve. Ranges follow the data (5% padding) unless set.
class PlotCanvas {
 public:
  explicit PlotCanvas(std::string title, PlotStyle style = {});

  void setXLabel(std::string label) { x_label_ = std::move(label); }
  void setYLabel(std::string label) { y_label_ = std::move(label); }
  /// Fixed ranges instead of the data's.
  void setXRange(double min, double max);
  void setYRange(double min, double max);
  /// Same metres per pixel on both axes (top views).
  void setEqualAspect(bool equal) { equal_aspect_ = equal; }

  /// A polyline; `alpha` < 1 blends it (wide translucent highlights), `dashed` for references.
  /// An empty label keeps it out of the legend. Sizes of x and y must match.
  void addLine(std::vector<double> x, std::vector<double> y, cv::Scalar color, std::string label,
               int thickness = 2, bool dashed = false, double alpha = 1.0);
  /// A shaded vertical band x0..x1 over the whole height (e.g. a conflict interval). Bands with
  /// the same label share one legend entry.
  void addXBand(double x0, double x1, cv::Scalar color, std::string label, double alpha = 0.35);

  cv::Mat render() const;
  /// Renders and writes a PNG; throws mcvio::InputError naming the file if it cannot.
  void save(const std::string& path) const;

  /// Tick positions covering [min, max] with about `target` steps of 1, 2 or 5 x 10^k.
  static std::vector<double> niceTicks(double min, double max, int target = 6);

 private:
  struct Line {
    std::vector<double> x, y;
    cv::Scalar color;
    std::string label;
    int thickness;
    bool dashed;
    double alpha;
  };
  struct Band {
    double x0, x1;
    cv::Scalar color;
    std::string label;
    double alpha;
  };

  std::string title_, x_label_, y_label_;
  PlotStyle style_;
  bool fixed_x_ = false, fixed_y_ = false, equal_aspect_ = false;
  double x_min_ = 0, x_max_ = 1, y_min_ = 0, y_max_ = 1;
  std::vector<Line> lines_;
  std::vector<Band> bands_;
};

}  // namespace mcvio::evaluation
