#include "mcap_summary.hpp"

#include <cstring>

#include "byte_io.hpp"

namespace mcvio::bag::detail {

void writeMcapRecord(FileOutput& out, std::uint8_t opcode,
                     const std::vector<std::uint8_t>& content) {
  std::uint8_t prefix[mcap::kRecordPrefix];
  prefix[0] = opcode;
  const std::uint64_t len = content.size();
  std::memcpy(prefix + 1, &len, 8);
  out.write(prefix, sizeof(prefix));
  out.write(content.data(), content.size());
}

std::vector<std::uint8_t> mcapSchemaContent(const mcap::Schema& s) {
  std::vector<std::uint8_t> c;
  c.reserve(14 + s.name.size() + s.encoding.size() + s.data.size());
  ByteWriter w(c);
  w.u16(s.id);
  w.str(s.name);
  w.str(s.encoding);
  w.str(s.data);
  return c;
}

std::vector<std::uint8_t> mcapChannelContent(const mcap::Channel& ch) {
  std::vector<std::uint8_t> c;
  c.reserve(256);
  ByteWriter w(c);
  w.u16(ch.id);
  w.u16(ch.schema_id);
  w.str(ch.topic);
  w.str(ch.message_encoding);
  w.stringMap(ch.metadata);
  return c;
}

std::vector<std::uint8_t> mcapMessageIndexContent(
    std::uint16_t channel_id, const std::vector<std::pair<std::uint64_t, std::uint64_t>>& entries) {
  std::vector<std::uint8_t> c;
  c.reserve(6 + entries.size() * 16);
  ByteWriter w(c);
  w.u16(channel_id);
  w.u32(static_cast<std::uint32_t>(entries.size() * 16));
  for (const auto& [t, off] : entries) {
    w.u64(t);
    w.u64(off);
  }
  return c;
}

mcap::MetadataIndex writeMcapMetadata(FileOutput& out, const std::string& name,
                                      const std::map<std::string, std::string>& entries) {
  std::vector<std::uint8_t> c;
  ByteWriter w(c);
  w.str(name);
  w.stringMap(entries);
  mcap::MetadataIndex loc;
  loc.offset = out.position();
  writeMcapRecord(out, mcap::kMetadata, c);
  loc.length = out.position() - loc.offset;
  loc.name = name;
  return loc;
}

void writeMcapTail(FileOutput& out, const std::vector<mcap::Schema>& schemas,
                   const std::vector<mcap::Channel>& channels,
                   const std::vector<mcap::ChunkInfo>& chunks, const McapStatistics& stats,
                   bool crcs, const std::vector<mcap::MetadataIndex>& metadata) {
  {
    std::vector<std::uint8_t> data_end;
    ByteWriter(data_end).u32(crcs ? out.crc() : 0);
    writeMcapRecord(out, mcap::kDataEnd, data_end);
  }
  out.resetCrc();
  const std::uint64_t summary_start = out.position();
  struct Group {
    std::uint8_t opcode;
    std::uint64_t start;
    std::uint64_t length;
  };
  std::vector<Group> groups;
  auto group = [&](std::uint8_t opcode, auto&& body) {
    const std::uint64_t start = out.position();
    body();
    if (out.position() > start) groups.push_back({opcode, start, out.position() - start});
  };
  group(mcap::kSchema, [&] {
    for (const auto& s : schemas) writeMcapRecord(out, mcap::kSchema, mcapSchemaContent(s));
  });
  group(mcap::kChannel, [&] {
    for (const auto& c : channels) writeMcapRecord(out, mcap::kChannel, mcapChannelContent(c));
  });
  group(mcap::kStatistics, [&] {
    std::vector<std::uint8_t> c;
    ByteWriter w(c);
    w.u64(stats.message_count);
    w.u16(static_cast<std::uint16_t>(schemas.size()));
    w.u32(static_cast<std::uint32_t>(channels.size()));
    w.u32(0);  // attachments
    w.u32(static_cast<std::uint32_t>(metadata.size()));
    w.u32(static_cast<std::uint32_t>(chunks.size()));
    w.u64(stats.message_start_time);
    w.u64(stats.message_end_time);
    const std::size_t at = w.size();
    w.u32(0);
    for (const auto& [id, n] : stats.channel_message_counts) {
      w.u16(id);
      w.u64(n);
    }
    w.patchU32(at, static_cast<std::uint32_t>(w.size() - at - 4));
    writeMcapRecord(out, mcap::kStatistics, c);
  });
  group(mcap::kChunkIndex, [&] {
    for (const auto& ci : chunks) {
      std::vector<std::uint8_t> c;
      ByteWriter w(c);
      w.u64(ci.message_start_time);
      w.u64(ci.message_end_time);
      w.u64(ci.start_offset);
      w.u64(ci.length);
      w.u32(static_cast<std::uint32_t>(ci.message_index_offsets.size() * 10));
      for (const auto& [id, off] : ci.message_index_offsets) {
        w.u16(id);
        w.u64(off);
      }
      w.u64(ci.message_index_length);
      w.str(ci.compression);
      w.u64(ci.compressed_size);
      w.u64(ci.uncompressed_size);
      writeMcapRecord(out, mcap::kChunkIndex, c);
    }
  });
  group(mcap::kMetadataIndex, [&] {
    for (const auto& m : metadata) {
      std::vector<std::uint8_t> c;
      ByteWriter w(c);
      w.u64(m.offset);
      w.u64(m.length);
      w.str(m.name);
      writeMcapRecord(out, mcap::kMetadataIndex, c);
    }
  });
  const std::uint64_t summary_offset_start = out.position();
  for (const auto& g : groups) {
    std::vector<std::uint8_t> c;
    ByteWriter w(c);
    w.u8(g.opcode);
    w.u64(g.start);
    w.u64(g.length);
    writeMcapRecord(out, mcap::kSummaryOffset, c);
  }
  std::vector<std::uint8_t> footer;
  ByteWriter fw(footer);
  fw.u8(mcap::kFooter);
  fw.u64(20);
  fw.u64(summary_start);
  fw.u64(summary_offset_start);
  out.write(footer.data(), footer.size());
  const std::uint32_t summary_crc = crcs ? out.crc() : 0;
  out.write(&summary_crc, 4);
  out.write(mcap::kMagic, sizeof(mcap::kMagic));
}

}  // namespace mcvio::bag::detail
