#include "mcvio/dataset/sensor_image.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace mcvio::dataset {
namespace {

struct Layout {
  int bytes_per_pixel;
  int cv_type;    ///< how the rows read as a cv::Mat
  int to_grey;    ///< cv::cvtColor code, or -1
};

// cv_bridge's pairing of ROS Bayer names with OpenCV's, whose names count from the second row.
bool layoutOf(const std::string& encoding, Layout* l) {
  if (encoding == "mono8" || encoding == "8UC1") *l = {1, CV_8UC1, -1};
  else if (encoding == "mono16" || encoding == "16UC1") *l = {2, CV_16UC1, -1};
  else if (encoding == "bgr8" || encoding == "8UC3") *l = {3, CV_8UC3, cv::COLOR_BGR2GRAY};
  else if (encoding == "rgb8") *l = {3, CV_8UC3, cv::COLOR_RGB2GRAY};
  else if (encoding == "bgra8" || encoding == "8UC4") *l = {4, CV_8UC4, cv::COLOR_BGRA2GRAY};
  else if (encoding == "rgba8") *l = {4, CV_8UC4, cv::COLOR_RGBA2GRAY};
  else if (encoding == "bayer_rggb8") *l = {1, CV_8UC1, cv::COLOR_BayerBG2GRAY};
  else if (encoding == "bayer_bggr8") *l = {1, CV_8UC1, cv::COLOR_BayerRG2GRAY};
  else if (encoding == "bayer_gbrg8") *l = {1, CV_8UC1, cv::COLOR_BayerGR2GRAY};
  else if (encoding == "bayer_grbg8") *l = {1, CV_8UC1, cv::COLOR_BayerGB2GRAY};
  else if (encoding == "yuv422" || encoding == "uyvy") *l = {2, CV_8UC2, cv::COLOR_YUV2GRAY_UYVY};
  else if (encoding == "yuv422_yuy2" || encoding == "yuyv") *l = {2, CV_8UC2, cv::COLOR_YUV2GRAY_YUY2};
  else return false;
  return true;
}

}  // namespace

const char* supportedImageEncodings() {
  return "mono8, 8UC1, mono16, 16UC1, rgb8, bgr8, 8UC3, rgba8, bgra8, 8UC4, bayer_rggb8, bayer_bggr8, bayer_gbrg8, "
         "bayer_grbg8, yuv422 (uyvy), yuv422_yuy2 (yuyv)";
}

cv::Mat greyImageOf(const SensorImageView& image, std::string* why) {
  Layout l{};
  if (!layoutOf(image.encoding, &l)) {
    *why = "encoding '" + image.encoding + "' is not one mcvio tracks (" + supportedImageEncodings() + ")";
    return {};
  }
  const std::size_t row_bytes = static_cast<std::size_t>(image.width) * l.bytes_per_pixel;
  const std::string size = std::to_string(image.width) + "x" + std::to_string(image.height) + " " + image.encoding;
  if (image.width == 0 || image.height == 0) {
    *why = "image is " + size + ": no pixels";
    return {};
  }
  if (image.step < row_bytes) {
    *why = "step " + std::to_string(image.step) + " is shorter than a row of " + size + " (" + std::to_string(row_bytes) + " bytes)";
    return {};
  }
  if (!image.data) {
    *why = "image " + size + " has no pixel data";
    return {};
  }
  if (image.size < static_cast<std::size_t>(image.step) * image.height) {
    *why = "data holds " + std::to_string(image.size) + " bytes, less than step*height (" +
           std::to_string(static_cast<std::size_t>(image.step) * image.height) + ") of " + size;
    return {};
  }
  if (l.cv_type == CV_8UC2 && image.width % 2 != 0) {
    *why = image.encoding + " packs two pixels in four bytes, and the width " + std::to_string(image.width) + " is odd";
    return {};
  }
  const cv::Mat rows(static_cast<int>(image.height), static_cast<int>(image.width), l.cv_type,
                     const_cast<std::uint8_t*>(image.data), image.step);
  cv::Mat grey;
  if (l.cv_type == CV_16UC1) {
    cv::Mat host = rows;
    // The message says which byte order its 16-bit pixels have; this machine is little-endian.
    if (image.big_endian) {
      host = rows.clone();
      for (int r = 0; r < host.rows; ++r) {
        auto* p = host.ptr<std::uint16_t>(r);
        for (int c = 0; c < host.cols; ++c) p[c] = static_cast<std::uint16_t>((p[c] >> 8) | (p[c] << 8));
      }
    }
    host.convertTo(grey, CV_8U, 1.0 / 256.0);
  } else if (l.to_grey >= 0) {
    cv::cvtColor(rows, grey, l.to_grey);
  } else {
    grey = rows.clone();
  }
  return grey;
}

cv::Mat greyImageOfCompressed(const std::string& format, const std::uint8_t* data, std::size_t size, std::string* why) {
  if (format.find("compressedDepth") != std::string::npos) {
    *why = "format '" + format + "' is a depth image (compressedDepth), not a camera image";
    return {};
  }
  if (format.find("jpeg") == std::string::npos && format.find("jpg") == std::string::npos &&
      format.find("png") == std::string::npos) {
    *why = "format '" + format + "' is neither jpeg nor png";
    return {};
  }
  if (!data || size == 0) {
    *why = "compressed image (" + format + ") has no data";
    return {};
  }
  const cv::Mat encoded(1, static_cast<int>(size), CV_8UC1, const_cast<std::uint8_t*>(data));
  cv::Mat grey;
  try {
    grey = cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    grey.release();  // OpenCV throws for some damaged files: the same as one that does not decode
  }
  if (grey.empty()) *why = "compressed image (" + format + ", " + std::to_string(size) + " bytes) does not decode";
  return grey;
}

}  // namespace mcvio::dataset
