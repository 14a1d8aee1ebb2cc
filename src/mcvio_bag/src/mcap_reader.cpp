#include "mcvio/bag/mcap_reader.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <set>
#include <sstream>

#include "byte_io.hpp"
#include "mcvio/bag/compression.hpp"
#include "mcvio/bag/crc32.hpp"
#include "mcvio/bag/message_definition.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

using detail::ByteReader;
using detail::ShortRead;

namespace {

std::uint64_t readU64(const std::uint8_t* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  return v;
}

/// Largest chunk we agree to decompress; protects against forged sizes.
constexpr std::uint64_t kMaxChunkSize = 4ull << 30;

/// Why the first `size` bytes of a file are no MCAP start (the magic, then a Header record
/// that parses); `at` is where. Empty when they are one.
std::string headerProblem(const std::uint8_t* data, std::uint64_t size, std::uint64_t& at) {
  at = 0;
  if (size < sizeof(mcap::kMagic) || std::memcmp(data, mcap::kMagic, sizeof(mcap::kMagic)) != 0) {
    return "not an MCAP file (wrong magic)";
  }
  at = 8;
  if (size < 8 + mcap::kRecordPrefix || data[8] != mcap::kHeader) return "missing Header record";
  const std::uint64_t len = readU64(data + 9);
  if (len > size - 17) return "truncated Header record";
  try {
    ByteReader r(data + 17, len);
    r.str("profile");
    r.str("library");
  } catch (const ShortRead& e) {
    at = 17 + e.offset;
    return std::string("malformed Header record: ") + e.what();
  }
  return {};
}

/// `tail`: the last kFooterAndMagic bytes of a file of `size` bytes. True when they are a
/// Footer record and the trailing magic.
bool endsWithFooter(const std::uint8_t* tail, std::uint64_t size) {
  return size >= 8 + mcap::kRecordPrefix + mcap::kFooterAndMagic &&
         std::memcmp(tail + mcap::kFooterAndMagic - 8, mcap::kMagic, 8) == 0 &&
         tail[0] == mcap::kFooter && readU64(tail + 1) == 20;
}

/// Walks the records of a decompressed Chunk, calling on_record(offset, opcode, body length) for
/// each. nullptr when they end exactly at its end; otherwise why not, with `at` the offset of the
/// record that does not fit.
template <class OnRecord>
const char* walkChunkRecords(const std::vector<std::uint8_t>& records, std::uint64_t& at,
                             OnRecord on_record) {
  for (at = 0; at < records.size();) {
    if (records.size() - at < mcap::kRecordPrefix) return "truncated record inside Chunk";
    const std::uint64_t len = readU64(records.data() + at + 1);
    if (len > records.size() - at - mcap::kRecordPrefix) return "record inside Chunk runs past the Chunk";
    on_record(at, records[at], len);
    at += mcap::kRecordPrefix + len;
  }
  return nullptr;
}

/// Reads `n` bytes at `offset`; false when the file has fewer.
bool readAt(int fd, std::uint64_t offset, std::uint8_t* out, std::uint64_t n) {
  while (n > 0) {
    const ssize_t got = ::pread(fd, out, n, static_cast<off_t>(offset));
    if (got <= 0) return false;
    out += got;
    offset += static_cast<std::uint64_t>(got);
    n -= static_cast<std::uint64_t>(got);
  }
  return true;
}

}  // namespace

McapReader::McapReader(const std::filesystem::path& path, McapReadMode mode)
    : name_(path.string()) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(name_ + ": cannot open (" + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw InputError(name_ + ": not a regular file");
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
  if (size_ > 0) {
    map_ = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (map_ == MAP_FAILED) {
      map_ = nullptr;
      ::close(fd);
      throw InputError(name_ + ": cannot map (" + std::strerror(errno) + ")");
    }
    data_ = static_cast<const std::uint8_t*>(map_);
  }
  ::close(fd);
  try {
    load(mode);
  } catch (...) {
    if (map_ != nullptr) ::munmap(map_, size_);
    map_ = nullptr;
    throw;
  }
}

McapReader::McapReader(std::vector<std::uint8_t> bytes, std::string name, McapReadMode mode)
    : name_(std::move(name)), owned_(std::move(bytes)) {
  data_ = owned_.data();
  size_ = owned_.size();
  load(mode);
}

McapReader::~McapReader() {
  if (map_ != nullptr) ::munmap(map_, size_);
}

void McapReader::fail(std::uint64_t offset, const std::string& what) const {
  std::ostringstream os;
  os << name_ << ": " << what << " at byte offset " << offset;
  throw InputError(os.str());
}

void McapReader::load(McapReadMode mode) {
  std::uint64_t at = 0;
  if (const std::string why = headerProblem(data_, size_, at); !why.empty()) fail(at, why);
  const bool has_footer = size_ >= mcap::kFooterAndMagic &&
                          endsWithFooter(data_ + size_ - mcap::kFooterAndMagic, size_);
  if (mode == McapReadMode::Recover) {
    if (has_footer) preloadSummaryDefinitions();
    linearScan(mode, size_);
  } else {
    if (!has_footer) {
      fail(size_,
           "truncated or unfinished MCAP file (no Footer record and trailing magic; "
           "`mcvio bag reindex` recovers its complete chunks)");
    }
    const Footer f = footer();
    if (f.summary_start != 0) {
      loadSummary(f.pos, f.summary_start, f.summary_offset_start, f.summary_crc);
    } else {
      linearScan(mode, f.pos);
    }
  }
  finishTopics();
}

void McapReader::addSchema(std::uint64_t pos, const std::uint8_t* p, std::uint64_t len) {
  mcap::Schema s;
  try {
    ByteReader r(p, len);
    s.id = r.u16();
    s.name = r.str("name");
    s.encoding = r.str("encoding");
    s.data = r.str("data");
  } catch (const ShortRead& e) {
    fail(pos, std::string("malformed Schema record: ") + e.what());
  }
  if (s.id == 0) return;  // invalid by the spec; readers ignore it
  for (const auto& old : schemas_) {
    if (old.id == s.id) {
      if (old.name != s.name || old.encoding != s.encoding || old.data != s.data) {
        fail(pos, "Schema record " + std::to_string(s.id) + " differs from an earlier one");
      }
      return;
    }
  }
  if (s.encoding == "ros2msg") {
    try {
      MessageDefinitionParser::parse(s.name, s.data);
    } catch (const InputError& e) {
      fail(pos, std::string("schema does not parse: ") + e.what());
    }
  }
  schemas_.push_back(std::move(s));
}

void McapReader::addChannel(std::uint64_t pos, const std::uint8_t* p, std::uint64_t len) {
  mcap::Channel c;
  try {
    ByteReader r(p, len);
    c.id = r.u16();
    c.schema_id = r.u16();
    c.topic = r.str("topic");
    c.message_encoding = r.str("message_encoding");
    c.metadata = r.stringMap("metadata");
  } catch (const ShortRead& e) {
    fail(pos, std::string("malformed Channel record: ") + e.what());
  }
  for (const auto& old : channels_) {
    if (old.id == c.id) {
      if (old.topic != c.topic || old.schema_id != c.schema_id) {
        fail(pos, "Channel record " + std::to_string(c.id) + " differs from an earlier one");
      }
      return;
    }
  }
  if (c.schema_id != 0 && std::none_of(schemas_.begin(), schemas_.end(),
                                       [&](const auto& s) { return s.id == c.schema_id; })) {
    fail(pos, "Channel " + std::to_string(c.id) + " refers to unknown schema " +
                  std::to_string(c.schema_id));
  }
  channels_.push_back(std::move(c));
}

void McapReader::parseChunkRecord(std::uint64_t pos, mcap::ChunkInfo& info) const {
  if (pos > size_ || size_ - pos < mcap::kRecordPrefix || data_[pos] != mcap::kChunk) {
    fail(pos, "expected a Chunk record");
  }
  const std::uint64_t len = readU64(data_ + pos + 1);
  if (len > size_ - pos - mcap::kRecordPrefix) fail(pos, "truncated Chunk record");
  try {
    ByteReader r(data_ + pos + mcap::kRecordPrefix, len);
    info.start_offset = pos;
    info.length = mcap::kRecordPrefix + len;
    info.message_start_time = r.u64();
    info.message_end_time = r.u64();
    info.uncompressed_size = r.u64();
    info.uncompressed_crc = r.u32();
    info.compression = r.str("compression");
    info.compressed_size = r.u64();
    r.need(info.compressed_size, "records");
    info.records_offset = pos + mcap::kRecordPrefix + r.pos();
  } catch (const ShortRead& e) {
    fail(pos, std::string("malformed Chunk record: ") + e.what());
  }
  if (info.uncompressed_size > kMaxChunkSize) fail(pos, "Chunk uncompressed size is implausible");
  if (info.compression != "" && info.compression != "zstd" && info.compression != "lz4") {
    fail(pos, "Chunk uses unsupported compression '" + info.compression + "'");
  }
}

void McapReader::decompressChunk(std::uint32_t chunk_no, std::vector<std::uint8_t>& out) const {
  decompress(chunks_[chunk_no], out);
}

void McapReader::decompress(const mcap::ChunkInfo& c, std::vector<std::uint8_t>& out) const {
  try {
    Codec::decompress(compressionFromString(c.compression), data_ + c.records_offset,
                      c.compressed_size, c.uncompressed_size, out);
  } catch (const std::exception& e) {
    fail(c.start_offset, std::string("Chunk does not decompress: ") + e.what());
  }
  if (c.uncompressed_crc != 0) {
    const std::uint32_t crc = Crc32::update(0, out.data(), out.size());
    if (crc != c.uncompressed_crc) fail(c.start_offset, "bad CRC of Chunk records");
  }
}

void McapReader::scanChunkRecords(std::uint32_t chunk_no, const std::vector<std::uint8_t>& records,
                                  bool collect_definitions) {
  mcap::ChunkInfo& c = chunks_[chunk_no];
  std::uint64_t p = 0;
  const std::uint64_t n = records.size();
  while (p < n) {
    if (n - p < mcap::kRecordPrefix) fail(c.start_offset, "truncated record inside Chunk");
    const std::uint8_t op = records[p];
    const std::uint64_t len = readU64(records.data() + p + 1);
    if (len > n - p - mcap::kRecordPrefix) {
      fail(c.start_offset, "record inside Chunk (uncompressed offset " + std::to_string(p) +
                               ") runs past the Chunk");
    }
    const std::uint8_t* body = records.data() + p + mcap::kRecordPrefix;
    if (op == mcap::kSchema && collect_definitions) {
      addSchema(c.start_offset, body, len);
    } else if (op == mcap::kChannel && collect_definitions) {
      addChannel(c.start_offset, body, len);
    } else if (op == mcap::kMessage) {
      if (len < 22) fail(c.start_offset, "Message record inside Chunk is too short");
      std::uint16_t ch;
      std::memcpy(&ch, body, 2);
      const std::uint64_t t = readU64(body + 6);
      entries_.push_back({t, chunk_no, ch, p});
      c.message_index[ch].emplace_back(t, p);
    }
    p += mcap::kRecordPrefix + len;
  }
}

bool McapReader::channelDeclared(std::uint16_t id) const {
  return std::any_of(channels_.begin(), channels_.end(), [&](const auto& c) { return c.id == id; });
}

void McapReader::acceptChunk(std::uint64_t pos, std::uint64_t len, bool strict,
                             std::vector<std::uint8_t>& records) {
  mcap::ChunkInfo info;
  parseChunkRecord(pos, info);
  if (!strict && info.records_offset + info.compressed_size != pos + mcap::kRecordPrefix + len) {
    fail(pos, "Chunk record length disagrees with its compressed size");
  }
  chunks_.push_back(info);
  chunk_index_complete_.push_back(false);
  const auto no = static_cast<std::uint32_t>(chunks_.size() - 1);
  const std::size_t entries_before = entries_.size();
  const std::size_t schemas_before = schemas_.size();
  const std::size_t channels_before = channels_.size();
  try {
    decompressChunk(no, records);
    scanChunkRecords(no, records, true);
    if (!strict) {
      // A chunk whose Channel record is lost cannot be read back; drop it as damaged.
      for (const auto& [ch, e] : chunks_.back().message_index) {
        if (!channelDeclared(ch)) {
          fail(pos, "Chunk holds messages on channel " + std::to_string(ch) +
                        " whose Channel record is lost");
        }
      }
    }
  } catch (const InputError&) {
    chunks_.pop_back();
    chunk_index_complete_.pop_back();
    entries_.resize(entries_before);
    schemas_.resize(schemas_before);
    channels_.resize(channels_before);
    throw;
  }
}

McapReader::Footer McapReader::footer() const {
  Footer out;
  out.pos = size_ - mcap::kFooterAndMagic;
  const std::uint8_t* f = data_ + out.pos + mcap::kRecordPrefix;
  out.summary_start = readU64(f);
  out.summary_offset_start = readU64(f + 8);
  std::memcpy(&out.summary_crc, f + 16, 4);
  return out;
}

void McapReader::preloadSummaryDefinitions() {
  // Recover mode: an intact summary holds a copy of every Schema and Channel record.
  const Footer footer_fields = footer();
  const std::uint64_t footer_pos = footer_fields.pos;
  const std::uint64_t start = footer_fields.summary_start;
  const std::uint64_t offsets = footer_fields.summary_offset_start;
  const std::uint32_t crc = footer_fields.summary_crc;
  if (start < 8 + mcap::kRecordPrefix || start > footer_pos) return;
  const std::uint64_t crc_end = footer_pos + mcap::kRecordPrefix + 16;
  if (crc != 0 && Crc32::update(0, data_ + start, crc_end - start) != crc) return;
  const std::uint64_t end = offsets >= start && offsets <= footer_pos && offsets != 0 ? offsets
                                                                                      : footer_pos;
  try {
    for (std::uint64_t pos = start; pos < end;) {
      if (end - pos < mcap::kRecordPrefix) break;
      const std::uint64_t len = readU64(data_ + pos + 1);
      if (len > end - pos - mcap::kRecordPrefix) break;
      const std::uint8_t* body = data_ + pos + mcap::kRecordPrefix;
      if (data_[pos] == mcap::kSchema) addSchema(pos, body, len);
      if (data_[pos] == mcap::kChannel) addChannel(pos, body, len);
      pos += mcap::kRecordPrefix + len;
    }
  } catch (const std::exception&) {
    schemas_.clear();  // not trustworthy: rely on the data section alone
    channels_.clear();
  }
}

std::int64_t McapReader::messagesIndexedAfter(std::uint64_t pos, std::uint64_t limit) const {
  // The Message Index records after a chunk count its messages, even when the chunk is damaged.
  if (limit - pos < mcap::kRecordPrefix || data_[pos] != mcap::kChunk) return -1;
  const std::uint64_t len = readU64(data_ + pos + 1);
  if (len > limit - pos - mcap::kRecordPrefix) return -1;
  std::uint64_t q = pos + mcap::kRecordPrefix + len;
  std::int64_t n = -1;
  while (limit - q >= mcap::kRecordPrefix + 6 && data_[q] == mcap::kMessageIndex) {
    const std::uint64_t l = readU64(data_ + q + 1);
    if (l > limit - q - mcap::kRecordPrefix || l < 6) break;
    std::uint32_t bytes;
    std::memcpy(&bytes, data_ + q + mcap::kRecordPrefix + 2, 4);
    if (bytes % 16 != 0 || 6ull + bytes != l) break;
    n = std::max<std::int64_t>(n, 0) + bytes / 16;
    q += mcap::kRecordPrefix + l;
  }
  return n;
}

std::uint64_t McapReader::resync(std::uint64_t from, std::uint64_t limit) const {
  // Candidates must prove themselves: a Chunk by decompressing to its CRC, Metadata by parsing
  // exactly, Data End by its fixed length. Message Index records of a damaged chunk and bare
  // Message records (no CRC) are never resync points.
  std::vector<std::uint8_t> records;
  for (std::uint64_t q = from; q < limit && limit - q >= mcap::kRecordPrefix; ++q) {
    const std::uint8_t op = data_[q];
    if (op != mcap::kChunk && op != mcap::kMetadata && op != mcap::kDataEnd) continue;
    const std::uint64_t len = readU64(data_ + q + 1);
    if (len > limit - q - mcap::kRecordPrefix) continue;
    const std::uint8_t* body = data_ + q + mcap::kRecordPrefix;
    try {
      if (op == mcap::kDataEnd) {
        if (len == 4) return q;
      } else if (op == mcap::kMetadata) {
        ByteReader r(body, len);
        r.str("name");
        r.stringMap("metadata");
        if (r.done()) return q;
      } else {
        mcap::ChunkInfo info;
        parseChunkRecord(q, info);
        if (info.records_offset + info.compressed_size != q + mcap::kRecordPrefix + len) continue;
        decompress(info, records);
        if (info.uncompressed_crc != 0) return q;
        // No CRC: at least every record inside must fit.
        std::uint64_t p = 0;
        while (p < records.size() && records.size() - p >= mcap::kRecordPrefix) {
          const std::uint64_t l = readU64(records.data() + p + 1);
          if (l > records.size() - p - mcap::kRecordPrefix) break;
          p += mcap::kRecordPrefix + l;
        }
        if (p == records.size()) return q;
      }
    } catch (const std::exception&) {
      // Not a record: keep looking.
    }
  }
  return limit;
}

void McapReader::linearScan(McapReadMode mode, std::uint64_t limit) {
  const bool strict = mode == McapReadMode::Strict;
  std::uint64_t pos = 8;
  valid_end_ = pos;
  std::vector<std::uint8_t> records;
  std::set<std::uint16_t> indexed;  // channels with a Message Index after the last chunk
  auto closeChunkIndexes = [&] {
    if (chunks_.empty()) return;
    std::set<std::uint16_t> needed;
    for (const auto& [ch, e] : chunks_.back().message_index) needed.insert(ch);
    chunk_index_complete_.back() = needed == indexed;
  };
  // Recover: the record at `pos` is unusable; skip to the next record that proves intact.
  auto skipDamage = [&](std::string why) {
    const std::string prefix = name_ + ": ";
    if (why.compare(0, prefix.size(), prefix) == 0) why.erase(0, prefix.size());
    McapDamage d;
    d.offset = pos;
    d.reason = std::move(why);
    d.messages_lost = messagesIndexedAfter(pos, limit);
    const bool cut = limit - pos < mcap::kRecordPrefix ||
                     readU64(data_ + pos + 1) > limit - pos - mcap::kRecordPrefix;
    const std::uint64_t next = resync(pos + 1, limit);
    d.size = next - pos;
    d.unfinished_tail = cut && next == limit;
    damage_.push_back(std::move(d));
    pos = next;
  };
  while (pos < limit) {
    std::uint64_t len = 0;
    try {
      if (limit - pos < mcap::kRecordPrefix) fail(pos, "truncated record");
      const std::uint8_t op = data_[pos];
      len = readU64(data_ + pos + 1);
      if (len > limit - pos - mcap::kRecordPrefix) {
        fail(pos, "truncated record (opcode " + std::to_string(op) + ")");
      }
      const std::uint8_t* body = data_ + pos + mcap::kRecordPrefix;
      if (op == mcap::kHeader && pos != 8) {
        fail(pos, "second Header record");
      } else if (op == mcap::kSchema) {
        addSchema(pos, body, len);
      } else if (op == mcap::kChannel) {
        addChannel(pos, body, len);
      } else if (op == mcap::kMessage) {
        if (len < 22) fail(pos, "Message record is too short");
        std::uint16_t ch;
        std::memcpy(&ch, body, 2);
        if (!strict && !channelDeclared(ch)) {
          fail(pos, "Message on channel " + std::to_string(ch) + " whose Channel record is lost");
        }
        entries_.push_back({readU64(body + 6), kNoChunk, ch, pos});
      } else if (op == mcap::kChunk) {
        closeChunkIndexes();
        acceptChunk(pos, len, strict, records);
        indexed.clear();
      } else if (op == mcap::kMessageIndex) {
        ByteReader r(body, len);
        const std::uint16_t ch = r.u16();
        ByteReader entries = r.sub32("records");
        if (entries.remaining() % 16 != 0) fail(pos, "Message Index entries are not 16-byte pairs");
        if (!strict) {
          // Kept only when it matches the chunk before it exactly (the repaired summary refers
          // readers to it).
          std::vector<std::pair<std::uint64_t, std::uint64_t>> got;
          while (!entries.done()) {
            const std::uint64_t t = entries.u64();
            got.emplace_back(t, entries.u64());
          }
          decltype(got) want;
          if (!chunks_.empty()) {
            const auto it = chunks_.back().message_index.find(ch);
            if (it != chunks_.back().message_index.end()) want = it->second;
          }
          std::sort(got.begin(), got.end());
          std::sort(want.begin(), want.end());
          if (chunks_.empty() || !r.done() || got != want) {
            fail(pos, "Message Index disagrees with its Chunk");
          }
        }
        if (!chunks_.empty()) {
          indexed.insert(ch);
          auto& c = chunks_.back();
          c.message_index_offsets[ch] = pos;
          c.message_index_length = pos + mcap::kRecordPrefix + len - (c.start_offset + c.length);
        }
      } else if (op == mcap::kMetadata) {
        ByteReader r(body, len);
        mcap::MetadataIndex m;
        m.name = r.str("name");
        r.stringMap("metadata");
        if (!strict && !r.done()) fail(pos, "Metadata record has trailing bytes");
        m.offset = pos;
        m.length = mcap::kRecordPrefix + len;
        metadata_.push_back(std::move(m));
      } else if (op == mcap::kDataEnd) {
        closeChunkIndexes();
        data_end_found_ = true;
        if (strict && len >= 4) {
          std::uint32_t crc;
          std::memcpy(&crc, body, 4);
          if (crc != 0 && crc != Crc32::update(0, data_, pos)) fail(pos, "bad data section CRC");
        }
        valid_end_ = pos;
        break;
      } else if (op == mcap::kFooter) {
        if (strict) fail(pos, "Footer record inside the data section");
        break;
      } else if (!strict && (op == mcap::kChunkIndex || op == mcap::kStatistics ||
                             op == mcap::kSummaryOffset || op == mcap::kMetadataIndex ||
                             op == mcap::kAttachmentIndex)) {
        break;  // the summary begins: a data section without Data End
      } else if (!strict && (op == 0 || (op > mcap::kDataEnd && op < 0x80))) {
        fail(pos, "reserved record opcode " + std::to_string(op));
      }
    } catch (const ShortRead& e) {
      if (strict) fail(pos, std::string("malformed record: ") + e.what());
      skipDamage(std::string("malformed record: ") + e.what());
      continue;
    } catch (const InputError& e) {
      if (strict) throw;
      skipDamage(e.what());
      continue;
    }
    pos += mcap::kRecordPrefix + len;
    valid_end_ = pos;
  }
  if (!data_end_found_) closeChunkIndexes();
  std::stable_sort(entries_.begin(), entries_.end(),
                   [](const Entry& a, const Entry& b) { return a.log_time < b.log_time; });
}

void McapReader::loadSummary(std::uint64_t footer_pos, std::uint64_t summary_start,
                             std::uint64_t summary_offset_start, std::uint32_t summary_crc) {
  used_summary_ = true;
  const std::uint64_t footer_at = footer_pos;
  if (summary_start < 8 + mcap::kRecordPrefix || summary_start > footer_pos) {
    fail(footer_at, "Footer points to a summary outside the file");
  }
  std::uint64_t end = footer_pos;
  if (summary_offset_start != 0) {
    if (summary_offset_start < summary_start || summary_offset_start > footer_pos) {
      fail(footer_at, "Footer points to summary offsets outside the summary");
    }
    end = summary_offset_start;
  }
  if (summary_crc != 0) {
    const std::uint64_t crc_end = footer_pos + mcap::kRecordPrefix + 16;
    if (Crc32::update(0, data_ + summary_start, crc_end - summary_start) != summary_crc) {
      fail(footer_at, "bad summary CRC");
    }
  }
  std::vector<mcap::ChunkInfo> indexes;
  bool have_statistics = false;
  std::uint64_t stated_messages = 0;
  std::uint64_t pos = summary_start;
  while (pos < end) {
    if (end - pos < mcap::kRecordPrefix) fail(pos, "truncated summary record");
    const std::uint8_t op = data_[pos];
    const std::uint64_t len = readU64(data_ + pos + 1);
    if (len > end - pos - mcap::kRecordPrefix) fail(pos, "truncated summary record");
    const std::uint8_t* body = data_ + pos + mcap::kRecordPrefix;
    try {
      if (op == mcap::kSchema) {
        addSchema(pos, body, len);
      } else if (op == mcap::kChannel) {
        addChannel(pos, body, len);
      } else if (op == mcap::kStatistics) {
        ByteReader r(body, len);
        stated_messages = r.u64();
        have_statistics = true;
      } else if (op == mcap::kChunkIndex) {
        ByteReader r(body, len);
        mcap::ChunkInfo ci;
        ci.message_start_time = r.u64();
        ci.message_end_time = r.u64();
        ci.start_offset = r.u64();
        ci.length = r.u64();
        ByteReader offsets = r.sub32("message_index_offsets");
        while (!offsets.done()) {
          const std::uint16_t ch = offsets.u16();
          ci.message_index_offsets[ch] = offsets.u64();
        }
        ci.message_index_length = r.u64();
        ci.compression = r.str("compression");
        ci.compressed_size = r.u64();
        ci.uncompressed_size = r.u64();
        indexes.push_back(std::move(ci));
      }
    } catch (const ShortRead& e) {
      fail(pos, std::string("malformed summary record: ") + e.what());
    }
    pos += mcap::kRecordPrefix + len;
  }
  for (const auto& ci : indexes) {
    if (ci.start_offset >= summary_start || ci.length > summary_start - ci.start_offset) {
      fail(ci.start_offset, "Chunk Index points outside the data section");
    }
    mcap::ChunkInfo info;
    parseChunkRecord(ci.start_offset, info);
    if (info.length != ci.length || info.compressed_size != ci.compressed_size ||
        info.uncompressed_size != ci.uncompressed_size || info.compression != ci.compression) {
      fail(ci.start_offset, "Chunk record disagrees with its Chunk Index");
    }
    info.message_index_offsets = ci.message_index_offsets;
    info.message_index_length = ci.message_index_length;
    chunks_.push_back(std::move(info));
    chunk_index_complete_.push_back(!ci.message_index_offsets.empty());
    const auto no = static_cast<std::uint32_t>(chunks_.size() - 1);
    if (ci.message_index_offsets.empty()) {
      // No message indexes: find the messages by scanning the chunk.
      std::vector<std::uint8_t> records;
      decompressChunk(no, records);
      scanChunkRecords(no, records, false);
      continue;
    }
    for (const auto& [ch, off] : ci.message_index_offsets) {
      if (off >= summary_start || summary_start - off < mcap::kRecordPrefix ||
          data_[off] != mcap::kMessageIndex) {
        fail(off, "Chunk Index points to a missing Message Index record");
      }
      const std::uint64_t len = readU64(data_ + off + 1);
      if (len > summary_start - off - mcap::kRecordPrefix) fail(off, "truncated Message Index");
      try {
        ByteReader r(data_ + off + mcap::kRecordPrefix, len);
        if (r.u16() != ch)
          fail(off, "Message Index is for another channel than its Chunk Index says");
        ByteReader e = r.sub32("records");
        if (e.remaining() % 16 != 0) fail(off, "Message Index entries are not 16-byte pairs");
        auto& list = chunks_.back().message_index[ch];
        while (!e.done()) {
          const std::uint64_t t = e.u64();
          const std::uint64_t o = e.u64();
          if (o >= info.uncompressed_size) fail(off, "Message Index offset outside its Chunk");
          list.emplace_back(t, o);
          entries_.push_back({t, no, ch, o});
        }
      } catch (const ShortRead& e) {
        fail(off, std::string("malformed Message Index: ") + e.what());
      }
    }
  }
  if (have_statistics ? stated_messages != entries_.size() : indexes.empty()) {
    // Messages outside chunks have no index (or no statistics to check against): the summary
    // cannot list them all, so read the data section itself.
    used_summary_ = false;
    schemas_.clear();
    channels_.clear();
    chunks_.clear();
    chunk_index_complete_.clear();
    entries_.clear();
    linearScan(McapReadMode::Strict, summary_start);
    return;
  }
  std::stable_sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
    if (a.log_time != b.log_time) return a.log_time < b.log_time;
    if (a.chunk != b.chunk) return a.chunk < b.chunk;
    return a.offset < b.offset;
  });
}

void McapReader::verifyChunks() const {
  std::vector<std::uint8_t> records;
  for (std::uint32_t no = 0; no < chunks_.size(); ++no) {
    const mcap::ChunkInfo& c = chunks_[no];
    decompressChunk(no, records);
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> found;
    std::uint64_t at = 0;
    const auto on_record = [&](std::uint64_t p, std::uint8_t op, std::uint64_t len) {
      if (op != mcap::kMessage) return;
      if (len < 22) fail(c.start_offset, "Message record inside Chunk is too short");
      std::uint16_t ch;
      std::memcpy(&ch, records.data() + p + mcap::kRecordPrefix, 2);
      found[ch].emplace_back(readU64(records.data() + p + mcap::kRecordPrefix + 6), p);
    };
    const char* why = walkChunkRecords(records, at, on_record);
    if (why != nullptr) fail(c.start_offset, why);
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> indexed;
    for (const auto& [ch, e] : c.message_index) {
      if (!e.empty()) indexed[ch] = e;
    }
    for (auto& [ch, e] : indexed) std::sort(e.begin(), e.end());
    for (auto& [ch, e] : found) std::sort(e.begin(), e.end());
    if (found != indexed) fail(c.start_offset, "Chunk records disagree with its Message Index");
  }
}

void McapReader::finishTopics() {
  channel_topic_.assign(65536, -1);
  for (const auto& c : channels_) {
    TopicInfo t;
    t.name = c.topic;
    t.serialization_format = c.message_encoding;
    if (auto it = c.metadata.find("offered_qos_profiles"); it != c.metadata.end()) {
      t.offered_qos_profiles = it->second;
    }
    if (auto it = c.metadata.find("topic_type_hash"); it != c.metadata.end()) {
      t.type_description_hash = it->second;
    }
    for (const auto& s : schemas_) {
      if (s.id == c.schema_id) {
        t.type = s.name;
        t.message_definition = s.data;
      }
    }
    channel_topic_[c.id] = static_cast<int>(topics_.size());
    topics_.push_back(std::move(t));
  }
  channel_selected_.assign(65536, true);
  for (const auto& e : entries_) {
    if (channel_topic_[e.channel] < 0) {
      const std::uint64_t at = e.chunk == kNoChunk ? e.offset : chunks_[e.chunk].start_offset;
      fail(at, "Message on channel " + std::to_string(e.channel) + " that was never declared");
    }
  }
}

void McapReader::setTopicFilter(const std::set<std::string>& topics) {
  for (const auto& c : channels_) {
    channel_selected_[c.id] = topics.empty() || topics.count(c.topic) != 0;
  }
}

bool McapReader::next(BagMessage& out) {
  while (cursor_ < entries_.size()) {
    const Entry e = entries_[cursor_++];
    if (!channel_selected_[e.channel]) continue;
    const std::uint8_t* rec = nullptr;
    std::uint64_t avail = 0;
    std::uint64_t report_at = e.offset;
    if (e.chunk == kNoChunk) {
      rec = data_ + e.offset;
      avail = size_ - e.offset;
    } else {
      if (cached_chunk_ != e.chunk) {
        cached_chunk_ = kNoChunk;
        decompressChunk(e.chunk, chunk_cache_);
        cached_chunk_ = e.chunk;
      }
      report_at = chunks_[e.chunk].start_offset;
      if (e.offset >= chunk_cache_.size()) fail(report_at, "message offset outside its Chunk");
      rec = chunk_cache_.data() + e.offset;
      avail = chunk_cache_.size() - e.offset;
    }
    if (const char* why = messageRecordProblem(rec, avail, e.channel)) fail(report_at, why);
    const std::uint64_t len = readU64(rec + 1);
    const std::uint8_t* b = rec + mcap::kRecordPrefix;
    const std::uint16_t ch = e.channel;
    std::memcpy(&out.sequence, b + 2, 4);
    out.log_time = static_cast<Timestamp>(readU64(b + 6));
    out.publish_time = static_cast<Timestamp>(readU64(b + 14));
    out.topic = topics_[static_cast<std::size_t>(channel_topic_[ch])].name;
    out.data.assign(b + 22, b + len);
    return true;
  }
  return false;
}

FileStatistics McapReader::statistics() const {
  FileStatistics s;
  for (const auto& t : topics_) s.topic_message_counts[t.name] += 0;
  for (const auto& e : entries_) {
    const auto t = static_cast<Timestamp>(e.log_time);
    if (s.message_count == 0) {
      s.start_time = s.end_time = t;
    } else {
      s.start_time = std::min(s.start_time, t);
      s.end_time = std::max(s.end_time, t);
    }
    ++s.message_count;
    ++s.topic_message_counts[topics_[static_cast<std::size_t>(channel_topic_[e.channel])].name];
  }
  return s;
}

std::uint64_t McapReader::unchunkedMessages() const {
  return static_cast<std::uint64_t>(std::count_if(
      entries_.begin(), entries_.end(), [](const Entry& e) { return e.chunk == kNoChunk; }));
}

const char* McapReader::messageRecordProblem(const std::uint8_t* rec, std::uint64_t avail,
                                             std::uint16_t channel) {
  if (avail < mcap::kRecordPrefix + 22 || rec[0] != mcap::kMessage) {
    return "Message Index points to something that is not a Message record";
  }
  const std::uint64_t len = readU64(rec + 1);
  if (len < 22 || len > avail - mcap::kRecordPrefix) return "truncated Message record";
  std::uint16_t ch;
  std::memcpy(&ch, rec + mcap::kRecordPrefix, 2);
  if (ch != channel) return "Message Index channel differs from its Message record";
  return nullptr;
}

McapLayout McapReader::layoutOf(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return McapLayout::NotMcap;
  McapLayout layout = McapLayout::NotMcap;
  struct stat st {};
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
    const auto size = static_cast<std::uint64_t>(st.st_size);
    // The magic and the Header record, whose length the file gives.
    std::vector<std::uint8_t> head(std::min<std::uint64_t>(size, 17));
    std::uint64_t at = 0;
    if (head.size() == 17 && readAt(fd, 0, head.data(), 17)) {
      const std::uint64_t len = readU64(head.data() + 9);
      if (len <= size - 17 && len <= kMaxChunkSize) {
        head.resize(17 + len);
        if (!readAt(fd, 17, head.data() + 17, len)) head.clear();
      }
    }
    std::uint8_t tail[mcap::kFooterAndMagic];
    if (headerProblem(head.data(), head.size(), at).empty()) {
      layout = size >= mcap::kFooterAndMagic &&
                       readAt(fd, size - mcap::kFooterAndMagic, tail, mcap::kFooterAndMagic) &&
                       endsWithFooter(tail, size)
                   ? McapLayout::Finished
                   : McapLayout::Unfinished;
    }
  }
  ::close(fd);
  return layout;
}

void McapReader::releasePages(std::uint64_t from, std::uint64_t to) const {
  // Read-only private mapping: dropped pages come back from the file if touched again.
  if (map_ == nullptr || to <= from) return;
  const auto page = static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
  const std::uint64_t begin = from / page * page;
  ::madvise(static_cast<std::uint8_t*>(map_) + begin, std::min(to, size_) - begin, MADV_DONTNEED);
}

void McapReader::verify(VerifySink& sink) {
  const auto topicOf = [this](std::uint16_t ch) -> const std::string& {
    return topics_[static_cast<std::size_t>(channel_topic_[ch])].name;
  };
  bool damaged = false;
  std::vector<std::uint8_t> records;
  for (std::uint32_t no = 0; no < chunks_.size(); ++no) {
    const mcap::ChunkInfo& c = chunks_[no];
    try {
      decompressChunk(no, records);
      releasePages(c.start_offset, c.start_offset + c.length);  // one chunk at a time in memory
    } catch (const InputError& e) {
      releasePages(c.start_offset, c.start_offset + c.length);
      // Its Message Index records (kept outside the chunk) still say what it held.
      damaged = true;
      for (const auto& [ch, entries] : c.message_index) {
        if (entries.empty()) continue;
        std::uint64_t first = entries.front().first;
        for (const auto& entry : entries) first = std::min(first, entry.first);
        std::ostringstream os;
        os << e.what() << ": " << entries.size() << " messages of " << topicOf(ch)
           << " in it are lost, the first at log time " << first
           << " ns; `mcvio bag reindex` drops the damaged chunk and keeps the others";
        sink.unreadable(topicOf(ch), entries.size(), os.str());
      }
      continue;
    }
    std::set<std::uint64_t> listed;
    std::uint64_t wrong_times = 0;
    for (const auto& [ch, entries] : c.message_index) {
      for (const auto& [t, off] : entries) {
        listed.insert(off);
        const char* why = off >= records.size() ? "message offset outside its Chunk"
                                                : messageRecordProblem(records.data() + off,
                                                                       records.size() - off, ch);
        if (why == nullptr) {
          // Readers order messages by the index's time: it must be the record's.
          if (readU64(records.data() + off + mcap::kRecordPrefix + 6) != t) ++wrong_times;
          sink.readable(topicOf(ch));
          continue;
        }
        damaged = true;
        std::ostringstream os;
        os << name_ << ": message at log time " << t << " ns on " << topicOf(ch)
           << " (Chunk at byte offset " << c.start_offset << ", uncompressed offset " << off
           << "): " << why << "; `mcvio bag reindex` rebuilds the indexes from the chunk";
        sink.unreadable(topicOf(ch), 1, os.str());
      }
    }
    // Message records no index lists: readers going by the indexes never return them.
    std::uint64_t unlisted = 0;
    std::uint64_t at = 0;
    if (walkChunkRecords(records, at, [&](std::uint64_t p, std::uint8_t op, std::uint64_t) {
          if (op == mcap::kMessage && listed.count(p) == 0) ++unlisted;
        }) != nullptr) {
      damaged = true;
      sink.problem(name_ + ": record at uncompressed offset " + std::to_string(at) +
                   " runs past its Chunk at byte offset " + std::to_string(c.start_offset));
    }
    if (wrong_times > 0) {
      damaged = true;
      sink.problem(name_ + ": Chunk at byte offset " + std::to_string(c.start_offset) + ": " +
                   std::to_string(wrong_times) +
                   " Message Index entries give another log time than their Message record "
                   "(readers return them out of order); `mcvio bag reindex` rebuilds the indexes "
                   "from the chunk");
    }
    if (unlisted > 0) {
      damaged = true;
      sink.problem(name_ + ": Chunk at byte offset " + std::to_string(c.start_offset) + " holds " +
                   std::to_string(unlisted) +
                   " Message records its Message Index does not list (readers skip them); "
                   "`mcvio bag reindex` rebuilds the indexes from the chunk");
    }
  }
  for (const auto& e : entries_) {
    if (e.chunk != kNoChunk) continue;
    if (const char* why = messageRecordProblem(data_ + e.offset, size_ - e.offset, e.channel)) {
      damaged = true;
      sink.unreadable(topicOf(e.channel), 1,
                      name_ + ": message at log time " + std::to_string(e.log_time) + " ns on " +
                          topicOf(e.channel) + " at byte offset " + std::to_string(e.offset) +
                          ": " + why);
    } else {
      sink.readable(topicOf(e.channel));
    }
  }
  if (used_summary_ && !damaged) {
    // A summary-based load never read the data section as a whole: its Data End CRC covers
    // the bytes between the chunks' records too (Schema, Channel, Message Index, Metadata).
    const Footer f = footer();
    const std::uint64_t data_end_size = mcap::kRecordPrefix + 4;
    if (f.summary_start >= 8 + data_end_size) {
      const std::uint64_t at = f.summary_start - data_end_size;
      std::uint32_t crc = 0;
      if (data_[at] == mcap::kDataEnd && readU64(data_ + at + 1) == 4) {
        std::memcpy(&crc, data_ + at + mcap::kRecordPrefix, 4);
      }
      std::uint32_t computed = 0;
      for (std::uint64_t p = 0; p < at;) {
        const std::uint64_t n = std::min<std::uint64_t>(at - p, 4ull << 20);
        computed = Crc32::update(computed, data_ + p, n);
        releasePages(p, p + n);
        p += n;
      }
      if (crc != 0 && computed != crc) {
        sink.problem(name_ + ": bad data section CRC (Data End at byte offset " +
                     std::to_string(at) +
                     "): bytes outside the chunks' records are damaged; every message was "
                     "read intact");
      }
    }
  }
}

}  // namespace mcvio::bag
