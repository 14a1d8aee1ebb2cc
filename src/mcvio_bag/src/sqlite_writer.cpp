#include "mcvio/bag/sqlite_writer.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <stdexcept>

namespace mcvio::bag {

namespace {

const char* kCreateSchema =
    "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
    "CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL,"
    " metadata TEXT NOT NULL);"
    "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
    " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL,"
    " type_description_hash TEXT NOT NULL);"
    "CREATE TABLE message_definitions(id INTEGER PRIMARY KEY, topic_type TEXT NOT NULL,"
    " encoding TEXT NOT NULL, encoded_message_definition TEXT NOT NULL,"
    " type_description_hash TEXT NOT NULL);"
    "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
    " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
    "CREATE INDEX timestamp_idx ON messages (timestamp ASC);";

/// Runs one statement with bound text parameters.
void execBound(sqlite3* db, const char* sql, const std::vector<std::string>& args,
               const std::string& where) {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &st, nullptr) != SQLITE_OK) {
    throw std::runtime_error(where + ": sqlite: " + sqlite3_errmsg(db));
  }
  for (std::size_t i = 0; i < args.size(); ++i) {
    sqlite3_bind_text(st, static_cast<int>(i + 1), args[i].data(), static_cast<int>(args[i].size()),
                      SQLITE_TRANSIENT);
  }
  const int rc = sqlite3_step(st);
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) throw std::runtime_error(where + ": sqlite: " + sqlite3_errmsg(db));
}

}  // namespace

SqliteWriter::SqliteWriter(const std::filesystem::path& path, SqliteWriterOptions options)
    : path_(path), options_(std::move(options)) {
  if (std::filesystem::exists(path)) fail("file exists already");
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw std::runtime_error(path.string() + ": cannot create sqlite3 file: " + why);
  }
  exec("PRAGMA journal_mode=WAL;");
  exec(options_.fsync_each_transaction ? "PRAGMA synchronous=FULL;" : "PRAGMA synchronous=NORMAL;");
  exec(std::string("BEGIN;") + kCreateSchema + "COMMIT;");
  execBound(db_, "INSERT INTO schema(schema_version, ros_distro) VALUES (4, ?);",
            {options_.ros_distro}, path_.string());
  if (sqlite3_prepare_v2(db_, "INSERT INTO messages(topic_id, timestamp, data) VALUES (?, ?, ?);",
                         -1, &insert_, nullptr) != SQLITE_OK) {
    fail(sqlite3_errmsg(db_));
  }
}

SqliteWriter::~SqliteWriter() {
  try {
    close();
  } catch (...) {
    // Destructors must not throw; call close() to see errors.
  }
}

void SqliteWriter::fail(const std::string& what) const {
  throw std::runtime_error(path_.string() + ": sqlite: " + what);
}

void SqliteWriter::exec(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string why = err ? err : "unknown error";
    sqlite3_free(err);
    fail(why);
  }
}

void SqliteWriter::addTopic(std::size_t topic_index, const TopicInfo& topic) {
  if (!db_) throw std::logic_error("SqliteWriter::addTopic after close");
  flush();
  execBound(db_,
            ("INSERT INTO topics(id, name, type, serialization_format, offered_qos_profiles,"
             " type_description_hash) VALUES (" +
             std::to_string(topic_index + 1) + ", ?, ?, ?, ?, ?);")
                .c_str(),
            {topic.name, topic.type, topic.serialization_format, topic.offered_qos_profiles,
             topic.type_description_hash},
            path_.string());
  if (std::find(known_types_.begin(), known_types_.end(), topic.type) == known_types_.end()) {
    known_types_.push_back(topic.type);
    execBound(db_,
              "INSERT INTO message_definitions(topic_type, encoding, encoded_message_definition,"
              " type_description_hash) VALUES (?, 'ros2msg', ?, ?);",
              {topic.type, topic.message_definition, topic.type_description_hash}, path_.string());
  }
}

void SqliteWriter::write(std::size_t topic_index, Timestamp log_time, Timestamp /*publish_time*/,
                         std::uint32_t /*sequence*/, const std::uint8_t* data, std::size_t size) {
  if (!db_) throw std::logic_error("SqliteWriter::write after close");
  if (!in_transaction_) {
    exec("BEGIN;");
    in_transaction_ = true;
  }
  const void* blob = data;
  std::size_t blob_size = size;
  if (options_.compression != Compression::None) {
    compressed_.clear();
    Codec::compress(options_.compression, data, size, options_.compression_level, compressed_);
    blob = compressed_.data();
    blob_size = compressed_.size();
  }
  sqlite3_bind_int64(insert_, 1, static_cast<sqlite3_int64>(topic_index + 1));
  sqlite3_bind_int64(insert_, 2, log_time);
  sqlite3_bind_blob64(insert_, 3, blob_size ? blob : "", blob_size, SQLITE_STATIC);
  const int rc = sqlite3_step(insert_);
  sqlite3_reset(insert_);
  sqlite3_clear_bindings(insert_);
  if (rc != SQLITE_DONE) fail(sqlite3_errmsg(db_));
  pending_bytes_ += blob_size + 32;
  if (pending_bytes_ >= options_.transaction_size) flush();
}

void SqliteWriter::flush() {
  if (!db_ || !in_transaction_) return;
  exec("COMMIT;");
  in_transaction_ = false;
  written_bytes_ += pending_bytes_;
  pending_bytes_ = 0;
}

std::uint64_t SqliteWriter::sizeBytes() const { return written_bytes_ + pending_bytes_; }

void SqliteWriter::setMetadataYaml(const std::string& yaml) { metadata_yaml_ = yaml; }

void SqliteWriter::close() {
  if (!db_) return;
  flush();
  if (insert_) sqlite3_finalize(insert_);
  insert_ = nullptr;
  if (!metadata_yaml_.empty()) {
    exec("DELETE FROM metadata;");
    execBound(db_, "INSERT INTO metadata(metadata_version, metadata) VALUES (8, ?);",
              {metadata_yaml_}, path_.string());
  }
  // Back to a single self-contained file, as rosbag2 leaves it.
  exec("PRAGMA wal_checkpoint(TRUNCATE);");
  exec("PRAGMA journal_mode=DELETE;");
  sqlite3* db = db_;
  db_ = nullptr;
  if (sqlite3_close(db) != SQLITE_OK) fail("cannot close");
}

}  // namespace mcvio::bag
