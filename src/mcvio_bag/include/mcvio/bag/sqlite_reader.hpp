#pragma once
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "mcvio/bag/compression.hpp"
#include "mcvio/bag/storage_file_reader.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace mcvio::bag {

/// Reads one rosbag2 sqlite3 file (schema versions 2..4; message definitions when the file has
/// the message_definitions table). Bad input throws mcvio::InputError naming the file.
/// sqlite stores no publish time: messages come back with publish_time = log_time.
class SqliteReader : public StorageFileReader {
 public:
  /// `message_compression` is the bag's rosbag2 message compression (metadata.yaml).
  explicit SqliteReader(const std::filesystem::path& path,
                        Compression message_compression = Compression::None);
  ~SqliteReader() override;
  SqliteReader(const SqliteReader&) = delete;
  SqliteReader& operator=(const SqliteReader&) = delete;

  const std::vector<TopicInfo>& topics() const override { return topics_; }
  void setTopicFilter(const std::set<std::string>& topics) override;
  bool next(BagMessage& out) override;
  FileStatistics statistics() const override;
  /// The YAML stored in the metadata table, or empty.
  std::string storedMetadataYaml() const;

  /// Makes a file left by a killed writer self-contained: replays its write-ahead log (every
  /// committed transaction) into the .db3 and switches it out of WAL mode.
  static void recover(const std::filesystem::path& path);

 private:
  [[noreturn]] void fail(const std::string& what) const;
  std::string name_;
  Compression compression_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* cursor_ = nullptr;
  std::vector<TopicInfo> topics_;
  std::vector<long long> topic_ids_;
  std::set<long long> selected_;
  bool filtered_ = false;
  std::vector<std::uint8_t> scratch_;
};

}  // namespace mcvio::bag
