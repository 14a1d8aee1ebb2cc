#include "mcvio/bag/sqlite_reader.hpp"

#include <sqlite3.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "mcvio/bag/mcap_records.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

namespace {

constexpr char kSqliteMagic[16] = "SQLite format 3";  // 15 chars + NUL, as on disk
/// Bound on one decompressed message, so a forged frame cannot exhaust memory.
constexpr std::size_t kMaxMessageSize = std::size_t{1} << 31;
/// The newest rosbag2 sqlite3 schema version this reader knows (Iron and later).
constexpr long long kKnownSchemaVersion = 4;

std::string columnText(sqlite3_stmt* st, int col) {
  const auto* t = sqlite3_column_text(st, col);
  return t ? std::string(reinterpret_cast<const char*>(t),
                         static_cast<std::size_t>(sqlite3_column_bytes(st, col)))
           : std::string();
}

std::string typeName(int sqlite_type) {
  switch (sqlite_type) {
    case SQLITE_INTEGER: return "an INTEGER";
    case SQLITE_FLOAT: return "a REAL";
    case SQLITE_TEXT: return "TEXT";
    case SQLITE_BLOB: return "a BLOB";
    default: return "NULL";
  }
}

std::filesystem::path sibling(const std::filesystem::path& path, const char* suffix) {
  std::filesystem::path p = path;
  p += suffix;
  return p;
}

/// `path` for an sqlite file: URI: '?' and '#' would end the path, '%' starts an escape.
std::string uriPath(const std::filesystem::path& path) {
  std::string out;
  for (const char c : std::filesystem::absolute(path).string()) {
    if (c == '?' || c == '#' || c == '%') {
      static const char kHex[] = "0123456789ABCDEF";
      out += '%';
      out += kHex[static_cast<unsigned char>(c) >> 4];
      out += kHex[c & 0xF];
    } else {
      out += c;
    }
  }
  return out;
}

std::uint64_t sizeOr0(const std::filesystem::path& p) {
  std::error_code ec;
  const auto n = std::filesystem::file_size(p, ec);
  return ec ? 0 : n;
}

/// The first 16 bytes of the file ("" when shorter).
std::string head16(const std::filesystem::path& path) {
  char head[16] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(head, 16);
  return in.gcount() < 16 ? std::string() : std::string(head, 16);
}

void checkMagic(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path.string() + ": cannot open (" + ec.message() + ")");
  const auto wal = sibling(path, "-wal");
  if (size == 0 && sizeOr0(wal) > 0) {
    // sqlite deletes the write-ahead log of an empty database file when it opens it: that would
    // throw away every message a killed writer committed.
    throw InputError(path.string() + ": the file is empty but its write-ahead log " + wal.string() +
                     " (" + std::to_string(sizeOr0(wal)) +
                     " bytes) may hold the recording of a killed writer; not opened. "
                     "`mcvio bag reindex` on the bag folder folds it in");
  }
  const std::string head = head16(path);
  if (head.size() == 16 && std::memcmp(head.data(), mcap::kMagic, sizeof(mcap::kMagic)) == 0) {
    throw InputError(path.string() +
                     ": is an MCAP file, not an sqlite3 database (metadata.yaml's "
                     "storage_identifier or the file's extension says sqlite3)");
  }
  if (head.size() < 16 || std::memcmp(head.data(), kSqliteMagic, 16) != 0) {
    throw InputError(path.string() + ": not an sqlite3 database (wrong magic at byte offset 0)");
  }
}

/// The compression whose frame magic a stored message starts with (a CDR message never starts
/// with one), else None.
Compression frameMagic(const std::uint8_t* data, std::size_t size) {
  static const std::uint8_t kZstd[4] = {0x28, 0xB5, 0x2F, 0xFD};
  static const std::uint8_t kLz4[4] = {0x04, 0x22, 0x4D, 0x18};
  if (size >= 4 && std::memcmp(data, kZstd, 4) == 0) return Compression::Zstd;
  if (size >= 4 && std::memcmp(data, kLz4, 4) == 0) return Compression::Lz4;
  return Compression::None;
}

std::uint32_t bigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

/// A killed writer can leave an empty .db3 beside a -wal that holds everything (page 1
/// included). sqlite would delete such a log; writing the log's last committed copy of page 1
/// into the .db3 lets sqlite replay the log itself (it checks the frames' checksums).
/// Returns false when the log holds no committed page 1.
bool restoreFirstPageFromWal(const std::filesystem::path& db, const std::filesystem::path& wal) {
  std::ifstream in(wal, std::ios::binary);
  std::vector<std::uint8_t> header(32);
  if (!in.read(reinterpret_cast<char*>(header.data()), 32)) return false;
  const std::uint32_t magic = bigEndian32(header.data());
  const std::uint32_t page_size = bigEndian32(header.data() + 8);
  if ((magic & 0xFFFFFFFEu) != 0x377f0682u || page_size < 512 || page_size > 65536 ||
      (page_size & (page_size - 1)) != 0) {
    return false;
  }
  std::vector<std::uint8_t> frame(24 + page_size);
  std::vector<std::uint8_t> candidate;
  std::vector<std::uint8_t> committed;
  while (in.read(reinterpret_cast<char*>(frame.data()), static_cast<std::streamsize>(frame.size()))) {
    // Frames of an older generation of the log carry other salts: they end the valid log.
    if (std::memcmp(frame.data() + 8, header.data() + 16, 8) != 0) break;
    if (bigEndian32(frame.data()) == 1) candidate.assign(frame.begin() + 24, frame.end());
    if (bigEndian32(frame.data() + 4) != 0 && !candidate.empty()) committed = candidate;
  }
  if (committed.empty()) return false;
  std::ofstream out(db, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(committed.data()),
            static_cast<std::streamsize>(committed.size()));
  return static_cast<bool>(out);
}

}  // namespace

bool SqliteReader::looksLikeSqlite(const std::filesystem::path& path) {
  const std::string head = head16(path);
  return head.size() == 16 && std::memcmp(head.data(), kSqliteMagic, 16) == 0;
}

SqliteReader::SqliteReader(const std::filesystem::path& path, Compression message_compression)
    : name_(path.string()), compression_(message_compression) {
  checkMagic(path);
  // Readers must leave a recording byte-identical (read-only media, checksums): a read-only
  // connection still sees a killed writer's -wal but never checkpoints it into the .db3 nor
  // deletes it; only `bag reindex` folds it in. sqlite may create the -shm (its wal-index, no
  // data) beside the file, which is far cheaper than copying a large .db3.
  std::string why;
  if (!openDatabase(path, /*read_only=*/true, why)) {
    // A read-only folder without a -shm (or a hot -journal, which must be rolled back before
    // the file reads consistently): replay it in a private copy instead of the user's files.
    const bool leftover = std::filesystem::exists(sibling(path, "-wal")) ||
                          std::filesystem::exists(sibling(path, "-journal"));
    if (!leftover) throw InputError(name_ + ": cannot open sqlite3 database: " + why);
    const auto copy = copyToTempDir(path);
    if (!openDatabase(copy, /*read_only=*/false, why)) {
      removeTempDir();
      throw InputError(name_ + ": cannot open sqlite3 database (also not a temporary copy " +
                       copy.string() + "): " + why);
    }
  }
  try {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db_, "SELECT name FROM sqlite_master WHERE type='table';", -1, &st,
                           nullptr) != SQLITE_OK) {
      fail(sqlite3_errmsg(db_));
    }
    std::set<std::string> tables;
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) tables.insert(columnText(st, 0));
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
    if (tables.count("topics") == 0 || tables.count("messages") == 0) {
      fail("not a rosbag2 sqlite3 file (no topics/messages tables)");
    }
    // Schema version 1 (Foxy and older) has no schema table; 2..4 name their version in it.
    if (tables.count("schema")) {
      if (sqlite3_prepare_v2(db_, "SELECT MAX(schema_version) FROM schema;", -1, &st, nullptr) ==
          SQLITE_OK) {
        if (sqlite3_step(st) == SQLITE_ROW) {
          if (sqlite3_column_type(st, 0) == SQLITE_NULL) {
            warnings_.push_back(name_ + ": the schema table holds no schema_version");
          } else if (const long long v = sqlite3_column_int64(st, 0);
                     v < 1 || v > kKnownSchemaVersion) {
            warnings_.push_back(name_ + ": schema_version " + std::to_string(v) +
                                " is not one of the known 1.." +
                                std::to_string(kKnownSchemaVersion) +
                                " (read as the newest known layout)");
          }
        }
        sqlite3_finalize(st);
      } else {
        warnings_.push_back(name_ + ": the schema table has no schema_version column");
      }
    }
    const std::set<std::string> message_columns = columns("messages");
    for (const char* c : {"topic_id", "timestamp", "data"}) {
      if (message_columns.count(c) == 0) {
        fail(std::string("table messages has no column ") + c +
             " (not a rosbag2 file, or a damaged one)");
      }
    }
    readTopics(tables.count("message_definitions") != 0);
    // rowid: the row's id whatever the table calls it, for error messages.
    if (sqlite3_prepare_v2(db_,
                           "SELECT rowid, topic_id, timestamp, data FROM messages "
                           "ORDER BY timestamp, rowid;",
                           -1, &cursor_, nullptr) != SQLITE_OK) {
      fail(sqlite3_errmsg(db_));
    }
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    removeTempDir();
    throw;
  }
}

bool SqliteReader::openDatabase(const std::filesystem::path& path, bool read_only,
                                std::string& why) {
  // mode=ro in the URI as well: a read-only open must not fall back to read-write.
  const std::string uri = "file:" + uriPath(path) + (read_only ? "?mode=ro" : "");
  const int flags = (read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE) | SQLITE_OPEN_URI;
  int rc = sqlite3_open_v2(uri.c_str(), &db_, flags, nullptr);
  if (rc == SQLITE_OK) {
    // The -wal and -shm are opened at the first read, not by sqlite3_open_v2: read now so a
    // folder where they cannot be used fails here. Other errors (a damaged file) are reported
    // by the checks that follow.
    rc = sqlite3_exec(db_, "SELECT COUNT(*) FROM sqlite_master;", nullptr, nullptr, nullptr);
    if ((rc & 0xFF) != SQLITE_CANTOPEN && (rc & 0xFF) != SQLITE_READONLY) return true;
  }
  why = db_ ? sqlite3_errmsg(db_) : "out of memory";
  sqlite3_close(db_);
  db_ = nullptr;
  return false;
}

std::filesystem::path SqliteReader::copyToTempDir(const std::filesystem::path& path) {
  std::string tmpl = (std::filesystem::temp_directory_path() / "mcvio_sqlite_XXXXXX").string();
  if (!mkdtemp(tmpl.data())) {
    throw InputError(name_ + ": cannot create a temporary directory for a copy to read (" +
                     std::strerror(errno) + ")");
  }
  temp_dir_ = tmpl;
  const auto copy = temp_dir_ / path.filename();
  try {
    std::filesystem::copy_file(path, copy);
    for (const char* suffix : {"-wal", "-journal"}) {
      if (std::filesystem::exists(sibling(path, suffix))) {
        std::filesystem::copy_file(sibling(path, suffix), sibling(copy, suffix));
      }
    }
  } catch (const std::filesystem::filesystem_error& e) {
    removeTempDir();
    throw InputError(name_ + ": cannot copy it to a temporary directory to read: " + e.what());
  }
  return copy;
}

void SqliteReader::removeTempDir() {
  if (temp_dir_.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(temp_dir_, ec);
  temp_dir_.clear();
}

std::set<std::string> SqliteReader::columns(const std::string& table) const {
  std::set<std::string> out;
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_, ("PRAGMA table_info(" + table + ");").c_str(), -1, &st, nullptr) !=
      SQLITE_OK) {
    fail(sqlite3_errmsg(db_));
  }
  int rc;
  while ((rc = sqlite3_step(st)) == SQLITE_ROW) out.insert(columnText(st, 1));
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
  return out;
}

void SqliteReader::readTopics(bool has_definitions) {
  sqlite3_stmt* st = nullptr;
  int rc;
  std::map<std::string, std::string> definitions;
  if (has_definitions) {
    if (sqlite3_prepare_v2(db_,
                           "SELECT topic_type, encoded_message_definition FROM "
                           "message_definitions;",
                           -1, &st, nullptr) != SQLITE_OK) {
      fail(std::string("table message_definitions: ") + sqlite3_errmsg(db_));
    }
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) definitions[columnText(st, 0)] = columnText(st, 1);
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
  }
  const std::set<std::string> cols = columns("topics");
  for (const char* c : {"id", "name", "type", "serialization_format"}) {
    if (cols.count(c) == 0) {
      fail(std::string("table topics has no column ") + c +
           " (not a rosbag2 file, or a damaged one)");
    }
  }
  // offered_qos_profiles came with Foxy and type_description_hash with Iron: older files
  // lack them.
  const bool has_qos = cols.count("offered_qos_profiles") != 0;
  const bool has_hash = cols.count("type_description_hash") != 0;
  const std::string q = std::string("SELECT id, name, type, serialization_format") +
                        (has_qos ? ", offered_qos_profiles" : ", ''") +
                        (has_hash ? ", type_description_hash" : ", ''") +
                        " FROM topics ORDER BY id;";
  if (sqlite3_prepare_v2(db_, q.c_str(), -1, &st, nullptr) != SQLITE_OK) {
    fail(sqlite3_errmsg(db_));
  }
  std::map<std::string, long long> first_id;
  try {
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
      const long long id = sqlite3_column_int64(st, 0);
      TopicInfo t;
      t.name = columnText(st, 1);
      t.type = columnText(st, 2);
      t.serialization_format = columnText(st, 3);
      t.offered_qos_profiles = columnText(st, 4);
      t.type_description_hash = columnText(st, 5);
      const std::string row = "topics row id " + std::to_string(id);
      if (t.name.empty()) fail(row + ": empty topic name");
      if (t.type.empty()) fail("topic " + t.name + " (" + row + "): empty type");
      if (auto it = first_id.find(t.name); it != first_id.end()) {
        // One name under two ids: the same topic again is merged; two types cannot be read.
        const std::size_t k = topic_index_.at(it->second);
        if (topics_[k].type != t.type) {
          fail("topic " + t.name + " is declared twice with different types: id " +
               std::to_string(it->second) + " " + topics_[k].type + ", id " + std::to_string(id) +
               " " + t.type);
        }
        topic_index_[id] = k;
        continue;
      }
      if (t.serialization_format != "cdr") {
        warnings_.push_back(name_ + ": topic " + t.name + ": serialization_format '" +
                            t.serialization_format + "' (expected cdr)");
      }
      if (auto it = definitions.find(t.type); it != definitions.end()) {
        t.message_definition = it->second;
      }
      first_id[t.name] = id;
      topic_index_[id] = topics_.size();
      topics_.push_back(std::move(t));
    }
  } catch (...) {
    sqlite3_finalize(st);
    throw;
  }
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
}

SqliteReader::~SqliteReader() {
  if (cursor_) sqlite3_finalize(cursor_);
  if (db_) sqlite3_close(db_);
  removeTempDir();
}

void SqliteReader::fail(const std::string& what) const {
  throw InputError(name_ + ": sqlite3: " + what);
}

void SqliteReader::setTopicFilter(const std::set<std::string>& topics) {
  selected_.clear();
  filtered_ = !topics.empty();
  for (const auto& [id, k] : topic_index_) {
    if (topics.count(topics_[k].name)) selected_.insert(id);
  }
}

bool SqliteReader::next(BagMessage& out) {
  while (true) {
    const int rc = sqlite3_step(cursor_);
    if (rc == SQLITE_DONE) return false;
    if (rc != SQLITE_ROW) fail(std::string("reading messages: ") + sqlite3_errmsg(db_));
    if (readRow(cursor_, compression_, /*filter=*/true, out)) return true;
  }
}

bool SqliteReader::readRow(sqlite3_stmt* st, Compression compression, bool filter,
                           BagMessage& out) {
  // Error texts are built only on failure: this runs once per message.
  const auto row = [st] {
    return "messages row id " + std::to_string(sqlite3_column_int64(st, 0));
  };
  // Checked before the topic filter: a row of no known topic may be a lost message of the
  // selected ones, so it is never skipped silently.
  const int id_type = sqlite3_column_type(st, 1);
  if (id_type != SQLITE_INTEGER) {
    fail(row() + ": topic_id is " + typeName(id_type) + ", not a topic id");
  }
  const long long id = sqlite3_column_int64(st, 1);
  const auto topic = topic_index_.find(id);
  if (topic == topic_index_.end()) {
    fail(row() + " refers to unknown topic id " + std::to_string(id));
  }
  if (filter && filtered_ && selected_.count(id) == 0) return false;
  out.topic = topics_[topic->second].name;
  const auto what = [&] { return row() + " on " + out.topic; };
  const int time_type = sqlite3_column_type(st, 2);
  if (time_type != SQLITE_INTEGER) {
    fail(what() + ": timestamp is " + typeName(time_type) +
         " (expected INTEGER nanoseconds since the epoch)");
  }
  out.log_time = sqlite3_column_int64(st, 2);
  if (out.log_time < 0) {
    fail(what() + ": negative timestamp " + std::to_string(out.log_time) + " ns");
  }
  out.publish_time = out.log_time;
  out.sequence = 0;
  const int data_type = sqlite3_column_type(st, 3);
  if (data_type != SQLITE_BLOB) {
    fail(what() + " at " + std::to_string(out.log_time) + " ns: data is " + typeName(data_type) +
         ", not a BLOB");
  }
  const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(st, 3));
  const auto n = static_cast<std::size_t>(sqlite3_column_bytes(st, 3));
  if (compression == Compression::None) {
    // A compressed payload under a metadata.yaml that says none would reach the decoder as
    // nonsense: name the likely cause instead.
    if (const Compression framed = frameMagic(blob, n); framed != Compression::None) {
      fail(what() + " at " + std::to_string(out.log_time) + " ns: data is a " + toString(framed) +
           " frame but metadata.yaml gives no message compression");
    }
    out.data.assign(blob, blob + n);
  } else {
    try {
      Codec::decompressFrame(compression, blob, n, kMaxMessageSize, out.data);
    } catch (const std::exception& e) {
      fail("message at " + std::to_string(out.log_time) + " ns on " + out.topic + " (" + row() +
           ") does not decompress: " + e.what());
    }
  }
  return true;
}

void SqliteReader::verify(VerifySink& sink) { verify(sink, compression_); }

void SqliteReader::verify(VerifySink& sink, Compression compression) {
  // Row id order: the table's own order, read front to back without the timestamp index.
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_,
                         "SELECT rowid, topic_id, timestamp, data FROM messages ORDER BY rowid;",
                         -1, &st, nullptr) != SQLITE_OK) {
    sink.problem(name_ + ": sqlite3: cannot read the messages table: " + sqlite3_errmsg(db_) +
                 "; `mcvio bag reindex` cannot repair an sqlite3 file");
    return;
  }
  const char* const kNoRepair =
      "; `mcvio bag reindex` cannot recover it (the stored row itself is damaged)";
  BagMessage m;
  long long last_row = 0;
  int rc;
  while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
    last_row = sqlite3_column_int64(st, 0);
    try {
      readRow(st, compression, /*filter=*/false, m);
      sink.readable(m.topic);
    } catch (const InputError& e) {
      std::string topic;
      if (sqlite3_column_type(st, 1) == SQLITE_INTEGER) {
        const auto it = topic_index_.find(sqlite3_column_int64(st, 1));
        if (it != topic_index_.end()) topic = topics_[it->second].name;
      }
      sink.unreadable(topic, 1, e.what() + std::string(kNoRepair));
    }
  }
  const std::string why = rc == SQLITE_DONE ? "" : sqlite3_errmsg(db_);
  sqlite3_finalize(st);
  if (rc == SQLITE_DONE) return;
  // Damaged pages end the scan: count what lies beyond, if sqlite still can.
  const std::string after = "after messages row id " + std::to_string(last_row);
  const std::string lost = name_ + ": sqlite3: reading messages " + after + " failed (" + why +
                           "); `mcvio bag reindex` cannot repair damage inside an sqlite3 file "
                           "(the sqlite3 shell's .recover salvages what is left)";
  std::map<std::string, std::uint64_t> rest;
  bool counted = sqlite3_prepare_v2(db_,
                                    "SELECT topic_id, COUNT(*) FROM messages WHERE rowid > ?1 "
                                    "GROUP BY topic_id;",
                                    -1, &st, nullptr) == SQLITE_OK;
  if (counted) {
    sqlite3_bind_int64(st, 1, last_row);
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
      const auto it = topic_index_.find(sqlite3_column_int64(st, 0));
      rest[it == topic_index_.end() ? std::string() : topics_[it->second].name] +=
          static_cast<std::uint64_t>(sqlite3_column_int64(st, 1));
    }
    counted = rc == SQLITE_DONE;
    sqlite3_finalize(st);
  }
  if (!counted || rest.empty()) {
    sink.problem(lost + "; how many messages lie beyond is unknown");
    return;
  }
  for (const auto& [topic, n] : rest) sink.unreadable(topic, n, lost);
}

FileStatistics SqliteReader::statistics() const {
  FileStatistics s;
  for (const auto& t : topics_) s.topic_message_counts[t.name] += 0;
  sqlite3_stmt* st = nullptr;
  // No data column here: GROUP BY would copy every BLOB into its sorter (slow on big bags).
  if (sqlite3_prepare_v2(db_,
                         "SELECT topic_id, typeof(topic_id), COUNT(*), MIN(timestamp), "
                         "MAX(timestamp), SUM(typeof(timestamp) <> 'integer'), MIN(rowid) "
                         "FROM messages GROUP BY topic_id;",
                         -1, &st, nullptr) != SQLITE_OK) {
    fail(sqlite3_errmsg(db_));
  }
  int rc;
  try {
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
      const long long id = sqlite3_column_int64(st, 0);
      const std::string id_type = columnText(st, 1);
      const auto n = static_cast<std::uint64_t>(sqlite3_column_int64(st, 2));
      const Timestamp lo = sqlite3_column_int64(st, 3);
      const Timestamp hi = sqlite3_column_int64(st, 4);
      const long long bad_times = sqlite3_column_int64(st, 5);
      const auto topic = topic_index_.find(id);
      if (id_type != "integer" || topic == topic_index_.end()) {
        fail(std::to_string(n) + " messages refer to " +
             (id_type != "integer" ? "a topic_id of type " + id_type
                                   : "unknown topic id " + std::to_string(id)) +
             " (first at messages row id " + std::to_string(sqlite3_column_int64(st, 6)) + ")");
      }
      const std::string& name = topics_[topic->second].name;
      if (bad_times > 0) {
        fail("topic " + name + ": " + std::to_string(bad_times) +
             " messages have a timestamp that is not an INTEGER");
      }
      if (lo < 0) fail("topic " + name + ": negative timestamp " + std::to_string(lo) + " ns");
      s.topic_message_counts[name] += n;
      if (s.message_count == 0) {
        s.start_time = lo;
        s.end_time = hi;
      } else {
        s.start_time = std::min(s.start_time, lo);
        s.end_time = std::max(s.end_time, hi);
      }
      s.message_count += n;
    }
  } catch (...) {
    sqlite3_finalize(st);
    throw;
  }
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
  // typeof() of a row's data reads its record header, not the BLOB's pages.
  if (sqlite3_prepare_v2(db_,
                         "SELECT COUNT(*), MIN(rowid) FROM messages WHERE typeof(data) <> 'blob';",
                         -1, &st, nullptr) != SQLITE_OK) {
    fail(sqlite3_errmsg(db_));
  }
  long long bad_data = 0;
  long long first_bad = 0;
  if (sqlite3_step(st) == SQLITE_ROW) {
    bad_data = sqlite3_column_int64(st, 0);
    first_bad = sqlite3_column_int64(st, 1);
  }
  sqlite3_finalize(st);
  if (bad_data > 0) {
    fail(std::to_string(bad_data) + " messages have data that is NULL or not a BLOB (first at " +
         "messages row id " + std::to_string(first_bad) + ")");
  }
  return s;
}

std::optional<Compression> SqliteReader::firstMessageCompression() const {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_, "SELECT substr(data, 1, 4) FROM messages ORDER BY timestamp, rowid LIMIT 1;", -1,
                         &st, nullptr) != SQLITE_OK) {
    fail(sqlite3_errmsg(db_));
  }
  std::optional<Compression> seen;
  if (sqlite3_step(st) == SQLITE_ROW) {
    const auto* head = static_cast<const std::uint8_t*>(sqlite3_column_blob(st, 0));
    const int n = sqlite3_column_bytes(st, 0);
    seen = frameMagic(head, static_cast<std::size_t>(n));
  }
  sqlite3_finalize(st);
  return seen;
}

std::string SqliteReader::storedMetadataYaml() const {
  sqlite3_stmt* st = nullptr;
  std::string yaml;
  if (sqlite3_prepare_v2(db_, "SELECT metadata FROM metadata ORDER BY id DESC LIMIT 1;", -1, &st,
                         nullptr) != SQLITE_OK) {
    return yaml;  // older schema without the table
  }
  if (sqlite3_step(st) == SQLITE_ROW) yaml = columnText(st, 0);
  sqlite3_finalize(st);
  return yaml;
}

bool SqliteReader::recover(const std::filesystem::path& path) {
  const auto wal = sibling(path, "-wal");
  const bool leftover = std::filesystem::exists(wal) ||
                        std::filesystem::exists(sibling(path, "-journal"));
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) == 0 && !ec && sizeOr0(wal) > 0 &&
      !restoreFirstPageFromWal(path, wal)) {
    throw InputError(path.string() + ": the file is empty and its write-ahead log " +
                     wal.string() + " holds no committed transaction: nothing to recover");
  }
  checkMagic(path);
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    const std::string why = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw InputError(path.string() + ": cannot open sqlite3 database: " + why);
  }
  char* err = nullptr;
  int rc = sqlite3_exec(db, "PRAGMA wal_checkpoint(TRUNCATE); PRAGMA journal_mode=DELETE;",
                        nullptr, nullptr, &err);
  std::string why = err ? err : "";
  sqlite3_free(err);
  // quick_check answers with rows ("ok", or one line per problem), not with an error code.
  std::string problems;
  if (rc == SQLITE_OK) {
    sqlite3_stmt* st = nullptr;
    rc = sqlite3_prepare_v2(db, "PRAGMA quick_check(5);", -1, &st, nullptr);
    while (rc == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW) {
      const std::string line = columnText(st, 0);
      if (line != "ok") problems += (problems.empty() ? "" : "; ") + line;
    }
    sqlite3_finalize(st);
    if (rc != SQLITE_OK) why = sqlite3_errmsg(db);
  }
  sqlite3_close(db);
  if (rc != SQLITE_OK) throw InputError(path.string() + ": sqlite3 recovery failed: " + why);
  if (!problems.empty()) {
    throw InputError(path.string() + ": sqlite3 integrity check failed (" + problems +
                     "); reindex cannot repair damage inside an sqlite3 file (the sqlite3 "
                     "shell's .recover salvages what is left)");
  }
  return leftover;
}

}  // namespace mcvio::bag
