#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mcvio/bag/compression.hpp"
#include "mcvio/bag/storage_file_writer.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace mcvio::bag {

/// Options of one rosbag2 sqlite3 file.
struct SqliteWriterOptions {
  /// Per-message compression (rosbag2's "message" mode); rosbag2 itself only ships zstd.
  Compression compression = Compression::None;
  int compression_level = 1;
  /// Messages are committed in transactions of about this many payload bytes.
  std::uint64_t transaction_size = 1024 * 1024;
  /// synchronous=FULL instead of NORMAL: committed data also survives power loss.
  bool fsync_each_transaction = false;
  std::string ros_distro;  ///< Stored in the schema table.
};

/// Writes one .db3 file with rosbag2's sqlite3 schema (version 4: schema, metadata, topics,
/// message_definitions, messages). The database runs in WAL mode while recording, so a killed
/// process keeps every committed transaction; close() checkpoints it back into one file.
class SqliteWriter : public StorageFileWriter {
 public:
  SqliteWriter(const std::filesystem::path& path, SqliteWriterOptions options = {});
  ~SqliteWriter() override;

  void addTopic(std::size_t topic_index, const TopicInfo& topic) override;
  void write(std::size_t topic_index, Timestamp log_time, Timestamp publish_time,
             std::uint32_t sequence, const std::uint8_t* data, std::size_t size) override;
  /// Commits the open transaction.
  void flush() override;
  std::uint64_t sizeBytes() const override;
  void close() override;
  /// Stores the bag's metadata YAML in the metadata table (rosbag2 does this at close).
  void setMetadataYaml(const std::string& yaml);

  /// rosbag2's sqlite3 schema version written here.
  static constexpr int kSchemaVersion = 4;

 private:
  void exec(const std::string& sql);
  [[noreturn]] void fail(const std::string& what) const;

  std::filesystem::path path_;
  SqliteWriterOptions options_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  std::vector<std::string> known_types_;
  std::vector<std::uint8_t> compressed_;
  std::uint64_t pending_bytes_ = 0;
  std::uint64_t written_bytes_ = 0;
  bool in_transaction_ = false;
  std::string metadata_yaml_;
};

}  // namespace mcvio::bag
