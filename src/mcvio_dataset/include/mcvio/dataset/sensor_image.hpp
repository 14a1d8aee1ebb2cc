#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include <opencv2/core/mat.hpp>

namespace mcvio::dataset {

/// The pixel fields of a sensor_msgs/Image as a camera driver sent them (the data is not owned).
struct SensorImageView {
  std::string encoding;  ///< a sensor_msgs/image_encodings name: "mono8", "bgr8", "bayer_rggb8", ...
  std::uint32_t width = 0, height = 0;
  std::uint32_t step = 0;  ///< bytes per row
  bool big_endian = false;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;  ///< bytes at data
};

/// The encodings greyImageOf() takes, for messages.
const char* supportedImageEncodings();

/// The 8-bit grey image the frontend tracks, from any common camera encoding: mono8 / 8UC1 as
/// they are; mono16 / 16UC1 scaled by 1/256 (as cv_bridge's mono8 conversion); rgb8, bgr8, 8UC3
/// (taken as bgr8, as cv_bridge does), rgba8, bgra8, 8UC4 to luminance (ITU-R BT.601, OpenCV's
/// weights); bayer_rggb8 / bggr8 / gbrg8 / grbg8 demosaiced; yuv422 (UYVY) and yuv422_yuy2 (YUYV)
/// by their luma bytes. Anything else (float depth images, unknown names), a step shorter than a
/// row or data shorter than step x height returns an empty image and says why in `why`.
cv::Mat greyImageOf(const SensorImageView& image, std::string* why);

/// The same for a sensor_msgs/CompressedImage (image_transport "compressed"): `format` as the
/// publisher wrote it ("jpeg", "png", "bgr8; jpeg compressed bgr8", ...), `data` the encoded
/// file, decoded to 8-bit grey. compressedDepth images, other codecs and data that does not
/// decode return an empty image and say why.
cv::Mat greyImageOfCompressed(const std::string& format, const std::uint8_t* data, std::size_t size, std::string* why);

}  // namespace mcvio::dataset
