#include "mcvio/bag/mcap_repairer.hpp"

#include <algorithm>
#include <set>

#include "file_output.hpp"
#include "mcap_summary.hpp"
#include "mcvio/bag/crc32.hpp"
#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

McapRepairReport McapRepairer::repair(const std::filesystem::path& path) {
  McapRepairReport report;
  try {
    McapReader intact(path, McapReadMode::Strict);
    report.was_complete = true;
    report.kept_bytes = intact.fileSize();
    report.chunks = intact.chunks().size();
    report.messages = intact.statistics().message_count;
    return report;
  } catch (const InputError&) {
    // Not intact: recover below.
  }
  std::vector<mcap::Schema> schemas;
  std::vector<mcap::Channel> channels;
  std::vector<mcap::ChunkInfo> chunks;
  std::vector<mcap::MetadataIndex> metadata;
  detail::McapStatistics stats;
  std::uint64_t valid_end = 0;
  std::uint32_t crc = 0;
  bool append_last_index = false;
  {
    McapReader r(path, McapReadMode::Recover);
    valid_end = r.validEnd();
    report.dropped_bytes = r.fileSize() - valid_end;
    crc = Crc32::update(0, r.data(), valid_end);
    schemas = r.schemas();
    channels = r.channels();
    chunks = r.chunks();
    metadata = r.metadataRecords();
    const auto& complete = r.chunkIndexComplete();
    for (std::size_t i = 0; i < chunks.size(); ++i) {
      if (complete[i]) continue;
      const auto& c = chunks[i];
      const bool is_last = i + 1 == chunks.size();
      // Indexes may be appended only directly after the chunk and its indexes so far.
      if (is_last && valid_end == c.start_offset + c.length + c.message_index_length) {
        append_last_index = true;
      } else {
        chunks[i].message_index_offsets.clear();  // readers scan the chunk instead
        chunks[i].message_index_length = 0;
      }
    }
    const FileStatistics s = r.statistics();
    stats.message_count = s.message_count;
    stats.message_start_time = static_cast<std::uint64_t>(s.start_time);
    stats.message_end_time = static_cast<std::uint64_t>(s.end_time);
    for (const auto& c : chunks) {
      for (const auto& [ch, entries] : c.message_index)
        stats.channel_message_counts[ch] += entries.size();
    }
    report.messages = s.message_count;
    if (r.unchunkedMessages() > 0) {
      // Messages outside chunks are counted per channel from the reader's topics.
      stats.channel_message_counts.clear();
    }
  }  // unmap before rewriting the file
  detail::FileOutput out(path, valid_end, crc);
  if (append_last_index) {
    auto& last = chunks.back();
    for (const auto& [ch, entries] : last.message_index) {
      if (last.message_index_offsets.count(ch)) continue;
      last.message_index_offsets[ch] = out.position();
      detail::writeMcapRecord(out, mcap::kMessageIndex,
                              detail::mcapMessageIndexContent(ch, entries));
    }
    last.message_index_length = out.position() - (last.start_offset + last.length);
  }
  report.kept_bytes = valid_end;
  report.chunks = chunks.size();
  detail::writeMcapTail(out, schemas, channels, chunks, stats, true, metadata);
  out.sync();
  out.close();
  // Prove the result reads back strictly.
  McapReader check(path, McapReadMode::Strict);
  return report;
}

}  // namespace mcvio::bag
