#include "mcvio/bag/mcap_repairer.hpp"

#include <algorithm>
#include <set>

#include "file_output.hpp"
#include "mcap_summary.hpp"
#include "mcvio/bag/crc32.hpp"
#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

bool McapRepairReport::damaged() const {
  return std::any_of(damage.begin(), damage.end(),
                     [](const McapDamage& d) { return !d.unfinished_tail; });
}

namespace {

/// `<file>.orig`, or `.orig.N` if taken: a free name for the untouched original.
std::filesystem::path originalName(const std::filesystem::path& path) {
  std::filesystem::path p = path.string() + ".orig";
  for (int i = 1; std::filesystem::exists(p); ++i) p = path.string() + ".orig." + std::to_string(i);
  return p;
}

/// Writes the Message Index records the last chunk lacks, right after it.
void appendMissingIndexes(detail::FileOutput& out, mcap::ChunkInfo& last) {
  for (const auto& [ch, entries] : last.message_index) {
    if (last.message_index_offsets.count(ch)) continue;
    last.message_index_offsets[ch] = out.position();
    detail::writeMcapRecord(out, mcap::kMessageIndex, detail::mcapMessageIndexContent(ch, entries));
  }
  last.message_index_length = out.position() - (last.start_offset + last.length);
}

}  // namespace

McapRepairReport McapRepairer::repair(const std::filesystem::path& path) {
  McapRepairReport report;
  try {
    McapReader intact(path, McapReadMode::Strict);
    intact.verifyChunks();  // a valid summary says nothing about the chunks' CRCs
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
  const std::filesystem::path tmp = path.string() + ".reindex-tmp";
  {
    McapReader r(path, McapReadMode::Recover);
    valid_end = r.validEnd();
    report.damage = r.damage();
    report.dropped_bytes = r.fileSize() - valid_end;
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
    if (report.damaged()) {
      // Damage inside the data: build the repaired file beside the original from the kept stretches
      // (everything before validEnd() but the holes) and move offsets accordingly.
      struct Kept {
        std::uint64_t begin, end, new_begin;
      };
      std::vector<Kept> kept;
      std::uint64_t at = 0;
      std::uint64_t new_at = 0;
      for (const auto& d : report.damage) {
        if (d.offset >= valid_end) break;
        kept.push_back({at, d.offset, new_at});
        new_at += d.offset - at;
        report.dropped_bytes += d.size;
        at = d.offset + d.size;
      }
      kept.push_back({at, valid_end, new_at});
      auto moved = [&](std::uint64_t old) {
        for (const auto& k : kept) {
          if (old >= k.begin && old < k.end) return old - k.begin + k.new_begin;
        }
        throw InputError(path.string() + ": internal error: kept record outside the kept data");
      };
      for (auto& c : chunks) {
        c.start_offset = moved(c.start_offset);
        c.records_offset = moved(c.records_offset);
        for (auto& [ch, off] : c.message_index_offsets) off = moved(off);
      }
      for (auto& m : metadata) m.offset = moved(m.offset);
      std::filesystem::remove(tmp);
      detail::FileOutput out(tmp);
      for (const auto& k : kept) out.write(r.data() + k.begin, k.end - k.begin);
      if (append_last_index) appendMissingIndexes(out, chunks.back());
      report.kept_bytes = new_at + (valid_end - at);
      report.chunks = chunks.size();
      detail::writeMcapTail(out, schemas, channels, chunks, stats, true, metadata);
      out.sync();
      out.close();
    } else {
      crc = Crc32::update(0, r.data(), valid_end);
    }
  }  // unmap before rewriting or renaming the file
  if (report.damaged()) {
    try {
      McapReader check(tmp, McapReadMode::Strict);  // prove the result reads back strictly
      check.verifyChunks();
    } catch (...) {
      std::filesystem::remove(tmp);
      throw;
    }
    report.original = originalName(path);
    std::filesystem::rename(path, report.original);
    std::filesystem::rename(tmp, path);
    return report;
  }
  // Nothing readable is dropped (at most an old summary, or the unfinished record a killed
  // recorder left at the end): finish the file in place, without a copy of a large bag.
  detail::FileOutput out(path, valid_end, crc);
  if (append_last_index) appendMissingIndexes(out, chunks.back());
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
