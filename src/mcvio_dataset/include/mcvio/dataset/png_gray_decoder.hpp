#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include <opencv2/core/mat.hpp>

namespace mcvio::dataset {

/// Decodes 8-bit greyscale, non-interlaced PNG files (how EuRoC and the simulator store their
/// images) without libpng, bit for bit as libpng does. libpng reverses the Paeth row filter with
/// SIMD only for 3- and 4-byte pixels; for EuRoC's one-byte pixels its scalar loop, one dependent
/// step per pixel, was most of a frame's decoding, and decoding cost more CPU per frame than the
/// frontend. Here runs of Paeth rows are reversed four rows at a time.
///
/// Any other PNG (colour, palette, alpha, 16 bit, interlaced) or a file that is not a PNG at all is
/// reported as kUnsupported, and the caller falls back to OpenCV. Ancillary chunks are skipped.
class PngGrayDecoder {
 public:
  enum class Status { kDecoded, kUnsupported };

  /// Decodes `size` bytes of a PNG file into `*image` (CV_8UC1, reallocated only when its size
  /// changes). Throws mcvio::InputError naming `name` when the data claim to be such a PNG but are
  /// damaged: truncated or oversized chunk, CRC mismatch, IDAT before IHDR, corrupt zlib stream,
  /// too little image data, an unknown row filter.
  static Status decode(const std::uint8_t* data, std::size_t size, const std::string& name, cv::Mat* image);

  /// Reads the file at `path` and decodes it; throws mcvio::InputError naming the file when it
  /// cannot be read or is damaged (see decode()).
  static Status decodeFile(const std::string& path, cv::Mat* image);

  /// The width and height in the IHDR of any PNG file (colour, 16 bit, interlaced included),
  /// read from its first 24 bytes without decoding; false when `path` cannot be read or does not
  /// start as a PNG. Lets a caller refuse an image of the wrong size before decoding megapixels.
  static bool readSize(const std::string& path, int* width, int* height);
};

}  // namespace mcvio::dataset
