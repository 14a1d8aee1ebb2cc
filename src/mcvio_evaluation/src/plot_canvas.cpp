#include "mcvio/evaluation/plot_canvas.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/write_failure.hpp"

namespace mcvio::evaluation {

namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr int kShift = 4;  // sub-pixel bits for anti-aliased lines
constexpr double kSub = 1 << kShift;

cv::Size textSize(const std::string& text, double scale, int thickness, int* baseline = nullptr) {
  int b = 0;
  const cv::Size s = cv::getTextSize(text, kFont, scale, thickness, &b);
  if (baseline) *baseline = b;
  return s;
}

void putText(cv::Mat& img, const std::string& text, cv::Point origin, double scale, cv::Scalar color,
             int thickness = 1) {
  cv::putText(img, text, origin, kFont, scale, color, thickness, cv::LINE_AA);
}

std::string tickLabel(double v, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  if (std::abs(v) < step * 1e-6) v = 0;  // no "-0"
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

void expandRange(double& lo, double& hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    lo = 0;
    hi = 1;
    return;
  }
  const double span = hi - lo;
  if (span < 1e-9 * std::max(1.0, std::abs(lo))) {
    lo -= 0.5;
    hi += 0.5;
    return;
  }
  lo -= 0.05 * span;
  hi += 0.05 * span;
}

}  // namespace

PlotCanvas::PlotCanvas(std::string title, PlotStyle style) : title_(std::move(title)), style_(style) {
  if (style_.width < 200 || style_.height < 150) throw std::invalid_argument("plot size must be at least 200 x 150 px");
}

void PlotCanvas::setXRange(double min, double max) {
  if (!(max > min)) throw std::invalid_argument("plot x range must have max > min");
  fixed_x_ = true;
  x_min_ = min;
  x_max_ = max;
}

void PlotCanvas::setYRange(double min, double max) {
  if (!(max > min)) throw std::invalid_argument("plot y range must have max > min");
  fixed_y_ = true;
  y_min_ = min;
  y_max_ = max;
}

void PlotCanvas::addLine(std::vector<double> x, std::vector<double> y, cv::Scalar color, std::string label,
                         int thickness, bool dashed, double alpha) {
  if (x.size() != y.size()) throw std::invalid_argument("plot line '" + label + "': x and y sizes differ");
  lines_.push_back({std::move(x), std::move(y), color, std::move(label), std::max(1, thickness), dashed,
                    std::clamp(alpha, 0.0, 1.0)});
}

void PlotCanvas::addXBand(double x0, double x1, cv::Scalar color, std::string label, double alpha) {
  bands_.push_back({std::min(x0, x1), std::max(x0, x1), color, std::move(label), std::clamp(alpha, 0.0, 1.0)});
}

std::vector<double> PlotCanvas::niceTicks(double min, double max, int target) {
  std::vector<double> ticks;
  if (!(max > min) || !std::isfinite(min) || !std::isfinite(max)) return ticks;
  const double raw = (max - min) / std::max(1, target);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double r = raw / magnitude;
  const double step = (r < 1.5 ? 1 : r < 3 ? 2 : r < 7 ? 5 : 10) * magnitude;
  for (double v = std::ceil(min / step - 1e-9) * step; v <= max + step * 1e-9; v += step) ticks.push_back(v);
  return ticks;
}

cv::Mat PlotCanvas::render() const {
  const double fs = style_.font_scale;
  cv::Mat img(style_.height, style_.width, CV_8UC3, style_.background);

  // Legend entries (unique labels), to size the right margin.
  struct Entry {
    std::string label;
    cv::Scalar color;
    bool band;
    int thickness;
    bool dashed;
    double alpha;
  };
  std::vector<Entry> entries;
  const auto has = [&](const std::string& l) {
    return std::any_of(entries.begin(), entries.end(), [&](const Entry& e) { return e.label == l; });
  };
  for (const auto& l : lines_) {
    if (!l.label.empty() && !has(l.label)) entries.push_back({l.label, l.color, false, std::min(l.thickness, 6), l.dashed, l.alpha});
  }
  for (const auto& b : bands_) {
    if (!b.label.empty() && !has(b.label)) entries.push_back({b.label, b.color, true, 1, false, b.alpha});
  }
  int legend_w = 0;
  for (const auto& e : entries) legend_w = std::max(legend_w, textSize(e.label, fs, 1).width);
  if (!entries.empty()) legend_w += 60;

  // Margins: y tick labels and the rotated y label on the left, x ticks and label below.
  const int title_h = title_.empty() ? 15 : textSize(title_, fs * 1.35, 2).height + 30;
  const int left = 30 + textSize("-000.00", fs, 1).width + (y_label_.empty() ? 0 : textSize("Ay", fs * 1.15, 1).height + 20);
  const int bottom = 30 + textSize("0", fs, 1).height + (x_label_.empty() ? 0 : textSize("Ay", fs * 1.15, 1).height + 20);
  const int right = entries.empty() ? 30 : legend_w + 45;
  const cv::Rect area(left, title_h, std::max(50, style_.width - left - right), std::max(50, style_.height - title_h - bottom));

  // Ranges.
  double x0 = x_min_, x1 = x_max_, y0 = y_min_, y1 = y_max_;
  if (!fixed_x_ || !fixed_y_) {
    double xl = std::numeric_limits<double>::infinity(), xh = -xl, yl = xl, yh = -xl;
    for (const auto& l : lines_) {
      for (std::size_t i = 0; i < l.x.size(); ++i) {
        if (!std::isfinite(l.x[i]) || !std::isfinite(l.y[i])) continue;
        xl = std::min(xl, l.x[i]);
        xh = std::max(xh, l.x[i]);
        yl = std::min(yl, l.y[i]);
        yh = std::max(yh, l.y[i]);
      }
    }
    if (!fixed_x_) {
      x0 = xl;
      x1 = xh;
      expandRange(x0, x1);
    }
    if (!fixed_y_) {
      y0 = yl;
      y1 = yh;
      expandRange(y0, y1);
    }
  }
  if (equal_aspect_) {
    // Grow the axis with fewer metres per pixel around its centre.
    const double sx = (x1 - x0) / area.width, sy = (y1 - y0) / area.height;
    if (sx > sy) {
      const double c = 0.5 * (y0 + y1), h = 0.5 * sx * area.height;
      y0 = c - h;
      y1 = c + h;
    } else {
      const double c = 0.5 * (x0 + x1), h = 0.5 * sy * area.width;
      x0 = c - h;
      x1 = c + h;
    }
  }
  const auto px = [&](double x) { return (x - x0) / (x1 - x0) * area.width; };
  const auto py = [&](double y) { return area.height - (y - y0) / (y1 - y0) * area.height; };
  cv::Mat plot = img(area);  // drawing through the ROI clips to the data area

  // Bands, then grid, then lines on top.
  for (const auto& b : bands_) {
    cv::Mat overlay = plot.clone();
    const int a = static_cast<int>(std::floor(px(b.x0))), c = static_cast<int>(std::ceil(px(b.x1)));
    cv::rectangle(overlay, cv::Point(a, 0), cv::Point(std::max(a + 1, c), area.height), b.color, cv::FILLED);
    cv::addWeighted(overlay, b.alpha, plot, 1.0 - b.alpha, 0, plot);
  }
  const auto xticks = niceTicks(x0, x1, std::max(3, area.width / 90));
  const auto yticks = niceTicks(y0, y1, std::max(3, area.height / 80));
  for (double t : xticks) {
    const int x = static_cast<int>(std::lround(px(t)));
    cv::line(plot, {x, 0}, {x, area.height}, style_.grid_color, 1);
  }
  for (double t : yticks) {
    const int y = static_cast<int>(std::lround(py(t)));
    cv::line(plot, {0, y}, {area.width, y}, style_.grid_color, 1);
  }
  for (const auto& l : lines_) {
    cv::Mat target = l.alpha < 1.0 ? plot.clone() : plot;
    const auto sub = [&](std::size_t i) {
      return cv::Point(static_cast<int>(std::lround(px(l.x[i]) * kSub)), static_cast<int>(std::lround(py(l.y[i]) * kSub)));
    };
    double run = 0;  // pixels along a dashed line
    for (std::size_t i = 1; i < l.x.size(); ++i) {
      if (!std::isfinite(l.x[i - 1]) || !std::isfinite(l.y[i - 1]) || !std::isfinite(l.x[i]) || !std::isfinite(l.y[i])) continue;
      const cv::Point a = sub(i - 1), b = sub(i);
      if (!l.dashed) {
        cv::line(target, a, b, l.color, l.thickness, cv::LINE_AA, kShift);
        continue;
      }
      const double len = std::hypot(b.x - a.x, b.y - a.y) / kSub;
      const double dash = 8.0 + 2 * l.thickness;
      for (double s = 0; s < len;) {
        const double phase = std::fmod(run + s, 2 * dash);
        const double piece = std::min(len - s, (phase < dash ? dash : 2 * dash) - phase);
        if (phase < dash) {
          const double f0 = s / len, f1 = (s + piece) / len;
          cv::line(target, a + (b - a) * f0, a + (b - a) * f1, l.color, l.thickness, cv::LINE_AA, kShift);
        }
        s += std::max(piece, 1e-3);
      }
      run += len;
    }
    if (l.x.size() == 1 && std::isfinite(l.x[0]) && std::isfinite(l.y[0])) {
      cv::circle(target, sub(0), static_cast<int>((l.thickness + 2) * kSub), l.color, cv::FILLED, cv::LINE_AA, kShift);
    }
    if (l.alpha < 1.0) cv::addWeighted(target, l.alpha, plot, 1.0 - l.alpha, 0, plot);
  }

  // Frame, ticks and their labels.
  cv::rectangle(img, area, style_.axis_color, 1);
  int base = 0;
  for (double t : xticks) {
    const int x = area.x + static_cast<int>(std::lround(px(t)));
    cv::line(img, {x, area.br().y}, {x, area.br().y + 5}, style_.axis_color, 1);
    const std::string s = tickLabel(t, xticks.size() > 1 ? xticks[1] - xticks[0] : 1.0);
    const cv::Size ts = textSize(s, fs, 1, &base);
    putText(img, s, {x - ts.width / 2, area.br().y + 10 + ts.height}, fs, style_.axis_color);
  }
  for (double t : yticks) {
    const int y = area.y + static_cast<int>(std::lround(py(t)));
    cv::line(img, {area.x - 5, y}, {area.x, y}, style_.axis_color, 1);
    const std::string s = tickLabel(t, yticks.size() > 1 ? yticks[1] - yticks[0] : 1.0);
    const cv::Size ts = textSize(s, fs, 1, &base);
    putText(img, s, {area.x - 10 - ts.width, y + ts.height / 2}, fs, style_.axis_color);
  }
  // Axis labels and title.
  if (!x_label_.empty()) {
    const cv::Size ts = textSize(x_label_, fs * 1.15, 1, &base);
    putText(img, x_label_, {area.x + (area.width - ts.width) / 2, style_.height - 15}, fs * 1.15, style_.axis_color);
  }
  if (!y_label_.empty()) {
    const cv::Size ts = textSize(y_label_, fs * 1.15, 1, &base);
    cv::Mat label(ts.height + base + 4, ts.width + 4, CV_8UC3, style_.background);
    putText(label, y_label_, {2, ts.height + 2}, fs * 1.15, style_.axis_color);
    cv::Mat rotated;
    cv::rotate(label, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int x = 12, y = area.y + (area.height - rotated.rows) / 2;
    if (y >= 0 && y + rotated.rows <= img.rows && x + rotated.cols <= img.cols) {
      rotated.copyTo(img(cv::Rect(x, y, rotated.cols, rotated.rows)));
    }
  }
  if (!title_.empty()) {
    const cv::Size ts = textSize(title_, fs * 1.35, 2, &base);
    putText(img, title_, {(style_.width - ts.width) / 2, 12 + ts.height}, fs * 1.35, style_.axis_color, 2);
  }
  // Legend to the right of the data area.
  if (!entries.empty()) {
    const int row_h = textSize("Ay", fs, 1, &base).height + 14;
    const cv::Rect box(area.br().x + 15, area.y, legend_w + 20, static_cast<int>(entries.size()) * row_h + 12);
    cv::rectangle(img, box, style_.grid_color, 1);
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const auto& e = entries[i];
      const int cy = box.y + 6 + static_cast<int>(i) * row_h + row_h / 2;
      const int sx = box.x + 10;
      if (e.band) {
        cv::Mat swatch = img(cv::Rect(sx, cy - 7, 36, 14));
        cv::Mat fill(swatch.size(), swatch.type(), e.color);
        cv::addWeighted(fill, 0.5, swatch, 0.5, 0, swatch);
      } else if (e.dashed) {
        cv::line(img, {sx, cy}, {sx + 14, cy}, e.color, e.thickness, cv::LINE_AA);
        cv::line(img, {sx + 22, cy}, {sx + 36, cy}, e.color, e.thickness, cv::LINE_AA);
      } else {
        // Translucent lines look in the legend as they do on the data.
        cv::Mat swatch = img(cv::Rect(sx - 4, cy - 8, 44, 17));
        cv::Mat drawn = swatch.clone();
        cv::line(drawn, {4, 8}, {40, 8}, e.color, e.thickness, cv::LINE_AA);
        cv::addWeighted(drawn, e.alpha, swatch, 1.0 - e.alpha, 0, swatch);
      }
      const cv::Size ts = textSize(e.label, fs, 1, &base);
      putText(img, e.label, {sx + 46, cy + ts.height / 2}, fs, style_.axis_color);
    }
  }
  return img;
}

void PlotCanvas::save(const std::string& path) const {
  const cv::Mat img = render();
  bool ok = false;
  try {
    ok = cv::imwrite(path, img);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot write PNG (" + e.what() + ")");
  }
  if (!ok) throwCannotWrite(path, errno, "PNG");
}

}  // namespace mcvio::evaluation
