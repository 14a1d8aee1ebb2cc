#include "mcvio/bag/bag_metadata.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/write_failure.hpp"

namespace mcvio::bag {

namespace {

void emitTime(YAML::Emitter& e, const char* key, const char* sub, Timestamp t) {
  e << YAML::Key << key << YAML::Value << YAML::BeginMap << YAML::Key << sub << YAML::Value << t
    << YAML::EndMap;
}

}  // namespace

std::string bagMetadataToYaml(const BagMetadata& m) {
  YAML::Emitter e;
  e << YAML::BeginMap << YAML::Key << "rosbag2_bagfile_information" << YAML::Value
    << YAML::BeginMap;
  e << YAML::Key << "version" << YAML::Value << m.version;
  e << YAML::Key << "storage_identifier" << YAML::Value << m.storage_identifier;
  emitTime(e, "duration", "nanoseconds", m.duration);
  emitTime(e, "starting_time", "nanoseconds_since_epoch", m.starting_time);
  e << YAML::Key << "message_count" << YAML::Value << m.message_count;
  e << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
  for (const auto& t : m.topics_with_message_count) {
    e << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap;
    e << YAML::Key << "name" << YAML::Value << t.topic.name;
    e << YAML::Key << "type" << YAML::Value << t.topic.type;
    e << YAML::Key << "serialization_format" << YAML::Value << t.topic.serialization_format;
    e << YAML::Key << "offered_qos_profiles" << YAML::Value << YAML::DoubleQuoted
      << t.topic.offered_qos_profiles;
    e << YAML::Key << "type_description_hash" << YAML::Value << YAML::DoubleQuoted
      << t.topic.type_description_hash;
    e << YAML::EndMap << YAML::Key << "message_count" << YAML::Value << t.message_count
      << YAML::EndMap;
  }
  e << YAML::EndSeq;
  e << YAML::Key << "compression_format" << YAML::Value << YAML::DoubleQuoted
    << m.compression_format;
  e << YAML::Key << "compression_mode" << YAML::Value << YAML::DoubleQuoted << m.compression_mode;
  e << YAML::Key << "relative_file_paths" << YAML::Value << YAML::BeginSeq;
  for (const auto& p : m.relative_file_paths) e << p;
  e << YAML::EndSeq;
  e << YAML::Key << "files" << YAML::Value << YAML::BeginSeq;
  for (const auto& f : m.files) {
    e << YAML::BeginMap << YAML::Key << "path" << YAML::Value << f.path;
    emitTime(e, "starting_time", "nanoseconds_since_epoch", f.starting_time);
    emitTime(e, "duration", "nanoseconds", f.duration);
    e << YAML::Key << "message_count" << YAML::Value << f.message_count << YAML::EndMap;
  }
  e << YAML::EndSeq;
  e << YAML::Key << "custom_data" << YAML::Value;
  if (m.custom_data.empty()) {
    e << YAML::Null;
  } else {
    e << YAML::BeginMap;
    for (const auto& [k, v] : m.custom_data) e << YAML::Key << k << YAML::Value << v;
    e << YAML::EndMap;
  }
  e << YAML::Key << "ros_distro" << YAML::Value << m.ros_distro;
  e << YAML::EndMap << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

namespace {

/// Reads `node[key]` as T; InputError naming the file and key path otherwise.
template <typename T>
T field(const YAML::Node& node, const std::string& key, const std::string& where,
        const std::string& source) {
  const YAML::Node v = node[key];
  if (!v) throw InputError(source + ": missing key '" + where + key + "'");
  try {
    return v.as<T>();
  } catch (const YAML::Exception& ex) {
    throw InputError(source + ": key '" + where + key + "' (line " +
                     std::to_string(v.Mark().line + 1) + ") has the wrong type: " + ex.msg);
  }
}

Timestamp timeField(const YAML::Node& node, const std::string& key, const char* sub,
                    const std::string& where, const std::string& source) {
  const YAML::Node v = node[key];
  if (!v || !v.IsMap()) throw InputError(source + ": missing map '" + where + key + "'");
  return field<Timestamp>(v, sub, where + key + ".", source);
}

}  // namespace

namespace {
BagMetadata parseMetadata(const std::string& yaml, const std::string& source);
}

BagMetadata bagMetadataFromYaml(const std::string& yaml, const std::string& source) {
  try {
    return parseMetadata(yaml, source);
  } catch (const YAML::Exception& ex) {
    // Anything the field checks did not name (e.g. a list where a map belongs).
    throw InputError(source + ": unexpected structure (line " + std::to_string(ex.mark.line + 1) +
                     "): " + ex.msg);
  }
}

namespace {

BagMetadata parseMetadata(const std::string& yaml, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& ex) {
    throw InputError(source + ": not valid YAML (line " + std::to_string(ex.mark.line + 1) +
                     "): " + ex.msg);
  }
  const YAML::Node info = root.IsMap() ? root["rosbag2_bagfile_information"] : YAML::Node();
  if (!info || !info.IsMap()) {
    throw InputError(source + ": missing map 'rosbag2_bagfile_information'");
  }
  const std::string w = "rosbag2_bagfile_information.";
  BagMetadata m;
  m.version = field<int>(info, "version", w, source);
  if (m.version < kMinMetadataVersion) {
    throw InputError(source + ": metadata version " + std::to_string(m.version) +
                     " is older than the oldest supported (" + std::to_string(kMinMetadataVersion) +
                     ")");
  }
  m.storage_identifier = field<std::string>(info, "storage_identifier", w, source);
  m.duration = timeField(info, "duration", "nanoseconds", w, source);
  m.starting_time = timeField(info, "starting_time", "nanoseconds_since_epoch", w, source);
  m.message_count = field<std::uint64_t>(info, "message_count", w, source);
  const YAML::Node topics = info["topics_with_message_count"];
  if (topics && !topics.IsNull()) {
    if (!topics.IsSequence()) {
      throw InputError(source + ": key '" + w + "topics_with_message_count' must be a list");
    }
    for (std::size_t i = 0; i < topics.size(); ++i) {
      const std::string tw = w + "topics_with_message_count[" + std::to_string(i) + "].";
      const YAML::Node tm = topics[i]["topic_metadata"];
      if (!tm || !tm.IsMap()) throw InputError(source + ": missing map '" + tw + "topic_metadata'");
      TopicInformation ti;
      const std::string mw = tw + "topic_metadata.";
      ti.topic.name = field<std::string>(tm, "name", mw, source);
      ti.topic.type = field<std::string>(tm, "type", mw, source);
      ti.topic.serialization_format = field<std::string>(tm, "serialization_format", mw, source);
      const YAML::Node qos = tm["offered_qos_profiles"];
      if (qos && qos.IsScalar()) {
        ti.topic.offered_qos_profiles = qos.as<std::string>();
      } else if (qos && !qos.IsNull()) {
        // Version 9 writes the profiles as a YAML list; keep them as YAML text.
        YAML::Emitter e;
        e << qos;
        ti.topic.offered_qos_profiles = e.c_str();
      }
      if (tm["type_description_hash"]) {
        ti.topic.type_description_hash =
            field<std::string>(tm, "type_description_hash", mw, source);
      }
      ti.message_count = field<std::uint64_t>(topics[i], "message_count", tw, source);
      m.topics_with_message_count.push_back(std::move(ti));
    }
  }
  if (info["compression_format"]) {
    m.compression_format = field<std::string>(info, "compression_format", w, source);
  }
  if (info["compression_mode"]) {
    m.compression_mode = field<std::string>(info, "compression_mode", w, source);
  }
  m.relative_file_paths = field<std::vector<std::string>>(info, "relative_file_paths", w, source);
  const YAML::Node files = info["files"];
  if (files && files.IsSequence()) {
    for (std::size_t i = 0; i < files.size(); ++i) {
      const std::string fw = w + "files[" + std::to_string(i) + "].";
      FileInformation f;
      f.path = field<std::string>(files[i], "path", fw, source);
      f.starting_time = timeField(files[i], "starting_time", "nanoseconds_since_epoch", fw, source);
      f.duration = timeField(files[i], "duration", "nanoseconds", fw, source);
      f.message_count = field<std::uint64_t>(files[i], "message_count", fw, source);
      m.files.push_back(std::move(f));
    }
  }
  const YAML::Node custom = info["custom_data"];
  if (custom && custom.IsMap()) {
    for (const auto& kv : custom) {
      m.custom_data[kv.first.as<std::string>()] = kv.second.as<std::string>();
    }
  }
  if (info["ros_distro"] && info["ros_distro"].IsScalar()) {
    m.ros_distro = info["ros_distro"].as<std::string>();
  }
  for (const auto& p : m.relative_file_paths) {
    const std::filesystem::path fp(p);
    if (fp.is_absolute() || p.find("..") != std::string::npos || p.empty()) {
      throw InputError(source + ": relative_file_paths entry '" + p +
                       "' must be a plain file name inside the bag");
    }
  }
  return m;
}

}  // namespace

BagMetadata readBagMetadata(const std::filesystem::path& bag_dir) {
  const auto path = bag_dir / kMetadataFileName;
  std::error_code ec;
  if (!std::filesystem::exists(bag_dir, ec)) throw InputError(bag_dir.string() + ": no such bag directory or file");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(path.string() + ": missing metadata.yaml (`mcvio bag reindex " +
                     bag_dir.string() + "` rebuilds it from the .mcap/.db3 files)");
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return bagMetadataFromYaml(ss.str(), path.string());
}

void writeBagMetadata(const std::filesystem::path& bag_dir, const BagMetadata& metadata) {
  const auto path = bag_dir / kMetadataFileName;
  const auto tmp = bag_dir / (std::string(kMetadataFileName) + ".tmp");
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << bagMetadataToYaml(metadata);
    out.flush();
    if (!out) throwCannotWrite(tmp, errno, "the bag's metadata");
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace mcvio::bag
