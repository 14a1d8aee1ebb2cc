#include "mcvio/bag/mcap_writer.hpp"

#include <algorithm>

#include "byte_io.hpp"
#include "file_output.hpp"
#include "mcap_summary.hpp"
#include "mcvio/bag/crc32.hpp"

namespace mcvio::bag {

using detail::ByteWriter;

McapWriter::McapWriter(const std::filesystem::path& path, McapWriterOptions options)
    : path_(path), options_(options), out_(std::make_unique<detail::FileOutput>(path)) {
  out_->setCrcEnabled(options_.compute_crcs);
  out_->write(mcap::kMagic, sizeof(mcap::kMagic));
  std::vector<std::uint8_t> header;
  ByteWriter w(header);
  w.str("ros2");
  w.str(kLibrary);
  writeRecord(mcap::kHeader, header);
  out_->flush();
  chunk_.reserve(options_.chunk_size + 1024);
}

McapWriter::~McapWriter() {
  try {
    close();
  } catch (...) {
    // Destructors must not throw; call close() to see errors.
  }
}

void McapWriter::writeRecord(std::uint8_t opcode, const std::vector<std::uint8_t>& content) {
  detail::writeMcapRecord(*out_, opcode, content);
}

void McapWriter::addTopic(std::size_t topic_index, const TopicInfo& topic) {
  if (closed_) throw std::logic_error("McapWriter::addTopic after close: " + path_.string());
  if (topic_index != channels_.size() || topic_index >= 0xFFFF) {
    throw std::logic_error("McapWriter: topics must be added in order, fewer than 65535");
  }
  std::uint16_t schema_id = 0;
  for (const auto& s : schemas_) {
    if (s.name == topic.type && s.data == topic.message_definition) schema_id = s.id;
  }
  if (schema_id == 0) {
    mcap::Schema s;
    s.id = static_cast<std::uint16_t>(schemas_.size() + 1);
    s.name = topic.type;
    s.encoding = "ros2msg";
    s.data = topic.message_definition;
    writeRecord(mcap::kSchema, detail::mcapSchemaContent(s));
    schemas_.push_back(s);
    schema_id = s.id;
  }
  mcap::Channel ch;
  ch.id = static_cast<std::uint16_t>(topic_index + 1);
  ch.schema_id = schema_id;
  ch.topic = topic.name;
  ch.message_encoding = topic.serialization_format;
  ch.metadata["offered_qos_profiles"] = topic.offered_qos_profiles;
  if (!topic.type_description_hash.empty()) {
    ch.metadata["topic_type_hash"] = topic.type_description_hash;
  }
  writeRecord(mcap::kChannel, detail::mcapChannelContent(ch));
  channels_.push_back(ch);
}

void McapWriter::write(std::size_t topic_index, Timestamp log_time, Timestamp publish_time,
                       std::uint32_t sequence, const std::uint8_t* data, std::size_t size) {
  if (closed_) throw std::logic_error("McapWriter::write after close: " + path_.string());
  if (topic_index >= channels_.size()) throw std::logic_error("McapWriter: unknown topic index");
  const auto channel_id = static_cast<std::uint16_t>(topic_index + 1);
  const auto log = static_cast<std::uint64_t>(log_time);
  const auto pub = static_cast<std::uint64_t>(publish_time);
  const std::uint64_t offset = chunk_.size();
  ByteWriter w(chunk_);
  w.u8(mcap::kMessage);
  w.u64(2 + 4 + 8 + 8 + size);
  w.u16(channel_id);
  w.u32(sequence);
  w.u64(log);
  w.u64(pub);
  // A big uncompressed message that fills a chunk on its own goes from the caller's buffer
  // to the file without being copied into the chunk.
  const bool direct = options_.compression == Compression::None && offset == 0 &&
                      chunk_.size() + size >= options_.chunk_size;
  if (!direct) w.raw(data, size);
  chunk_index_[channel_id].emplace_back(log, offset);
  if (offset == 0) {
    chunk_start_time_ = chunk_end_time_ = log;
  } else {
    chunk_start_time_ = std::min(chunk_start_time_, log);
    chunk_end_time_ = std::max(chunk_end_time_, log);
  }
  if (message_count_ == 0) {
    start_time_ = end_time_ = log;
  } else {
    start_time_ = std::min(start_time_, log);
    end_time_ = std::max(end_time_, log);
  }
  ++message_count_;
  ++channel_counts_[channel_id];
  if (direct) {
    flushChunk(data, size);
  } else if (chunk_.size() >= options_.chunk_size) {
    flushChunk();
  }
}

void McapWriter::flush() {
  if (closed_) return;
  flushChunk();
}

std::uint64_t McapWriter::sizeBytes() const { return out_->position() + chunk_.size(); }

void McapWriter::flushChunk(const std::uint8_t* tail, std::size_t tail_size) {
  if (chunk_.empty()) return;
  const bool crcs = options_.compute_crcs;
  const std::uint32_t head_crc = crcs ? Crc32::update(0, chunk_.data(), chunk_.size()) : 0;
  const std::uint32_t tail_crc = crcs && tail_size > 0 ? Crc32::update(0, tail, tail_size) : 0;
  const std::uint32_t crc = !crcs           ? 0
                            : tail_size > 0 ? Crc32::combine(head_crc, tail_crc, tail_size)
                                            : head_crc;
  const std::vector<std::uint8_t>* records = &chunk_;
  if (options_.compression != Compression::None) {
    compressed_.clear();
    Codec::compress(options_.compression, chunk_.data(), chunk_.size(), options_.compression_level,
                    compressed_);
    records = &compressed_;
  }
  mcap::ChunkInfo info;
  info.start_offset = out_->position();
  info.message_start_time = chunk_start_time_;
  info.message_end_time = chunk_end_time_;
  info.uncompressed_size = chunk_.size() + tail_size;
  info.uncompressed_crc = crc;
  info.compression = mcapCompressionName(options_.compression);
  info.compressed_size = records->size() + tail_size;

  std::vector<std::uint8_t> head;
  ByteWriter w(head);
  w.u8(mcap::kChunk);
  w.u64(8 + 8 + 8 + 4 + 4 + info.compression.size() + 8 + info.compressed_size);
  w.u64(info.message_start_time);
  w.u64(info.message_end_time);
  w.u64(info.uncompressed_size);
  w.u32(info.uncompressed_crc);
  w.str(info.compression);
  w.u64(info.compressed_size);
  out_->write(head.data(), head.size());
  if (crcs && records == &chunk_) {
    out_->writeWithCrc(records->data(), records->size(), head_crc);
  } else {
    out_->write(records->data(), records->size());
  }
  if (tail_size > 0) out_->writeWithCrc(tail, tail_size, tail_crc);
  info.records_offset = info.start_offset + head.size();
  info.length = out_->position() - info.start_offset;

  const std::uint64_t index_start = out_->position();
  for (const auto& [channel_id, entries] : chunk_index_) {
    info.message_index_offsets[channel_id] = out_->position();
    writeRecord(mcap::kMessageIndex, detail::mcapMessageIndexContent(channel_id, entries));
  }
  info.message_index_length = out_->position() - index_start;
  chunk_indexes_.push_back(std::move(info));
  // Persist the finished chunk now: a killed recorder keeps it.
  if (options_.fsync_each_chunk) {
    out_->sync();
  } else {
    out_->flush();
  }
  chunk_.clear();
  chunk_index_.clear();
}

void McapWriter::addMetadata(const std::string& name,
                             const std::map<std::string, std::string>& entries) {
  if (closed_) throw std::logic_error("McapWriter::addMetadata after close: " + path_.string());
  metadata_.emplace_back(name, entries);
}

void McapWriter::close() {
  if (closed_) return;
  closed_ = true;
  flushChunk();
  detail::McapStatistics stats;
  stats.message_count = message_count_;
  stats.message_start_time = start_time_;
  stats.message_end_time = end_time_;
  stats.channel_message_counts = channel_counts_;
  std::vector<mcap::MetadataIndex> locations;
  for (const auto& [name, entries] : metadata_) {
    locations.push_back(detail::writeMcapMetadata(*out_, name, entries));
  }
  detail::writeMcapTail(*out_, schemas_, channels_, chunk_indexes_, stats, options_.compute_crcs,
                        locations);
  if (options_.fsync_each_chunk) out_->sync();
  out_->close();
}

}  // namespace mcvio::bag
