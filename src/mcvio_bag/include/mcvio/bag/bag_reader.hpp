#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mcvio/bag/bag_message.hpp"
#include "mcvio/bag/bag_metadata.hpp"
#include "mcvio/bag/storage_file_reader.hpp"
#include "mcvio/bag/topic_info.hpp"

namespace mcvio::bag {

struct BagReaderOptions {
  /// Only these topics; empty = all.
  std::vector<std::string> topics;
  /// Read the complete chunks of an unfinished MCAP file (a killed recorder) instead of
  /// failing. Default false: such a file is an InputError that says to run reindex.
  bool allow_unfinished = false;
};

/// Reads a rosbag2 bag (directory with metadata.yaml; or a single .mcap / .db3 file) and
/// yields its messages in log-time order across all its files.
class BagReader {
 public:
  /// Opens and indexes every storage file. InputError for a missing metadata.yaml, unknown
  /// storage, missing or corrupt files (the message names the file and byte offset).
  explicit BagReader(const std::filesystem::path& bag, BagReaderOptions options = {});
  ~BagReader();
  /// A bag rather than a data set folder: a .mcap/.db3 file, or a directory holding
  /// metadata.yaml or .mcap/.db3 files (then a missing metadata.yaml is an error that names
  /// `mcvio bag reindex`, not "not a EuRoC folder").
  static bool looksLikeBag(const std::filesystem::path& path);
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  /// metadata.yaml as stored (for a single file: derived from the file).
  const BagMetadata& metadata() const { return metadata_; }
  /// Topics of all files, with message definitions from the storage.
  const std::vector<TopicInfo>& topics() const { return topics_; }
  /// The next message in log-time order; false at the end.
  bool next(BagMessage& out);
  std::optional<BagMessage> next();
  /// Where the message last returned by next() came from, for error messages:
  /// "<storage file>: topic <name>, message at log time <ns> ns".
  std::string where(const BagMessage& m) const;
  /// Counts and time range gathered from the storage files themselves.
  FileStatistics statistics() const;
  /// Disagreements between metadata.yaml and the storage files that do not stop reading
  /// (a topic's type differs from its schema), one line each naming the topic and both types,
  /// and each storage file's own warnings (StorageFileReader::warnings).
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  void openFiles(const std::vector<std::filesystem::path>& files, const BagReaderOptions& o);
  /// The next message of file `i` into heads_[i]; a damaged MCAP file's error says what repairs it.
  bool readHead(std::size_t i);

  std::filesystem::path bag_;
  BagMetadata metadata_;
  std::vector<TopicInfo> topics_;
  std::vector<std::unique_ptr<StorageFileReader>> files_;
  std::vector<std::filesystem::path> paths_;
  std::size_t last_file_ = 0;
  std::vector<BagMessage> heads_;
  std::vector<bool> has_head_;
  std::vector<std::string> warnings_;
};

}  // namespace mcvio::bag
