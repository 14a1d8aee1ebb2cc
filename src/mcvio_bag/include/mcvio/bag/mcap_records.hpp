#pragma once
// MCAP (https://mcap.dev/spec) record contents that mcvio_bag writes and reads.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace mcvio::bag::mcap {

/// 0x89 'M' 'C' 'A' 'P' '0' '\r' '\n': starts and ends every MCAP file.
inline constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};

/// Record opcodes of MCAP major version 0.
enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// Opcode byte + uint64 content length.
inline constexpr std::uint64_t kRecordPrefix = 9;
/// Footer record (prefix + 8 + 8 + 4) followed by the trailing magic.
inline constexpr std::uint64_t kFooterAndMagic = kRecordPrefix + 20 + 8;

struct Schema {
  std::uint16_t id = 0;
  std::string name;
  std::string encoding;
  std::string data;
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;
  std::map<std::string, std::string> metadata;
};

/// A Metadata record's place in the file (the content of a Metadata Index record).
struct MetadataIndex {
  std::uint64_t offset = 0;
  std::uint64_t length = 0;
  std::string name;
};

/// Where one chunk sits and what it holds: the content of a Chunk Index record plus the
/// message index entries (log_time, offset into the uncompressed records) per channel.
struct ChunkInfo {
  std::uint64_t start_offset = 0;    ///< File offset of the Chunk record's opcode.
  std::uint64_t length = 0;          ///< Whole Chunk record, prefix included.
  std::uint64_t records_offset = 0;  ///< File offset of the (compressed) records bytes.
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::uint64_t compressed_size = 0;
  std::uint64_t uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string compression;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> message_index;
  std::map<std::uint16_t, std::uint64_t> message_index_offsets;  ///< File offsets, per channel.
  std::uint64_t message_index_length = 0;
};

}  // namespace mcvio::bag::mcap
