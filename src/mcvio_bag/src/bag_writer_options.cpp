#include "mcvio/bag/bag_writer_options.hpp"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_fields.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::bag {

void BagWriterOptions::validate() const {
  if (storage != "mcap" && storage != "sqlite3") {
    throw std::invalid_argument("storage: '" + storage + "' is not mcap or sqlite3");
  }
  if (chunk_size == 0) throw std::invalid_argument("chunk_size: must be > 0");
  if (chunk_size > (1ull << 31)) throw std::invalid_argument("chunk_size: must be <= 2 GiB");
  if (max_bagfile_duration < 0) throw std::invalid_argument("max_bagfile_duration: must be >= 0");
  if (compression == Compression::Zstd && (compression_level < -7 || compression_level > 22)) {
    throw std::invalid_argument("compression_level: zstd levels are -7..22");
  }
  if (compression == Compression::Lz4 && (compression_level < 0 || compression_level > 12)) {
    throw std::invalid_argument("compression_level: lz4 levels are 0..12");
  }
}

BagWriterOptions BagWriterOptions::fromYaml(const std::string& yaml, const std::string& source) {
  const YAML::Node root = parseYamlText(yaml, source);
  BagWriterOptions o;
  try {
    YamlFields f(root, "", "key");
    f.get("storage", &o.storage);
    if (f.has("compression")) {
      std::string compression;
      f.get("compression", &compression);
      try {
        o.compression = compressionFromString(compression);
      } catch (const std::invalid_argument& e) {
        throw InputError(std::string("key 'compression': ") + e.what());
      }
    }
    f.get("compression_level", &o.compression_level);
    f.get("chunk_size", &o.chunk_size);
    f.get("max_bagfile_size", &o.max_bagfile_size);
    if (f.has("max_bagfile_duration")) {
      double seconds = 0;
      f.get("max_bagfile_duration", &seconds);
      o.max_bagfile_duration = fromSeconds(seconds);
    }
    f.get("fsync", &o.fsync);
    f.get("crc", &o.crc);
    f.get("ros_distro", &o.ros_distro);
    f.get("custom_data", &o.custom_data);
    f.rejectUnknown();
  } catch (const InputError& e) {
    throw InputError(source + ": " + e.what());
  }
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(source + ": " + e.what());
  }
  return o;
}

BagWriterOptions BagWriterOptions::fromYamlFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return fromYaml(ss.str(), path.string());
}

}  // namespace mcvio::bag
