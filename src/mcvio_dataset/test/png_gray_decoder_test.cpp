// PngGrayDecoder against OpenCV's libpng decoder (the reference): every row filter, libpng's own
// adaptive filter choice, the real EuRoC images, and damaged or unsupported files.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <zlib.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/png_gray_decoder.hpp"

namespace mcvio::dataset {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;
using Status = PngGrayDecoder::Status;

void put32(Bytes* out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out->push_back(static_cast<std::uint8_t>(v >> s));
}

void putChunk(Bytes* out, const char* type, const Bytes& body) {
  put32(out, static_cast<std::uint32_t>(body.size()));
  Bytes typed(type, type + 4);
  typed.insert(typed.end(), body.begin(), body.end());
  out->insert(out->end(), typed.begin(), typed.end());
  put32(out, static_cast<std::uint32_t>(crc32(0L, typed.data(), static_cast<uInt>(typed.size()))));
}

int paethPredictor(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

struct PngSpec {
  std::vector<int> filters;  ///< filter type of row y is filters[y % size]
  int bit_depth = 8, color_type = 0, interlace = 0;
  std::size_t keep_rows = 0;  ///< compress only this many rows (0: all)
  std::size_t idat_split = 0;  ///< split the zlib stream into IDAT chunks of this size (0: one)
};

// A minimal PNG encoder with a chosen filter per row: the test's own, written from the PNG spec,
// so each of the five filters is exercised on purpose, not only where libpng's heuristic picks it.
Bytes encodePng(const cv::Mat& img, const PngSpec& spec) {
  Bytes raw;
  for (int y = 0; y < img.rows; ++y) {
    const int f = spec.filters[static_cast<std::size_t>(y) % spec.filters.size()];
    raw.push_back(static_cast<std::uint8_t>(f));
    for (int x = 0; x < img.cols; ++x) {
      const int v = img.at<std::uint8_t>(y, x);
      const int a = x > 0 ? img.at<std::uint8_t>(y, x - 1) : 0;
      const int b = y > 0 ? img.at<std::uint8_t>(y - 1, x) : 0;
      const int c = x > 0 && y > 0 ? img.at<std::uint8_t>(y - 1, x - 1) : 0;
      const int pred = f == 0 ? 0 : f == 1 ? a : f == 2 ? b : f == 3 ? (a + b) / 2 : f == 4 ? paethPredictor(a, b, c) : 0;
      raw.push_back(static_cast<std::uint8_t>((v - pred) & 0xff));
    }
  }
  if (spec.keep_rows > 0) raw.resize(spec.keep_rows * static_cast<std::size_t>(img.cols + 1));
  uLongf zsize = compressBound(static_cast<uLong>(raw.size()));
  Bytes z(zsize);
  EXPECT_EQ(compress2(z.data(), &zsize, raw.data(), static_cast<uLong>(raw.size()), 6), Z_OK);
  z.resize(zsize);

  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  Bytes ihdr;
  put32(&ihdr, static_cast<std::uint32_t>(img.cols));
  put32(&ihdr, static_cast<std::uint32_t>(img.rows));
  ihdr.insert(ihdr.end(), {static_cast<std::uint8_t>(spec.bit_depth), static_cast<std::uint8_t>(spec.color_type), 0, 0,
                           static_cast<std::uint8_t>(spec.interlace)});
  putChunk(&png, "IHDR", ihdr);
  putChunk(&png, "tEXt", Bytes{'C', 'o', 'm', 'm', 'e', 'n', 't', 0, 'x'});
  const std::size_t step = spec.idat_split > 0 ? spec.idat_split : z.size();
  for (std::size_t i = 0; i < z.size(); i += step)
    putChunk(&png, "IDAT", Bytes(z.begin() + static_cast<long>(i), z.begin() + static_cast<long>(std::min(z.size(), i + step))));
  putChunk(&png, "IEND", {});
  return png;
}

// The signature and an 8-bit greyscale IHDR claiming `width` x `height`, and nothing else.
Bytes forgedHeader(std::uint32_t width, std::uint32_t height) {
  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  Bytes ihdr;
  put32(&ihdr, width);
  put32(&ihdr, height);
  ihdr.insert(ihdr.end(), {8, 0, 0, 0, 0});
  putChunk(&png, "IHDR", ihdr);
  return png;
}

// Texture with flat areas, edges and noise, so every predictor wins somewhere and Paeth meets ties.
cv::Mat testImage(int rows, int cols, unsigned seed) {
  cv::Mat img(rows, cols, CV_8UC1);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(0, 255);
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x) {
      int v = (x / 7 + y / 5) % 2 == 0 ? 3 * x + y : 200 - 2 * y;
      if ((x * 31 + y * 17) % 11 == 0) v = noise(rng);
      img.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(v & 0xff);
    }
  return img;
}

cv::Mat decodeOurs(const Bytes& png) {
  cv::Mat out;
  EXPECT_EQ(PngGrayDecoder::decode(png.data(), png.size(), "test.png", &out), Status::kDecoded);
  return out;
}

void expectSame(const cv::Mat& a, const cv::Mat& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.type(), b.type());
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
}

std::string errorOf(const Bytes& png) {
  cv::Mat out;
  try {
    PngGrayDecoder::decode(png.data(), png.size(), "damaged.png", &out);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PngGrayDecoder, EveryRowFilterMatchesLibpng) {
  const cv::Mat img = testImage(41, 57, 1);
  for (const std::vector<int>& filters :
       {std::vector<int>{0}, {1}, {2}, {3}, {4}, {4, 3, 2, 1, 0}, {2, 4, 4, 1, 3}}) {
    SCOPED_TRACE(testing::Message() << "filters starting " << filters.front() << ", " << filters.size() << " kinds");
    const Bytes png = encodePng(img, {filters});
    const cv::Mat ours = decodeOurs(png);
    expectSame(ours, img);
    expectSame(ours, cv::imdecode(png, cv::IMREAD_GRAYSCALE));
  }
}

// Runs of Paeth rows are reversed several rows at a time, staggered by a pixel: narrow images,
// heights that are no multiple of the group, and runs broken by other filters take the edges.
TEST(PngGrayDecoder, PaethRowGroupsOfEveryShape) {
  for (const int cols : {1, 2, 3, 4, 5, 57})
    for (const int rows : {1, 3, 4, 5, 9, 13})
      for (const std::vector<int>& filters : {std::vector<int>{4}, {4, 4, 4, 0, 4, 4, 4, 4, 4, 2, 4, 1, 4, 4, 3}}) {
        SCOPED_TRACE(testing::Message() << cols << "x" << rows << ", " << filters.size() << " filters");
        const cv::Mat img = testImage(rows, cols, static_cast<unsigned>(cols * 100 + rows));
        const Bytes png = encodePng(img, {filters});
        const cv::Mat ours = decodeOurs(png);
        expectSame(ours, img);
        expectSame(ours, cv::imdecode(png, cv::IMREAD_GRAYSCALE));
      }
}

TEST(PngGrayDecoder, SplitImageDataAndLibpngsOwnFilterChoice) {
  const cv::Mat img = testImage(480, 752, 2);
  PngSpec split{{4, 1}};
  split.idat_split = 777;  // many IDAT chunks, boundaries inside rows
  expectSame(decodeOurs(encodePng(img, split)), img);
  for (const int level : {0, 1, 6, 9}) {
    std::vector<std::uint8_t> png;
    ASSERT_TRUE(cv::imencode(".png", img, png, {cv::IMWRITE_PNG_COMPRESSION, level}));
    expectSame(decodeOurs(png), img);
  }
}

TEST(PngGrayDecoder, OtherPngsAndOtherFormatsAreLeftToOpenCv) {
  cv::Mat out;
  const cv::Mat gray = testImage(8, 9, 3);
  Bytes png;
  cv::Mat colour;
  cv::merge(std::vector<cv::Mat>{gray, gray, gray}, colour);
  ASSERT_TRUE(cv::imencode(".png", colour, png));
  EXPECT_EQ(PngGrayDecoder::decode(png.data(), png.size(), "c.png", &out), Status::kUnsupported);
  cv::Mat deep;
  gray.convertTo(deep, CV_16U, 256);
  ASSERT_TRUE(cv::imencode(".png", deep, png));
  EXPECT_EQ(PngGrayDecoder::decode(png.data(), png.size(), "d.png", &out), Status::kUnsupported);
  PngSpec interlaced{{0}};
  interlaced.interlace = 1;
  png = encodePng(gray, interlaced);
  EXPECT_EQ(PngGrayDecoder::decode(png.data(), png.size(), "i.png", &out), Status::kUnsupported);
  ASSERT_TRUE(cv::imencode(".bmp", gray, png));
  EXPECT_EQ(PngGrayDecoder::decode(png.data(), png.size(), "b.png", &out), Status::kUnsupported);
  EXPECT_EQ(PngGrayDecoder::decode(png.data(), 0, "empty.png", &out), Status::kUnsupported);
  // A forged header of 30000 x 30000 pixels in a file of a few bytes reserves nothing here.
  Bytes forged = forgedHeader(30000, 30000);
  putChunk(&forged, "IDAT", Bytes{0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01});
  EXPECT_EQ(PngGrayDecoder::decode(forged.data(), forged.size(), "forged.png", &out), Status::kUnsupported);
}

TEST(PngGrayDecoder, DamagedFilesNameTheFileAndTheFault) {
  const cv::Mat img = testImage(20, 30, 4);
  const Bytes good = encodePng(img, {{4}});

  const std::string truncated = errorOf(Bytes(good.begin(), good.begin() + static_cast<long>(good.size() / 2)));
  EXPECT_NE(truncated.find("damaged.png: cannot read or decode image"), std::string::npos) << truncated;
  EXPECT_NE(truncated.find("runs past the end of the file"), std::string::npos) << truncated;

  Bytes flipped = good;
  flipped[good.size() - 20] ^= 0x10;  // inside the IDAT body
  EXPECT_NE(errorOf(flipped).find("CRC mismatch in chunk 'IDAT'"), std::string::npos) << errorOf(flipped);

  EXPECT_NE(errorOf(encodePng(img, {{0, 7}})).find("unknown row filter 7 in row 1"), std::string::npos);

  PngSpec short_data{{2}};
  short_data.keep_rows = 12;
  EXPECT_NE(errorOf(encodePng(img, short_data)).find("image data end in row 12 of 20"), std::string::npos)
      << errorOf(encodePng(img, short_data));

  Bytes no_header(good.begin(), good.begin() + 8);
  putChunk(&no_header, "IDAT", Bytes{1, 2, 3});
  EXPECT_NE(errorOf(no_header).find("the first chunk is 'IDAT', not a 13-byte IHDR"), std::string::npos);

  // A zlib stream that is not one, with a valid CRC.
  Bytes bad_zlib(good.begin(), good.begin() + 33);  // signature + IHDR
  putChunk(&bad_zlib, "IDAT", Bytes{0x78, 0x9c, 0xff, 0xff, 0xff, 0xff});
  EXPECT_NE(errorOf(bad_zlib).find("corrupt image data (zlib"), std::string::npos) << errorOf(bad_zlib);

  // The file ends after the image data without IEND: the image is complete, so it is accepted.
  const Bytes no_end(good.begin(), good.end() - 12);
  expectSame(decodeOurs(no_end), img);
}

TEST(PngGrayDecoder, RandomDamageGivesAnImageOrInputErrorNeverACrash) {
  const Bytes good = encodePng(testImage(16, 24, 5), {{4, 1, 2}});
  std::mt19937 rng(77);
  int decoded = 0, errors = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Bytes b = good;
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits && !b.empty(); ++e) {
      const std::size_t p = rng() % b.size();
      switch (rng() % 3) {
        case 0:
          b[p] = static_cast<std::uint8_t>(rng());
          break;
        case 1:
          b.erase(b.begin() + static_cast<long>(p), b.begin() + static_cast<long>(std::min(b.size(), p + 1 + rng() % 20)));
          break;
        default:
          b.insert(b.begin() + static_cast<long>(p), static_cast<std::uint8_t>(rng()));
      }
    }
    cv::Mat out;
    try {
      PngGrayDecoder::decode(b.data(), b.size(), "fuzz.png", &out);
      ++decoded;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("fuzz.png"), std::string::npos);
      ++errors;
    }
  }
  EXPECT_GT(errors, 1000);  // CRCs catch nearly every change
  std::printf("2000 damaged files: %d decoded or left to OpenCV, %d InputError\n", decoded, errors);
}

TEST(PngGrayDecoder, ReadSizeTakesAnyPngsHeaderWithoutDecoding) {
  const fs::path dir = fs::temp_directory_path() / "mcvio_png_read_size";
  fs::create_directories(dir);
  const auto write = [&](const std::string& name, const Bytes& bytes) {
    const std::string path = (dir / name).string();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
    return path;
  };
  int w = 0, h = 0;
  const cv::Mat gray = testImage(8, 9, 3);
  ASSERT_TRUE(PngGrayDecoder::readSize(write("gray.png", encodePng(gray, PngSpec{{0}})), &w, &h));
  EXPECT_EQ(w, 9);
  EXPECT_EQ(h, 8);
  Bytes colour;
  cv::Mat three;
  cv::merge(std::vector<cv::Mat>{gray, gray, gray}, three);
  ASSERT_TRUE(cv::imencode(".png", three, colour));
  ASSERT_TRUE(PngGrayDecoder::readSize(write("colour.png", colour), &w, &h));
  EXPECT_EQ(w, 9);
  // A header claiming 30000 x 20000 pixels in a few bytes is read as such: nothing is decoded.
  const Bytes forged = forgedHeader(30000, 20000);
  ASSERT_TRUE(PngGrayDecoder::readSize(write("forged.png", forged), &w, &h));
  EXPECT_EQ(w, 30000);
  EXPECT_EQ(h, 20000);
  EXPECT_FALSE(PngGrayDecoder::readSize(write("short.png", Bytes(forged.begin(), forged.begin() + 20)), &w, &h));
  EXPECT_FALSE(PngGrayDecoder::readSize(write("text.png", Bytes(30, 'x')), &w, &h));
  EXPECT_FALSE(PngGrayDecoder::readSize((dir / "missing.png").string(), &w, &h));
}

TEST(PngGrayDecoder, MissingFileIsAnInputErrorNamingIt) {
  cv::Mat out;
  try {
    PngGrayDecoder::decodeFile("/nonexistent/dir/1.png", &out);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/1.png: cannot read or decode image"), std::string::npos);
  }
}

TEST(PngGrayDecoder, RealEurocImagesEqualLibpngs) {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  const fs::path dir = fs::path(shared != nullptr ? shared : "") / "data" / "euroc_V1_01_excerpt" / "mav0";
  if (shared == nullptr || !fs::is_directory(dir)) GTEST_SKIP() << "MCVIO_SHARED_DIR/data/euroc_V1_01_excerpt not present";
  int n = 0;
  for (const char* cam : {"cam0", "cam1"})
    for (const auto& entry : fs::directory_iterator(dir / cam / "data")) {
      cv::Mat ours;
      ASSERT_EQ(PngGrayDecoder::decodeFile(entry.path().string(), &ours), Status::kDecoded) << entry.path();
      expectSame(ours, cv::imread(entry.path().string(), cv::IMREAD_GRAYSCALE));
      ++n;
    }
  EXPECT_GE(n, 190);
}

}  // namespace
}  // namespace mcvio::dataset
