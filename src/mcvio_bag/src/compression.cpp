#include "mcvio/bag/compression.hpp"

#include <lz4frame.h>
#include <zstd.h>

#include <stdexcept>

namespace mcvio::bag {

Compression compressionFromString(const std::string& name) {
  if (name.empty() || name == "none") return Compression::None;
  if (name == "zstd") return Compression::Zstd;
  if (name == "lz4") return Compression::Lz4;
  throw std::invalid_argument("unknown compression '" + name + "' (expected none, zstd or lz4)");
}

std::string mcapCompressionName(Compression c) {
  switch (c) {
    case Compression::Zstd:
      return "zstd";
    case Compression::Lz4:
      return "lz4";
    case Compression::None:
      break;
  }
  return "";
}

std::string toString(Compression c) {
  return c == Compression::None ? "none" : mcapCompressionName(c);
}

void Codec::compress(Compression c, const std::uint8_t* data, std::size_t size, int level,
                     std::vector<std::uint8_t>& out) {
  const std::size_t base = out.size();
  if (c == Compression::None) {
    out.insert(out.end(), data, data + size);
    return;
  }
  if (c == Compression::Zstd) {
    out.resize(base + ZSTD_compressBound(size));
    const std::size_t n = ZSTD_compress(out.data() + base, out.size() - base, data, size, level);
    if (ZSTD_isError(n)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(n));
    out.resize(base + n);
    return;
  }
  LZ4F_preferences_t prefs{};
  prefs.compressionLevel = level;
  prefs.frameInfo.contentSize = size;  // lets readers size their buffer up front
  prefs.frameInfo.blockSizeID = LZ4F_max4MB;
  out.resize(base + LZ4F_compressFrameBound(size, &prefs));
  const std::size_t n =
      LZ4F_compressFrame(out.data() + base, out.size() - base, data, size, &prefs);
  if (LZ4F_isError(n)) throw std::runtime_error(std::string("lz4: ") + LZ4F_getErrorName(n));
  out.resize(base + n);
}

namespace {

/// Streams an lz4 frame into `out`, refusing to grow beyond `max_size`.
void lz4DecompressFrame(const std::uint8_t* data, std::size_t size, std::size_t max_size,
                        std::vector<std::uint8_t>& out, bool exact) {
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) {
    throw std::runtime_error("lz4: cannot create a decompression context");
  }
  std::size_t produced = 0;
  std::size_t consumed = 0;
  std::size_t hint = 1;
  try {
    if (out.size() < 64) out.resize(exact ? max_size : std::min<std::size_t>(max_size, 1 << 16));
    while (consumed < size && hint != 0) {
      if (produced == out.size()) {
        if (out.size() >= max_size) throw std::runtime_error("lz4: output larger than expected");
        out.resize(std::min(max_size, out.size() * 2));
      }
      std::size_t dst_n = out.size() - produced;
      std::size_t src_n = size - consumed;
      hint = LZ4F_decompress(ctx, out.data() + produced, &dst_n, data + consumed, &src_n, nullptr);
      if (LZ4F_isError(hint)) {
        throw std::runtime_error(std::string("lz4: ") + LZ4F_getErrorName(hint));
      }
      produced += dst_n;
      consumed += src_n;
      if (dst_n == 0 && src_n == 0 && produced < out.size()) {
        throw std::runtime_error("lz4: decoder made no progress");
      }
    }
    if (hint != 0) throw std::runtime_error("lz4: frame is truncated");
  } catch (...) {
    LZ4F_freeDecompressionContext(ctx);
    throw;
  }
  LZ4F_freeDecompressionContext(ctx);
  out.resize(produced);
}

}  // namespace

void Codec::decompress(Compression c, const std::uint8_t* data, std::size_t size,
                       std::size_t expected_size, std::vector<std::uint8_t>& out) {
  if (c == Compression::None) {
    if (size != expected_size) throw std::runtime_error("uncompressed size mismatch");
    out.assign(data, data + size);
    return;
  }
  // The sizes come from the file: check them against the frame before allocating, so a forged
  // size cannot make us allocate gigabytes (found by fuzzing).
  if (c == Compression::Zstd) {
    const unsigned long long known = ZSTD_getFrameContentSize(data, size);
    if (known == ZSTD_CONTENTSIZE_ERROR) throw std::runtime_error("zstd: not a zstd frame");
    if (known != ZSTD_CONTENTSIZE_UNKNOWN && known != expected_size) {
      throw std::runtime_error("zstd: frame content size differs from record");
    }
    // A zstd block of 128 KiB compresses to no less than 4 bytes.
    if (expected_size / 32768 > size + 1) {
      throw std::runtime_error("zstd: uncompressed size implausible for the compressed size");
    }
    out.resize(expected_size);
    const std::size_t n = ZSTD_decompress(out.data(), expected_size, data, size);
    if (ZSTD_isError(n)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(n));
    if (n != expected_size) throw std::runtime_error("zstd: decompressed size differs from record");
    return;
  }
  // LZ4 cannot compress better than about 255:1.
  if (expected_size / 255 > size + 64) {
    throw std::runtime_error("lz4: uncompressed size implausible for the compressed size");
  }
  out.clear();
  out.resize(expected_size == 0 ? 1 : expected_size);
  lz4DecompressFrame(data, size, expected_size == 0 ? 1 : expected_size, out, true);
  if (out.size() != expected_size) {
    throw std::runtime_error("lz4: decompressed size differs from record");
  }
}

void Codec::decompressFrame(Compression c, const std::uint8_t* data, std::size_t size,
                            std::size_t max_size, std::vector<std::uint8_t>& out) {
  if (c == Compression::None) {
    out.assign(data, data + size);
    return;
  }
  if (c == Compression::Zstd) {
    const unsigned long long known = ZSTD_getFrameContentSize(data, size);
    if (known == ZSTD_CONTENTSIZE_ERROR) throw std::runtime_error("zstd: not a zstd frame");
    if (known != ZSTD_CONTENTSIZE_UNKNOWN) {
      if (known > max_size) throw std::runtime_error("zstd: frame content size too large");
      decompress(c, data, size, static_cast<std::size_t>(known), out);
      return;
    }
    // Unknown content size: stream.
    ZSTD_DStream* ds = ZSTD_createDStream();
    out.clear();
    ZSTD_inBuffer in{data, size, 0};
    std::size_t ret = 1;
    while (in.pos < in.size && ret != 0) {
      const std::size_t base = out.size();
      if (base >= max_size) {
        ZSTD_freeDStream(ds);
        throw std::runtime_error("zstd: output larger than allowed");
      }
      out.resize(std::min(max_size, base + ZSTD_DStreamOutSize()));
      ZSTD_outBuffer o{out.data() + base, out.size() - base, 0};
      ret = ZSTD_decompressStream(ds, &o, &in);
      out.resize(base + o.pos);
      if (ZSTD_isError(ret)) {
        ZSTD_freeDStream(ds);
        throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(ret));
      }
    }
    ZSTD_freeDStream(ds);
    if (ret != 0) throw std::runtime_error("zstd: frame is truncated");
    return;
  }
  out.clear();
  lz4DecompressFrame(data, size, max_size, out, false);
}

}  // namespace mcvio::bag
