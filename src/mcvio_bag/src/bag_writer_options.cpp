#include "mcvio/bag/bag_writer_options.hpp"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "mcvio/core/input_error.hpp"
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
  if (root.IsNull()) return o;
  if (!root.IsMap()) throw InputError(source + ": bag writer options must be a YAML map");
  static const std::set<std::string> known = {"storage",
                                              "compression",
                                              "compression_level",
                                              "chunk_size",
                                              "max_bagfile_size",
                                              "max_bagfile_duration",
                                              "fsync",
                                              "crc",
                                              "ros_distro",
                                              "custom_data"};
  for (const auto& kv : root) {
    const auto key = kv.first.as<std::string>();
    if (known.count(key) == 0) throw InputError(source + ": unknown key '" + key + "'");
  }
  std::string key;
  try {
    key = "storage";
    if (root[key]) o.storage = root[key].as<std::string>();
    key = "compression";
    if (root[key]) o.compression = compressionFromString(root[key].as<std::string>());
    key = "compression_level";
    if (root[key]) o.compression_level = root[key].as<int>();
    key = "chunk_size";
    if (root[key]) o.chunk_size = root[key].as<std::uint64_t>();
    key = "max_bagfile_size";
    if (root[key]) o.max_bagfile_size = root[key].as<std::uint64_t>();
    key = "max_bagfile_duration";
    if (root[key]) o.max_bagfile_duration = fromSeconds(root[key].as<double>());
    key = "fsync";
    if (root[key]) o.fsync = root[key].as<bool>();
    key = "crc";
    if (root[key]) o.crc = root[key].as<bool>();
    key = "ros_distro";
    if (root[key]) o.ros_distro = root[key].as<std::string>();
    key = "custom_data";
    if (root[key]) o.custom_data = root[key].as<std::map<std::string, std::string>>();
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": key '" + key + "': " + e.msg);
  } catch (const std::invalid_argument& e) {
    throw InputError(source + ": key '" + key + "': " + e.what());
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
