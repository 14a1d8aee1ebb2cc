#include "mcvio/dataset/sensor_image.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <functional>
#include <vector>

namespace mcvio::dataset {
namespace {

// A small grey pattern and its bytes in one encoding, rows padded by `pad` bytes.
struct Encoded {
  std::vector<std::uint8_t> bytes;
  SensorImageView view;
};

constexpr int kW = 8, kH = 6;

std::uint8_t greyAt(int r, int c) { return static_cast<std::uint8_t>(17 + 29 * r + 13 * c); }

Encoded encode(const std::string& encoding, int bytes_per_pixel, int pad,
               const std::function<void(std::uint8_t*, int r, int c)>& pixel) {
  Encoded e;
  const int step = kW * bytes_per_pixel + pad;
  e.bytes.assign(static_cast<std::size_t>(step) * kH, 0xEE);
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c) pixel(&e.bytes[static_cast<std::size_t>(r) * step + c * bytes_per_pixel], r, c);
  e.view = {encoding, kW, kH, static_cast<std::uint32_t>(step), false, e.bytes.data(), e.bytes.size()};
  return e;
}

void expectPattern(const cv::Mat& grey, const std::string& encoding) {
  ASSERT_EQ(grey.type(), CV_8UC1) << encoding;
  ASSERT_EQ(grey.cols, kW) << encoding;
  ASSERT_EQ(grey.rows, kH) << encoding;
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c) ASSERT_EQ(grey.at<std::uint8_t>(r, c), greyAt(r, c)) << encoding << " at " << r << "," << c;
}

TEST(SensorImage, EveryColourEncodingOfAGreySceneGivesThatGrey) {
  std::string why;
  for (const char* enc : {"mono8", "8UC1"}) {
    auto e = encode(enc, 1, 3, [](std::uint8_t* p, int r, int c) { p[0] = greyAt(r, c); });
    expectPattern(greyImageOf(e.view, &why), enc);
  }
  for (const char* enc : {"rgb8", "bgr8", "8UC3"}) {
    auto e = encode(enc, 3, 2, [](std::uint8_t* p, int r, int c) { p[0] = p[1] = p[2] = greyAt(r, c); });
    expectPattern(greyImageOf(e.view, &why), enc);
  }
  for (const char* enc : {"rgba8", "bgra8", "8UC4"}) {
    auto e = encode(enc, 4, 0, [](std::uint8_t* p, int r, int c) { p[0] = p[1] = p[2] = greyAt(r, c); p[3] = 255; });
    expectPattern(greyImageOf(e.view, &why), enc);
  }
  // 16-bit: the high byte is the grey, in either byte order.
  for (const char* enc : {"mono16", "16UC1"}) {
    auto little = encode(enc, 2, 2, [](std::uint8_t* p, int r, int c) { p[0] = 0x4D; p[1] = greyAt(r, c); });
    expectPattern(greyImageOf(little.view, &why), std::string(enc) + " little-endian");
    auto big = encode(enc, 2, 2, [](std::uint8_t* p, int r, int c) { p[0] = greyAt(r, c); p[1] = 0x4D; });
    big.view.big_endian = true;
    expectPattern(greyImageOf(big.view, &why), std::string(enc) + " big-endian");
  }
  // Packed 4:2:2: the luma bytes are the grey, whatever the chroma.
  auto uyvy = encode("yuv422", 2, 0, [](std::uint8_t* p, int r, int c) { p[0] = c % 2 ? 90 : 160; p[1] = greyAt(r, c); });
  expectPattern(greyImageOf(uyvy.view, &why), "yuv422");
  auto yuyv = encode("yuv422_yuy2", 2, 4, [](std::uint8_t* p, int r, int c) { p[0] = greyAt(r, c); p[1] = c % 2 ? 90 : 160; });
  expectPattern(greyImageOf(yuyv.view, &why), "yuv422_yuy2");
}

TEST(SensorImage, ColourChannelsAreWeightedByTheirEncodingsOrder) {
  std::string why;
  // One pure red pixel: luminance 0.299 x 255 = 76 in rgb8; the same bytes as bgr8 are blue (29).
  const std::vector<std::uint8_t> red_first = {255, 0, 0};
  SensorImageView v{"rgb8", 1, 1, 3, false, red_first.data(), red_first.size()};
  EXPECT_EQ(greyImageOf(v, &why).at<std::uint8_t>(0, 0), 76);
  v.encoding = "bgr8";
  EXPECT_EQ(greyImageOf(v, &why).at<std::uint8_t>(0, 0), 29);
  // A flat Bayer mosaic of one colour demosaics to a flat grey (its centre, away from borders).
  for (const char* enc : {"bayer_rggb8", "bayer_bggr8", "bayer_gbrg8", "bayer_grbg8"}) {
    std::vector<std::uint8_t> mosaic(8 * 8, 120);
    const cv::Mat grey = greyImageOf({enc, 8, 8, 8, false, mosaic.data(), mosaic.size()}, &why);
    ASSERT_EQ(grey.type(), CV_8UC1) << enc << ": " << why;
    EXPECT_EQ(grey.at<std::uint8_t>(4, 4), 120) << enc;
  }
  // Red where a bggr8 mosaic has red (odd rows, odd columns) and nothing else is dark red:
  // brighter than the same bytes read as rggb8, where those are blue sites.
  std::vector<std::uint8_t> mosaic(8 * 8, 0);
  for (int r = 1; r < 8; r += 2)
    for (int c = 1; c < 8; c += 2) mosaic[r * 8 + c] = 250;
  const int as_bggr = greyImageOf({"bayer_bggr8", 8, 8, 8, false, mosaic.data(), mosaic.size()}, &why).at<std::uint8_t>(4, 4);
  const int as_rggb = greyImageOf({"bayer_rggb8", 8, 8, 8, false, mosaic.data(), mosaic.size()}, &why).at<std::uint8_t>(4, 4);
  EXPECT_GT(as_bggr, as_rggb);
  EXPECT_NEAR(as_bggr, 0.299 * 250, 3);
  EXPECT_NEAR(as_rggb, 0.114 * 250, 3);
}

TEST(SensorImage, WhatCannotBeTrackedSaysWhy) {
  std::vector<std::uint8_t> bytes(64 * 4, 0);
  auto why = [&](SensorImageView v) {
    std::string w;
    const cv::Mat m = greyImageOf(v, &w);
    EXPECT_TRUE(m.empty()) << v.encoding;
    return w;
  };
  EXPECT_EQ(why({"32FC1", 8, 8, 32, false, bytes.data(), bytes.size()}),
            std::string("encoding '32FC1' is not one mcvio tracks (") + supportedImageEncodings() + ")");
  EXPECT_EQ(why({"rgb8", 8, 8, 16, false, bytes.data(), bytes.size()}),
            "step 16 is shorter than a row of 8x8 rgb8 (24 bytes)");
  EXPECT_EQ(why({"mono16", 8, 9, 16, false, bytes.data(), 100}),
            "data holds 100 bytes, less than step*height (144) of 8x9 mono16");
  EXPECT_EQ(why({"mono8", 0, 8, 0, false, bytes.data(), bytes.size()}), "image is 0x8 mono8: no pixels");
  EXPECT_EQ(why({"yuv422", 7, 2, 14, false, bytes.data(), bytes.size()}),
            "yuv422 packs two pixels in four bytes, and the width 7 is odd");
  EXPECT_EQ(why({"mono8", 8, 8, 8, false, nullptr, 64}), "image 8x8 mono8 has no pixel data");
}

TEST(SensorImage, CompressedPngIsExactAndJpegClose) {
  cv::Mat grey(48, 64, CV_8UC1);
  for (int r = 0; r < grey.rows; ++r)
    for (int c = 0; c < grey.cols; ++c) grey.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>((r * 7 + c * 3) % 256);
  std::string why;
  std::vector<std::uint8_t> png, jpeg;
  ASSERT_TRUE(cv::imencode(".png", grey, png));
  ASSERT_TRUE(cv::imencode(".jpg", grey, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
  for (const char* format : {"png", "mono8; png compressed mono8", "mono8; compressed png"}) {
    const cv::Mat back = greyImageOfCompressed(format, png.data(), png.size(), &why);
    ASSERT_EQ(back.type(), CV_8UC1) << format << ": " << why;
    EXPECT_EQ(cv::norm(back, grey, cv::NORM_INF), 0.0) << format;
  }
  // A colour PNG (bgr8 published compressed) decodes to its grey.
  cv::Mat colour;
  cv::merge(std::vector<cv::Mat>{grey, grey, grey}, colour);
  std::vector<std::uint8_t> colour_png;
  ASSERT_TRUE(cv::imencode(".png", colour, colour_png));
  EXPECT_EQ(cv::norm(greyImageOfCompressed("bgr8; png compressed bgr8", colour_png.data(), colour_png.size(), &why), grey,
                     cv::NORM_INF),
            0.0);
  const cv::Mat from_jpeg = greyImageOfCompressed("jpeg", jpeg.data(), jpeg.size(), &why);
  ASSERT_EQ(from_jpeg.size(), grey.size()) << why;
  EXPECT_LT(cv::norm(from_jpeg, grey, cv::NORM_L1) / static_cast<double>(grey.total()), 3.0);
}

TEST(SensorImage, CompressedImagesThatCannotBeTrackedSayWhy) {
  std::string why;
  const std::vector<std::uint8_t> garbage = {1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_TRUE(greyImageOfCompressed("16UC1; compressedDepth png", garbage.data(), garbage.size(), &why).empty());
  EXPECT_EQ(why, "format '16UC1; compressedDepth png' is a depth image (compressedDepth), not a camera image");
  EXPECT_TRUE(greyImageOfCompressed("tiff", garbage.data(), garbage.size(), &why).empty());
  EXPECT_EQ(why, "format 'tiff' is neither jpeg nor png");
  EXPECT_TRUE(greyImageOfCompressed("jpeg", garbage.data(), garbage.size(), &why).empty());
  EXPECT_EQ(why, "compressed image (jpeg, 8 bytes) does not decode");
  EXPECT_TRUE(greyImageOfCompressed("png", nullptr, 0, &why).empty());
  EXPECT_EQ(why, "compressed image (png) has no data");
}

}  // namespace
}  // namespace mcvio::dataset
