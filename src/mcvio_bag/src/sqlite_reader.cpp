#include "mcvio/bag/sqlite_reader.hpp"

#include <sqlite3.h>

#include <cstring>
#include <fstream>
#include <map>

#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

namespace {

constexpr char kSqliteMagic[16] = "SQLite format 3";  // 15 chars + NUL, as on disk
/// Bound on one decompressed message, so a forged frame cannot exhaust memory.
constexpr std::size_t kMaxMessageSize = std::size_t{1} << 31;

std::string columnText(sqlite3_stmt* st, int col) {
  const auto* t = sqlite3_column_text(st, col);
  return t ? std::string(reinterpret_cast<const char*>(t),
                         static_cast<std::size_t>(sqlite3_column_bytes(st, col)))
           : std::string();
}

void checkMagic(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path.string() + ": cannot open (" + ec.message() + ")");
  std::filesystem::path wal = path;
  wal += "-wal";
  if (size == 0 && std::filesystem::exists(wal)) return;  // everything still in the WAL
  char head[16] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(head, 16);
  if (in.gcount() < 16 || std::memcmp(head, kSqliteMagic, 16) != 0) {
    throw InputError(path.string() + ": not an sqlite3 database (wrong magic at byte offset 0)");
  }
}

}  // namespace

SqliteReader::SqliteReader(const std::filesystem::path& path, Compression message_compression)
    : name_(path.string()), compression_(message_compression) {
  checkMagic(path);
  std::filesystem::path wal = path;
  wal += "-wal";
  // A file with a live WAL (killed writer) needs write access to replay it; otherwise read only.
  const int flags = std::filesystem::exists(wal) ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY;
  if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(name_ + ": cannot open sqlite3 database: " + why);
  }
  try {
    sqlite3_stmt* st = nullptr;
    std::map<std::string, std::string> definitions;
    bool has_hash = false;
    bool has_definitions = false;
    if (sqlite3_prepare_v2(db_, "SELECT name, sql FROM sqlite_master WHERE type='table';", -1, &st,
                           nullptr) != SQLITE_OK) {
      fail(sqlite3_errmsg(db_));
    }
    std::set<std::string> tables;
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
      const std::string table = columnText(st, 0);
      tables.insert(table);
      if (table == "topics" &&
          columnText(st, 1).find("type_description_hash") != std::string::npos) {
        has_hash = true;
      }
    }
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
    if (tables.count("topics") == 0 || tables.count("messages") == 0) {
      fail("not a rosbag2 sqlite3 file (no topics/messages tables)");
    }
    has_definitions = tables.count("message_definitions") != 0;
    if (has_definitions) {
      if (sqlite3_prepare_v2(db_,
                             "SELECT topic_type, encoding, encoded_message_definition FROM "
                             "message_definitions;",
                             -1, &st, nullptr) != SQLITE_OK) {
        fail(sqlite3_errmsg(db_));
      }
      while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        definitions[columnText(st, 0)] = columnText(st, 2);
      }
      sqlite3_finalize(st);
      if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
    }
    const std::string q = std::string("SELECT id, name, type, serialization_format, ") +
                          "offered_qos_profiles" + (has_hash ? ", type_description_hash" : "") +
                          " FROM topics ORDER BY id;";
    if (sqlite3_prepare_v2(db_, q.c_str(), -1, &st, nullptr) != SQLITE_OK) {
      fail(sqlite3_errmsg(db_));
    }
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
      TopicInfo t;
      topic_ids_.push_back(sqlite3_column_int64(st, 0));
      t.name = columnText(st, 1);
      t.type = columnText(st, 2);
      t.serialization_format = columnText(st, 3);
      t.offered_qos_profiles = columnText(st, 4);
      if (has_hash) t.type_description_hash = columnText(st, 5);
      if (auto it = definitions.find(t.type); it != definitions.end())
        t.message_definition = it->second;
      topics_.push_back(std::move(t));
    }
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
    if (sqlite3_prepare_v2(db_,
                           "SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id;",
                           -1, &cursor_, nullptr) != SQLITE_OK) {
      fail(sqlite3_errmsg(db_));
    }
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

SqliteReader::~SqliteReader() {
  if (cursor_) sqlite3_finalize(cursor_);
  if (db_) sqlite3_close(db_);
}

void SqliteReader::fail(const std::string& what) const {
  throw InputError(name_ + ": sqlite3: " + what);
}

void SqliteReader::setTopicFilter(const std::set<std::string>& topics) {
  selected_.clear();
  filtered_ = !topics.empty();
  for (std::size_t i = 0; i < topics_.size(); ++i) {
    if (topics.count(topics_[i].name)) selected_.insert(topic_ids_[i]);
  }
}

bool SqliteReader::next(BagMessage& out) {
  while (true) {
    const int rc = sqlite3_step(cursor_);
    if (rc == SQLITE_DONE) return false;
    if (rc != SQLITE_ROW) fail(std::string("reading messages: ") + sqlite3_errmsg(db_));
    const long long id = sqlite3_column_int64(cursor_, 0);
    if (filtered_ && selected_.count(id) == 0) continue;
    std::size_t k = 0;
    while (k < topic_ids_.size() && topic_ids_[k] != id) ++k;
    if (k == topic_ids_.size()) {
      fail("message refers to unknown topic id " + std::to_string(id));
    }
    out.topic = topics_[k].name;
    out.log_time = sqlite3_column_int64(cursor_, 1);
    out.publish_time = out.log_time;
    out.sequence = 0;
    const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(cursor_, 2));
    const auto n = static_cast<std::size_t>(sqlite3_column_bytes(cursor_, 2));
    if (compression_ == Compression::None) {
      out.data.assign(blob, blob + n);
    } else {
      try {
        Codec::decompressFrame(compression_, blob, n, kMaxMessageSize, out.data);
      } catch (const std::exception& e) {
        fail("message at " + std::to_string(out.log_time) + " ns on " + out.topic +
             " does not decompress: " + e.what());
      }
    }
    return true;
  }
}

FileStatistics SqliteReader::statistics() const {
  FileStatistics s;
  for (const auto& t : topics_) s.topic_message_counts[t.name] += 0;
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_,
                         "SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) FROM messages "
                         "GROUP BY topic_id;",
                         -1, &st, nullptr) != SQLITE_OK) {
    fail(sqlite3_errmsg(db_));
  }
  int rc;
  while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
    const long long id = sqlite3_column_int64(st, 0);
    const auto n = static_cast<std::uint64_t>(sqlite3_column_int64(st, 1));
    const Timestamp lo = sqlite3_column_int64(st, 2);
    const Timestamp hi = sqlite3_column_int64(st, 3);
    std::string name;
    for (std::size_t i = 0; i < topic_ids_.size(); ++i) {
      if (topic_ids_[i] == id) name = topics_[i].name;
    }
    if (name.empty()) {
      sqlite3_finalize(st);
      fail("messages refer to unknown topic id " + std::to_string(id));
    }
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
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
  return s;
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

void SqliteReader::recover(const std::filesystem::path& path) {
  checkMagic(path);
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    const std::string why = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw InputError(path.string() + ": cannot open sqlite3 database: " + why);
  }
  char* err = nullptr;
  const int rc = sqlite3_exec(db,
                              "PRAGMA wal_checkpoint(TRUNCATE); PRAGMA journal_mode=DELETE;"
                              "PRAGMA quick_check;",
                              nullptr, nullptr, &err);
  const std::string why = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  if (rc != SQLITE_OK) throw InputError(path.string() + ": sqlite3 recovery failed: " + why);
}

}  // namespace mcvio::bag
