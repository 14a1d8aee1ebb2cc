#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "mcvio/bag/mcap_records.hpp"
#include "mcvio/bag/storage_file_reader.hpp"

namespace mcvio::bag {

/// How McapReader treats a file that does not end with a footer.
enum class McapReadMode {
  /// The file must be complete: magic, records, footer, magic. Uses the summary (chunk and
  /// message indexes) when present, a linear scan otherwise. Anything else is an InputError.
  Strict,
  /// Linear scan that keeps every complete, CRC-clean record. A truncated or corrupt record is
  /// skipped up to the next record that proves intact (a Chunk that decompresses with its CRC,
  /// Metadata, Data End); damage() lists what was skipped. Schemas and channels also come from
  /// an intact summary, so a damaged Schema or Channel record loses no messages.
  Recover,
};

/// A stretch of an MCAP file that McapReadMode::Recover could not use.
struct McapDamage {
  std::uint64_t offset = 0;         ///< File offset of the first skipped byte.
  std::uint64_t size = 0;           ///< Bytes skipped.
  std::int64_t messages_lost = -1;  ///< From a damaged chunk's Message Index records; -1: unknown.
  /// A record cut by the end of the file with nothing usable after it (a killed writer).
  bool unfinished_tail = false;
  std::string reason;
};

/// What the first and last bytes of a file say about it (McapReader::layoutOf).
enum class McapLayout {
  NotMcap,     ///< No MCAP magic and Header record at the start: nothing to recover.
  Unfinished,  ///< Starts as MCAP but has no Footer and trailing magic (a killed writer).
  Finished,    ///< Starts and ends as MCAP (its inside may still be damaged).
};

/// Reads one MCAP file written with the ros2 profile (by mcvio or by rosbag2).
class McapReader : public StorageFileReader {
 public:
  /// Maps and indexes the file. InputError on bad magic, truncation, bad CRCs, malformed
  /// records or a ros2msg schema that does not parse, naming the file and byte offset.
  explicit McapReader(const std::filesystem::path& path, McapReadMode mode = McapReadMode::Strict);
  /// Reads from memory (tests, fuzzing); `name` stands for the file in messages.
  McapReader(std::vector<std::uint8_t> bytes, std::string name,
             McapReadMode mode = McapReadMode::Strict);
  ~McapReader() override;

  const std::vector<TopicInfo>& topics() const override { return topics_; }
  void setTopicFilter(const std::set<std::string>& topics) override;
  bool next(BagMessage& out) override;
  FileStatistics statistics() const override;
  /// Every chunk in file order: decompressed, CRC checked, each message its index lists read
  /// as next() would (a damaged chunk counts all of its indexed messages, per topic), records
  /// the indexes miss; messages outside chunks; the data section CRC of Data End when the
  /// file was loaded through its summary (a linear scan has checked it already).
  void verify(VerifySink& sink) override;
  /// Reads only the head and tail of `path`. NotMcap also for a file that cannot be read.
  static McapLayout layoutOf(const std::filesystem::path& path);

  /// True when the index came from the summary section, false after a linear scan.
  bool usedSummary() const { return used_summary_; }
  /// Recover mode: offset just past the last complete record that was kept.
  std::uint64_t validEnd() const { return valid_end_; }
  /// Recover mode: the skipped stretches in file order (holes before validEnd(), then the tail).
  const std::vector<McapDamage>& damage() const { return damage_; }
  /// Decompresses every chunk, checks its CRC and that its records agree with the message
  /// indexes (a summary-based load reads chunks only on demand). InputError on the first bad one.
  void verifyChunks() const;
  /// Recover mode: a Data End record was found (at validEnd()).
  bool dataEndFound() const { return data_end_found_; }
  /// Chunks with their message index entries (recomputed from the data on a linear scan).
  const std::vector<mcap::ChunkInfo>& chunks() const { return chunks_; }
  /// For each chunk: were all its Message Index records present in the file after it?
  const std::vector<bool>& chunkIndexComplete() const { return chunk_index_complete_; }
  const std::vector<mcap::Schema>& schemas() const { return schemas_; }
  /// Metadata records met by a linear scan (name and place).
  const std::vector<mcap::MetadataIndex>& metadataRecords() const { return metadata_; }
  const std::vector<mcap::Channel>& channels() const { return channels_; }
  /// Number of messages stored outside chunks.
  std::uint64_t unchunkedMessages() const;
  std::uint64_t fileSize() const { return size_; }
  const std::uint8_t* data() const { return data_; }

 private:
  struct Entry {
    std::uint64_t log_time;
    std::uint32_t chunk;  // kNoChunk for messages outside chunks
    std::uint16_t channel;
    std::uint64_t offset;  // in the uncompressed chunk, or in the file
  };
  static constexpr std::uint32_t kNoChunk = 0xFFFFFFFFu;

  /// The Footer record's fields (the caller has checked that the file ends in one).
  struct Footer {
    std::uint64_t pos = 0, summary_start = 0, summary_offset_start = 0;
    std::uint32_t summary_crc = 0;
  };
  Footer footer() const;
  void load(McapReadMode mode);
  void loadSummary(std::uint64_t footer_pos, std::uint64_t summary_start,
                   std::uint64_t summary_offset_start, std::uint32_t summary_crc);
  void linearScan(McapReadMode mode, std::uint64_t limit);
  void scanChunkRecords(std::uint32_t chunk_no, const std::vector<std::uint8_t>& records,
                        bool collect_definitions);
  void parseChunkRecord(std::uint64_t pos, mcap::ChunkInfo& info) const;
  void decompressChunk(std::uint32_t chunk_no, std::vector<std::uint8_t>& out) const;
  void decompress(const mcap::ChunkInfo& c, std::vector<std::uint8_t>& out) const;
  void acceptChunk(std::uint64_t pos, std::uint64_t len, bool strict,
                   std::vector<std::uint8_t>& records);
  void preloadSummaryDefinitions();
  std::uint64_t resync(std::uint64_t from, std::uint64_t limit) const;
  std::int64_t messagesIndexedAfter(std::uint64_t pos, std::uint64_t limit) const;
  bool channelDeclared(std::uint16_t id) const;
  void addSchema(std::uint64_t pos, const std::uint8_t* p, std::uint64_t len);
  void addChannel(std::uint64_t pos, const std::uint8_t* p, std::uint64_t len);
  void finishTopics();
  /// Why `rec` (`avail` bytes to the end of its chunk or file) is no readable Message record
  /// on `channel`; nullptr when it is one.
  static const char* messageRecordProblem(const std::uint8_t* rec, std::uint64_t avail,
                                          std::uint16_t channel);
  /// Lets the kernel drop the mapped pages of [from, to) (verify() reads a file once).
  void releasePages(std::uint64_t from, std::uint64_t to) const;
  [[noreturn]] void fail(std::uint64_t offset, const std::string& what) const;

  std::string name_;
  std::vector<std::uint8_t> owned_;
  void* map_ = nullptr;
  const std::uint8_t* data_ = nullptr;
  std::uint64_t size_ = 0;

  std::vector<mcap::Schema> schemas_;
  std::vector<mcap::Channel> channels_;
  std::vector<mcap::ChunkInfo> chunks_;
  std::vector<mcap::MetadataIndex> metadata_;
  std::vector<bool> chunk_index_complete_;
  std::vector<McapDamage> damage_;
  std::vector<Entry> entries_;
  std::vector<TopicInfo> topics_;
  std::vector<int> channel_topic_;  // channel id -> index in topics_, -1 if none
  std::vector<bool> channel_selected_;
  bool used_summary_ = false;
  bool data_end_found_ = false;
  std::uint64_t valid_end_ = 0;
  std::size_t cursor_ = 0;
  std::uint32_t cached_chunk_ = kNoChunk;
  std::vector<std::uint8_t> chunk_cache_;
};

}  // namespace mcvio::bag
