#pragma once
// Writes an MCAP file's tail: Data End, summary, summary offsets, footer, magic (internal).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "file_output.hpp"
#include "mcvio/bag/mcap_records.hpp"

namespace mcvio::bag::detail {

struct McapStatistics {
  std::uint64_t message_count = 0;
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

void writeMcapRecord(FileOutput& out, std::uint8_t opcode,
                     const std::vector<std::uint8_t>& content);
std::vector<std::uint8_t> mcapSchemaContent(const mcap::Schema& s);
std::vector<std::uint8_t> mcapChannelContent(const mcap::Channel& c);
std::vector<std::uint8_t> mcapMessageIndexContent(
    std::uint16_t channel_id, const std::vector<std::pair<std::uint64_t, std::uint64_t>>& entries);

/// Writes a Metadata record (name + string map) and returns where it went.
mcap::MetadataIndex writeMcapMetadata(FileOutput& out, const std::string& name,
                                      const std::map<std::string, std::string>& entries);

/// Appends Data End (with the CRC `out` has accumulated, if `crcs`), the summary section
/// (schemas, channels, statistics, chunk indexes), summary offsets, footer and magic.
void writeMcapTail(FileOutput& out, const std::vector<mcap::Schema>& schemas,
                   const std::vector<mcap::Channel>& channels,
                   const std::vector<mcap::ChunkInfo>& chunks, const McapStatistics& stats,
                   bool crcs, const std::vector<mcap::MetadataIndex>& metadata = {});

}  // namespace mcvio::bag::detail
