#include "mcvio/bag/bag_writer.hpp"

#include <algorithm>
#include <stdexcept>

#include "mcvio/bag/mcap_writer.hpp"
#include "mcvio/bag/message_definition.hpp"
#include "mcvio/bag/sqlite_writer.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

BagWriter::BagWriter(const std::filesystem::path& bag_dir, BagWriterOptions options)
    : dir_(bag_dir), options_(std::move(options)) {
  options_.validate();
  if (std::filesystem::exists(dir_)) {
    if (!std::filesystem::is_directory(dir_) || !std::filesystem::is_empty(dir_)) {
      throw std::invalid_argument(dir_.string() + ": exists and is not an empty directory");
    }
  } else {
    std::filesystem::create_directories(dir_);
  }
  metadata_.storage_identifier = options_.storage;
  metadata_.ros_distro = options_.ros_distro;
  metadata_.custom_data = options_.custom_data;
  if (options_.storage == "sqlite3" && options_.compression != Compression::None) {
    metadata_.compression_format = toString(options_.compression);
    metadata_.compression_mode = "MESSAGE";
  }
  openFile();
}

BagWriter::~BagWriter() {
  try {
    close();
  } catch (...) {
    // Destructors must not throw; close() reports errors.
  }
}

void BagWriter::openFile() {
  const std::string stem =
      dir_.filename().empty() ? dir_.parent_path().filename().string() : dir_.filename().string();
  const std::string ext = options_.storage == "mcap" ? ".mcap" : ".db3";
  const std::string name = stem + "_" + std::to_string(metadata_.relative_file_paths.size()) + ext;
  if (options_.storage == "mcap") {
    McapWriterOptions o;
    o.compression = options_.compression;
    o.compression_level = options_.compression_level;
    o.chunk_size = options_.chunk_size;
    o.fsync_each_chunk = options_.fsync;
    o.compute_crcs = options_.crc;
    file_ = std::make_unique<McapWriter>(dir_ / name, o);
  } else {
    SqliteWriterOptions o;
    o.compression = options_.compression;
    o.compression_level = options_.compression_level;
    o.transaction_size = options_.chunk_size;
    o.fsync_each_transaction = options_.fsync;
    o.ros_distro = options_.ros_distro;
    file_ = std::make_unique<SqliteWriter>(dir_ / name, o);
  }
  for (std::size_t i = 0; i < topics_.size(); ++i) file_->addTopic(i, topics_[i]);
  current_ = FileInformation{};
  current_.path = name;
  metadata_.relative_file_paths.push_back(name);
  refreshMetadata();
  // The file list on disk is what reindex starts from after a crash.
  writeBagMetadata(dir_, metadata_);
}

void BagWriter::refreshMetadata() {
  metadata_.files.resize(metadata_.relative_file_paths.size() - 1);
  metadata_.files.push_back(current_);
  metadata_.message_count = 0;
  Timestamp start = 0;
  Timestamp end = 0;
  bool any = false;
  for (const auto& f : metadata_.files) {
    if (f.message_count == 0) continue;
    metadata_.message_count += f.message_count;
    start = any ? std::min(start, f.starting_time) : f.starting_time;
    end = any ? std::max(end, f.starting_time + f.duration) : f.starting_time + f.duration;
    any = true;
  }
  metadata_.starting_time = start;
  metadata_.duration = end - start;
  metadata_.topics_with_message_count.clear();
  for (std::size_t i = 0; i < topics_.size(); ++i) {
    TopicInformation ti;
    ti.topic = topics_[i];
    ti.topic.message_definition.clear();
    ti.message_count = topic_counts_[i];
    metadata_.topics_with_message_count.push_back(std::move(ti));
  }
}

std::size_t BagWriter::addTopic(const TopicInfo& topic) {
  if (closed_) throw std::logic_error("BagWriter::addTopic after close");
  if (auto it = topic_index_.find(topic.name); it != topic_index_.end()) {
    if (topics_[it->second].type != topic.type) {
      throw InputError("topic '" + topic.name + "' registered as '" + topics_[it->second].type +
                       "' and again as '" + topic.type + "'");
    }
    return it->second;
  }
  if (topic.name.empty()) throw InputError("topic with an empty name");
  if (topic.type.empty()) throw InputError("topic '" + topic.name + "' has no type");
  try {
    MessageDefinitionParser::parse(topic.type, topic.message_definition);
  } catch (const InputError& e) {
    throw InputError("topic '" + topic.name + "': " + e.what());
  }
  const std::size_t index = topics_.size();
  topics_.push_back(topic);
  topic_counts_.push_back(0);
  sequences_.push_back(0);
  topic_index_[topic.name] = index;
  file_->addTopic(index, topic);
  return index;
}

void BagWriter::write(const std::string& topic, Timestamp log_time, Timestamp publish_time,
                      const std::uint8_t* data, std::size_t size) {
  const auto it = topic_index_.find(topic);
  if (it == topic_index_.end()) {
    throw std::invalid_argument("BagWriter::write: topic '" + topic + "' was not added");
  }
  write(it->second, log_time, publish_time, data, size);
}

void BagWriter::write(const BagMessage& m) {
  write(m.topic, m.log_time, m.publish_time, m.data.data(), m.data.size());
}

void BagWriter::write(std::size_t topic_index, Timestamp log_time, Timestamp publish_time,
                      const std::uint8_t* data, std::size_t size) {
  if (closed_) throw std::logic_error("BagWriter::write after close");
  if (topic_index >= topics_.size())
    throw std::invalid_argument("BagWriter::write: bad topic index");
  if (current_.message_count > 0) {
    const bool too_big =
        options_.max_bagfile_size > 0 && file_->sizeBytes() >= options_.max_bagfile_size;
    const bool too_long = options_.max_bagfile_duration > 0 &&
                          log_time - current_.starting_time >= options_.max_bagfile_duration;
    if (too_big || too_long) {
      closeFile();
      openFile();
    }
  }
  file_->write(topic_index, log_time, publish_time, sequences_[topic_index]++, data, size);
  if (current_.message_count == 0) {
    current_.starting_time = log_time;
  } else if (log_time < current_.starting_time) {
    current_.duration += current_.starting_time - log_time;
    current_.starting_time = log_time;
  }
  current_.duration = std::max(current_.duration, log_time - current_.starting_time);
  ++current_.message_count;
  ++topic_counts_[topic_index];
}

void BagWriter::flush() {
  if (!closed_) file_->flush();
}

void BagWriter::closeFile() {
  refreshMetadata();
  if (auto* sqlite = dynamic_cast<SqliteWriter*>(file_.get())) {
    sqlite->setMetadataYaml(bagMetadataToYaml(metadata_));
  }
  if (auto* mcap = dynamic_cast<McapWriter*>(file_.get())) {
    mcap->addMetadata("rosbag2", {{"serialized_metadata", bagMetadataToYaml(metadata_)}});
  }
  file_->close();
  file_.reset();
}

void BagWriter::close() {
  if (closed_) return;
  closed_ = true;
  closeFile();
  writeBagMetadata(dir_, metadata_);
}

}  // namespace mcvio::bag
