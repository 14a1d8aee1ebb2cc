#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "mcvio/bag/bag_message.hpp"
#include "mcvio/bag/bag_metadata.hpp"
#include "mcvio/bag/bag_writer_options.hpp"
#include "mcvio/bag/storage_file_writer.hpp"
#include "mcvio/bag/topic_info.hpp"

namespace mcvio::bag {

/// Records a rosbag2 bag: a directory with metadata.yaml and one or more storage files
/// (`<dir name>_<n>.mcap` or `.db3`), split by size or duration.
///
/// Durability: messages are buffered per chunk/transaction and handed to the kernel when it
/// fills, so a killed process loses at most one chunk_size of the newest messages.
/// metadata.yaml is written when the bag opens and on every split (listing the files), and in
/// full at close(); after a crash BagReindexer rebuilds it and the MCAP summaries.
class BagWriter {
 public:
  /// Creates `bag_dir` (it must not exist, or be an empty directory).
  explicit BagWriter(const std::filesystem::path& bag_dir, BagWriterOptions options = {});
  /// Closes the bag if close() was not called (errors are swallowed there: call close()).
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  /// Registers a topic and returns its index for the fast write(). Registering the same name
  /// again with the same type returns the old index. InputError when the type differs from
  /// the one registered, or the message definition does not parse (ros2msg).
  std::size_t addTopic(const TopicInfo& topic);
  /// Appends one message. `log_time` is the receive time, `publish_time` the publish/header
  /// time. std::invalid_argument for an unregistered topic.
  void write(const std::string& topic, Timestamp log_time, Timestamp publish_time,
             const std::uint8_t* data, std::size_t size);
  void write(std::size_t topic_index, Timestamp log_time, Timestamp publish_time,
             const std::uint8_t* data, std::size_t size);
  void write(const BagMessage& message);
  /// Persists buffered messages now (ends the current chunk/transaction early).
  void flush();
  /// Finishes the open file and writes the final metadata.yaml. Idempotent.
  void close();

  const BagMetadata& metadata() const { return metadata_; }
  const std::filesystem::path& path() const { return dir_; }

 private:
  void openFile();
  void closeFile();
  void refreshMetadata();

  std::filesystem::path dir_;
  BagWriterOptions options_;
  BagMetadata metadata_;
  std::vector<TopicInfo> topics_;
  std::vector<std::uint64_t> topic_counts_;
  std::vector<std::uint32_t> sequences_;
  std::unordered_map<std::string, std::size_t> topic_index_;
  std::unique_ptr<StorageFileWriter> file_;
  FileInformation current_;
  bool closed_ = false;
};

}  // namespace mcvio::bag
