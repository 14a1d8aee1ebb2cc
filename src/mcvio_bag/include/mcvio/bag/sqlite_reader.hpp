#pragma once
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "mcvio/bag/compression.hpp"
#include "mcvio/bag/storage_file_reader.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace mcvio::bag {

/// Reads one rosbag2 sqlite3 file (schema versions 1..4; message definitions when the file has
/// the message_definitions table). Bad input throws mcvio::InputError naming the file (and the
/// topic, row and field where one is at fault): missing tables or columns, a topic without a
/// name or type, one name declared with two types, messages of an unknown topic id, timestamps
/// that are not non-negative integers, data that is NULL or not a BLOB (an empty BLOB is an
/// empty message, as the writer stores it).
/// sqlite stores no publish time: messages come back with publish_time = log_time.
/// The file and its -wal are never modified: committed transactions still in a -wal are read;
/// where sqlite cannot read them in place (a read-only folder without a -shm, a hot -journal)
/// a temporary copy is read instead.
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
  std::vector<std::string> warnings() const override { return warnings_; }
  /// Every row in row id order, checked as next() checks it and decompressed with the
  /// compression the reader was given. Damaged pages end the scan: the rows beyond them are
  /// counted per topic when sqlite still can.
  void verify(VerifySink& sink) override;
  /// verify() with another message compression (e.g. the one the messages show when
  /// metadata.yaml names the wrong one).
  void verify(VerifySink& sink, Compression message_compression);
  /// The YAML stored in the metadata table, or empty.
  std::string storedMetadataYaml() const;
  /// The message compression the first stored message shows (a zstd or lz4 frame starts with
  /// its magic, a CDR message never does); nullopt when the file holds no message.
  std::optional<Compression> firstMessageCompression() const;

  /// Makes a file left by a killed writer self-contained: replays its write-ahead log (every
  /// committed transaction) into the .db3 and switches it out of WAL mode; a hot rollback
  /// journal is rolled back. Then checks the file (PRAGMA quick_check): InputError when it is
  /// damaged, which this cannot repair. Returns true when a -wal or -journal file was folded in.
  static bool recover(const std::filesystem::path& path);
  /// True when the file starts with the sqlite3 magic (whatever its extension).
  static bool looksLikeSqlite(const std::filesystem::path& path);

 private:
  [[noreturn]] void fail(const std::string& what) const;
  /// Checks and decodes the current row of `st` (rowid, topic_id, timestamp, data) into `out`;
  /// InputError naming the row, topic and field when it cannot be read. False when `filter`
  /// is set and the topic filter excludes the row.
  bool readRow(sqlite3_stmt* st, Compression compression, bool filter, BagMessage& out);
  /// Opens `path` into db_ and reads its schema once; false (db_ null, `why` set) on failure.
  bool openDatabase(const std::filesystem::path& path, bool read_only, std::string& why);
  /// Copies the file with its -wal / -journal into a new temp_dir_; returns the copy's path.
  std::filesystem::path copyToTempDir(const std::filesystem::path& path);
  void removeTempDir();
  void readTopics(bool has_definitions);
  /// The column names of `table`.
  std::set<std::string> columns(const std::string& table) const;
  std::string name_;
  Compression compression_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* cursor_ = nullptr;
  std::vector<TopicInfo> topics_;
  /// topics row id -> index into topics_ (a name declared twice with one type shares an entry).
  std::map<long long, std::size_t> topic_index_;
  std::set<long long> selected_;
  std::vector<std::string> warnings_;
  bool filtered_ = false;
  std::vector<std::uint8_t> scratch_;
  /// A private copy's directory, removed with the reader (empty when the file is read in place).
  std::filesystem::path temp_dir_;
};

}  // namespace mcvio::bag
