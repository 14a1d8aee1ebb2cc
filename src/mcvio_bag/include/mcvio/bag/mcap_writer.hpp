#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mcvio/bag/compression.hpp"
#include "mcvio/bag/mcap_records.hpp"
#include "mcvio/bag/storage_file_writer.hpp"

namespace mcvio::bag {

namespace detail {
class FileOutput;
}

/// Options of one MCAP file.
struct McapWriterOptions {
  Compression compression = Compression::Zstd;  ///< Chunk compression.
  int compression_level = 1;  ///< zstd level (1 is fast enough for live recording); lz4 level.
  /// A chunk is compressed and written once its uncompressed records reach this size.
  /// Smaller chunks lose less on a crash; larger ones compress better.
  std::uint64_t chunk_size = 1024 * 1024;
  bool fsync_each_chunk = false;  ///< fsync after each chunk (survives power loss, slower).
  bool compute_crcs = true;       ///< Chunk, data-section and summary CRCs.
};

/// Writes one MCAP file with the `ros2` profile: schemas (`ros2msg`, the full definition text),
/// channels (`cdr`, metadata `offered_qos_profiles` and `topic_type_hash`), compressed chunks
/// each followed by its message indexes, then Data End, a summary (schemas, channels,
/// statistics, chunk indexes), summary offsets and the footer.
///
/// Crash behaviour: each chunk and its message indexes are handed to the kernel as soon as the
/// chunk is full, so a killed process leaves every completed chunk readable by McapRepairer.
class McapWriter : public StorageFileWriter {
 public:
  McapWriter(const std::filesystem::path& path, McapWriterOptions options = {});
  ~McapWriter() override;

  void addTopic(std::size_t topic_index, const TopicInfo& topic) override;
  void write(std::size_t topic_index, Timestamp log_time, Timestamp publish_time,
             std::uint32_t sequence, const std::uint8_t* data, std::size_t size) override;
  /// Ends the current chunk early and writes it out.
  void flush() override;
  std::uint64_t sizeBytes() const override;
  void close() override;

  /// Adds a Metadata record (written at close, indexed in the summary). BagWriter stores
  /// rosbag2's {"serialized_metadata": <metadata.yaml text>} under the name "rosbag2", as
  /// rosbag2's MCAP plugin does, so a lone .mcap file still describes its bag.
  void addMetadata(const std::string& name, const std::map<std::string, std::string>& entries);

  /// The library string written in the Header record.
  static constexpr const char* kLibrary = "mcvio_bag";

 private:
  void writeRecord(std::uint8_t opcode, const std::vector<std::uint8_t>& content);
  /// Writes the current chunk; `tail` (uncompressed chunks only) are record bytes that follow
  /// chunk_ without having been copied into it.
  void flushChunk(const std::uint8_t* tail = nullptr, std::size_t tail_size = 0);

  std::filesystem::path path_;
  McapWriterOptions options_;
  std::unique_ptr<detail::FileOutput> out_;
  std::vector<mcap::Schema> schemas_;
  std::vector<mcap::Channel> channels_;  ///< Index = topic_index; channel id = index + 1.
  std::vector<mcap::ChunkInfo> chunk_indexes_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0;
  std::uint64_t start_time_ = 0;
  std::uint64_t end_time_ = 0;
  // Current chunk.
  std::vector<std::uint8_t> chunk_;
  std::vector<std::uint8_t> compressed_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::uint64_t chunk_start_time_ = 0;
  std::uint64_t chunk_end_time_ = 0;
  std::vector<std::pair<std::string, std::map<std::string, std::string>>> metadata_;
  bool closed_ = false;
};

}  // namespace mcvio::bag
