#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstring>
#include <fstream>

#include "bag_test_util.hpp"
#include "mcvio/bag/bag_info.hpp"
#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/bag/bag_reindexer.hpp"
#include "mcvio/bag/bag_writer.hpp"
#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/bag/mcap_writer.hpp"
#include "mcvio/bag/sqlite_reader.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {
namespace {

/// Runs `f`, expects an InputError whose message contains every one of `parts`.
template <typename F>
void expectInputError(F&& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    for (const auto& p : parts) {
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos)
          << "'" << p << "' not in: " << e.what();
    }
  }
}

std::filesystem::path smallBag(const std::string& name, const std::string& storage,
                               Compression c = Compression::None) {
  const auto dir = test::freshPath(name);
  BagWriterOptions o;
  o.storage = storage;
  o.compression = c;
  o.chunk_size = 1024;
  BagWriter w(dir, o);
  w.addTopic(test::stringTopic("/a"));
  for (int i = 0; i < 40; ++i) {
    const auto d = test::payload(static_cast<std::uint64_t>(i), 300);
    w.write("/a", 1000 + i, 1000 + i, d.data(), d.size());
  }
  return dir;
}

std::vector<std::uint8_t> slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::filesystem::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

TEST(BadInput, MissingMetadataYaml) {
  const auto dir = smallBag("bad_no_metadata", "mcap");
  std::filesystem::remove(dir / "metadata.yaml");
  expectInputError([&] { BagReader r(dir); }, {"metadata.yaml", "missing"});
}

TEST(BadInput, MissingBag) {
  expectInputError([&] { BagReader r(test::freshPath("nothing_here")); }, {"nothing_here"});
}

TEST(BadInput, UnknownStorage) {
  const auto dir = smallBag("bad_storage", "mcap");
  BagMetadata md = readBagMetadata(dir);
  md.storage_identifier = "rosbag_v2";
  writeBagMetadata(dir, md);
  expectInputError([&] { BagReader r(dir); },
                   {"metadata.yaml", "unknown storage_identifier 'rosbag_v2'"});
}

TEST(BadInput, MalformedMetadataYaml) {
  const auto dir = smallBag("bad_yaml", "mcap");
  std::ofstream(dir / "metadata.yaml")
      << "rosbag2_bagfile_information:\n  version: 8\n  storage_identifier: [\n";
  expectInputError([&] { BagReader r(dir); }, {"metadata.yaml", "line"});
  std::ofstream(dir / "metadata.yaml") << "rosbag2_bagfile_information:\n  version: 8\n";
  expectInputError([&] { BagReader r(dir); }, {"metadata.yaml", "storage_identifier"});
}

TEST(BadInput, StorageFileListedButMissing) {
  const auto dir = smallBag("bad_missing_file", "mcap");
  std::filesystem::remove(dir / "bad_missing_file_0.mcap");
  expectInputError([&] { BagReader r(dir); }, {"bad_missing_file_0.mcap", "missing"});
}

TEST(BadInput, WrongMagic) {
  const auto dir = smallBag("bad_magic", "mcap");
  const auto f = dir / "bad_magic_0.mcap";
  auto b = slurp(f);
  b[1] = 'X';
  spit(f, b);
  expectInputError([&] { BagReader r(dir); }, {"bad_magic_0.mcap", "wrong magic", "byte offset 0"});
  expectInputError([&] { BagReindexer::reindex(dir); }, {"bad_magic_0.mcap", "wrong magic"});
}

TEST(BadInput, TruncatedMcap) {
  const auto dir = smallBag("bad_truncated", "mcap");
  const auto f = dir / "bad_truncated_0.mcap";
  std::filesystem::resize_file(f, std::filesystem::file_size(f) / 2);
  expectInputError([&] { BagReader r(dir); }, {"bad_truncated_0.mcap", "truncated", "byte offset"});
  std::filesystem::resize_file(f, 5);
  expectInputError([&] { BagReader r(dir); }, {"bad_truncated_0.mcap", "byte offset 0"});
}

TEST(BadInput, BadChunkCrc) {
  const auto dir = smallBag("bad_crc", "mcap");
  const auto f = dir / "bad_crc_0.mcap";
  McapReader good(f);
  const auto chunk = good.chunks().at(1);
  auto b = slurp(f);
  b[chunk.records_offset + 40] ^= 0x5A;  // a payload byte of an uncompressed chunk
  spit(f, b);
  expectInputError(
      [&] { test::readAll(dir); },
      {"bad_crc_0.mcap", "bad CRC", "byte offset " + std::to_string(chunk.start_offset)});
}

TEST(BadInput, CorruptCompressedChunk) {
  const auto dir = smallBag("bad_zstd", "mcap", Compression::Zstd);
  const auto f = dir / "bad_zstd_0.mcap";
  McapReader good(f);
  const auto chunk = good.chunks().at(0);
  auto b = slurp(f);
  for (std::uint64_t i = 0; i < 8; ++i) b[chunk.records_offset + i] ^= 0xFF;
  spit(f, b);
  expectInputError([&] { test::readAll(dir); },
                   {"bad_zstd_0.mcap", "does not decompress",
                    "byte offset " + std::to_string(chunk.start_offset)});
}

TEST(BadInput, BadSummaryCrc) {
  const auto dir = smallBag("bad_summary", "mcap");
  const auto f = dir / "bad_summary_0.mcap";
  auto b = slurp(f);
  b[b.size() - 60] ^= 0x01;  // inside the summary offsets
  spit(f, b);
  expectInputError([&] { BagReader r(dir); },
                   {"bad_summary_0.mcap", "bad summary CRC", "byte offset"});
}

TEST(BadInput, SchemaThatDoesNotParse) {
  const auto dir = test::freshPath("bad_schema");
  std::filesystem::create_directories(dir);
  {
    McapWriter w(dir / "bad_schema_0.mcap");
    TopicInfo t = test::poseStampedTopic("/pose");
    // Drop the nested Point definition: the schema no longer describes a decodable type.
    const auto at = t.message_definition.find("MSG: geometry_msgs/Point");
    t.message_definition = t.message_definition.substr(0, at - 81);
    w.addTopic(0, t);
    const std::uint8_t d[4] = {0, 1, 0, 0};
    w.write(0, 1, 1, 0, d, 4);
    w.close();
  }
  expectInputError(
      [&] { McapReader r(dir / "bad_schema_0.mcap"); },
      {"bad_schema_0.mcap", "schema does not parse", "geometry_msgs/Point", "byte offset"});
  // The writer refuses it up front.
  BagWriter w(test::freshPath("bad_schema_writer"));
  TopicInfo t = test::stringTopic("/x");
  t.message_definition = "string[ data\n";
  expectInputError([&] { w.addTopic(t); }, {"/x", "line 1"});
}

TEST(BadInput, SqliteGarbageAndWrongSchema) {
  const auto dir = smallBag("bad_sqlite", "sqlite3");
  const auto f = dir / "bad_sqlite_0.db3";
  auto b = slurp(f);
  auto garbage = b;
  garbage[3] = 'X';
  spit(f, garbage);
  expectInputError([&] { BagReader r(dir); }, {"bad_sqlite_0.db3", "wrong magic", "byte offset 0"});
  // A valid sqlite3 database that is not a rosbag2 file.
  std::filesystem::remove(f);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(f.c_str(), &db), SQLITE_OK);
  sqlite3_exec(db, "CREATE TABLE foo(x INTEGER);", nullptr, nullptr, nullptr);
  sqlite3_close(db);
  expectInputError([&] { BagReader r(dir); }, {"bad_sqlite_0.db3", "not a rosbag2 sqlite3 file"});
}

TEST(BadInput, SqliteCorruptPages) {
  const auto dir = smallBag("bad_sqlite_pages", "sqlite3");
  const auto f = dir / "bad_sqlite_pages_0.db3";
  auto b = slurp(f);
  ASSERT_GT(b.size(), 8192u);
  for (std::size_t i = 4096; i < b.size(); i += 7) b[i] = static_cast<std::uint8_t>(i * 31);
  spit(f, b);
  expectInputError([&] { test::readAll(dir); }, {"bad_sqlite_pages_0.db3", "sqlite3"});
}

TEST(BadInput, ReindexWithoutStorageFiles) {
  const auto dir = test::freshPath("bad_empty_dir");
  std::filesystem::create_directories(dir);
  expectInputError([&] { BagReindexer::reindex(dir); }, {"bad_empty_dir", "no .mcap or .db3"});
}

}  // namespace
}  // namespace mcvio::bag

namespace mcvio::bag {
namespace {

// Regression for a fuzzer finding: a Chunk claiming a huge uncompressed size made the reader
// allocate it before looking at the data.
TEST(BadInput, ForgedChunkSizeIsRejectedBeforeAllocating) {
  for (Compression c : {Compression::Zstd, Compression::Lz4}) {
    const auto dir = test::freshPath("bad_forged_" + toString(c));
    {
      BagWriterOptions o;
      o.compression = c;
      BagWriter w(dir, o);
      w.addTopic(test::stringTopic("/a"));
      const auto d = test::payload(1, 500);
      w.write("/a", 1, 1, d.data(), d.size());
    }
    const auto f = dir / (dir.filename().string() + "_0.mcap");
    const auto chunk = McapReader(f).chunks().at(0);
    std::ifstream in(f, std::ios::binary);
    std::vector<char> b{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const std::uint64_t huge = 3ull << 30;
    std::memcpy(b.data() + chunk.start_offset + 9 + 16, &huge, 8);  // uncompressed_size
    std::memset(b.data() + b.size() - 37 + 9, 0, 8);  // footer: no summary -> linear scan
    std::ofstream(f, std::ios::binary | std::ios::trunc)
        .write(b.data(), static_cast<std::streamsize>(b.size()));
    try {
      McapReader r(f);
      ADD_FAILURE() << "forged chunk accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("does not decompress"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte offset " + std::to_string(chunk.start_offset)),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace mcvio::bag

namespace mcvio::bag {
namespace {

/// Joins warnings for assertion messages.
std::string joined(const std::vector<std::string>& w) {
  std::string s;
  for (const auto& l : w) s += l + "\n";
  return s;
}

bool anyHas(const std::vector<std::string>& w, const std::vector<std::string>& parts) {
  for (const auto& l : w) {
    bool all = true;
    for (const auto& p : parts) all &= l.find(p) != std::string::npos;
    if (all) return true;
  }
  return false;
}

/// bag info used to read metadata.yaml alone: an emptied or cut data file still showed every
/// message. It must name the file.
TEST(BagInfoChecks, EmptyOrTruncatedDataFileIsReported) {
  for (const bool empty : {true, false}) {
    const auto dir = smallBag(empty ? "info_empty" : "info_cut", "mcap");
    const auto file = dir / readBagMetadata(dir).relative_file_paths.at(0);
    std::filesystem::resize_file(file, empty ? 0 : std::filesystem::file_size(file) / 2);
    std::vector<std::string> w;
    bagInfo(dir, &w);
    EXPECT_TRUE(anyHas(w, {file.string()})) << joined(w);
  }
  const auto dir = smallBag("info_ok", "mcap");
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(w.empty()) << joined(w);
}

/// metadata.yaml that disagrees with the MCAP summary: counts, types, serialization format,
/// negative duration, unknown version. Reading the bag warns about the type too.
TEST(BagInfoChecks, MetadataDisagreeingWithTheStorageIsReported) {
  const auto dir = smallBag("info_disagree", "mcap");
  BagMetadata m = readBagMetadata(dir);
  ASSERT_FALSE(m.topics_with_message_count.empty());
  auto& t = m.topics_with_message_count[0];
  const std::string topic = t.topic.name;
  const std::string real_type = t.topic.type;
  t.topic.type = "sensor_msgs/msg/Imu";
  t.topic.serialization_format = "json";
  t.message_count += 7;
  m.message_count += 7;
  m.duration = -5;
  m.version = 12;
  writeBagMetadata(dir, m);
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(anyHas(w, {topic, "sensor_msgs/msg/Imu", real_type})) << joined(w);
  EXPECT_TRUE(anyHas(w, {topic, "json"})) << joined(w);
  EXPECT_TRUE(anyHas(w, {topic, std::to_string(t.message_count)})) << joined(w);
  EXPECT_TRUE(anyHas(w, {"message_count", std::to_string(m.message_count)})) << joined(w);
  EXPECT_TRUE(anyHas(w, {"negative duration"})) << joined(w);
  EXPECT_TRUE(anyHas(w, {"version 12"})) << joined(w);
  BagReader r(dir);
  EXPECT_TRUE(anyHas(r.warnings(), {topic, "sensor_msgs/msg/Imu", real_type})) << joined(r.warnings());
}

/// The help says a single .mcap file is accepted: its summary describes it.
TEST(BagInfoChecks, SingleMcapFileIsDescribedFromItsSummary) {
  const auto dir = smallBag("info_single", "mcap");
  const BagMetadata m = readBagMetadata(dir);
  const auto file = dir / m.relative_file_paths.at(0);
  std::filesystem::remove(dir / kMetadataFileName);
  std::vector<std::string> w;
  const std::string info = bagInfo(file, &w);
  EXPECT_TRUE(w.empty()) << joined(w);
  EXPECT_NE(info.find("Messages:          " + std::to_string(m.message_count)), std::string::npos)
      << info;
  EXPECT_NE(info.find("Topic: " + m.topics_with_message_count[0].topic.name), std::string::npos)
      << info;
}

}  // namespace
}  // namespace mcvio::bag

namespace mcvio::bag {
namespace {

/// A bag folder whose metadata.yaml is lost is still a bag (play/run used to call it "not a
/// EuRoC folder"); reading it names metadata.yaml and `mcvio bag reindex`.
TEST(BagFolder, WithoutMetadataIsABagThatNeedsReindex) {
  const auto dir = smallBag("no_metadata_folder", "mcap");
  std::filesystem::remove(dir / kMetadataFileName);
  EXPECT_TRUE(BagReader::looksLikeBag(dir));
  expectInputError([&] { BagReader r(dir); },
                   {"metadata.yaml", "mcvio bag reindex " + dir.string()});
  const auto plain = test::freshPath("plain_folder");
  std::filesystem::create_directories(plain / "mav0");
  EXPECT_FALSE(BagReader::looksLikeBag(plain));
}

/// Decode errors of a bag message must name the storage file, topic and log time.
TEST(BagFolder, WhereNamesFileTopicAndTime) {
  const auto dir = smallBag("where_bag", "mcap");
  const auto file = dir / readBagMetadata(dir).relative_file_paths.at(0);
  BagReader r(dir);
  BagMessage m;
  ASSERT_TRUE(r.next(m));
  ASSERT_TRUE(r.next(m));
  const std::string w = r.where(m);
  EXPECT_NE(w.find(file.string()), std::string::npos) << w;
  EXPECT_NE(w.find("topic /a"), std::string::npos) << w;
  EXPECT_NE(w.find("log time 1001 ns"), std::string::npos) << w;
}

}  // namespace
}  // namespace mcvio::bag

namespace mcvio::bag {
namespace {

// sqlite3 storage fed with damaged or forged files: each case must be an InputError (or a
// warning) naming the file and the topic/row/field, and no committed data may be dropped.

/// Runs SQL on a .db3 outside the library (the damage a test wants).
void sqlExec(const std::filesystem::path& db3, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db3.c_str(), &db), SQLITE_OK);
  char* err = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err);
  const std::string why = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << why << " in " << sql;
}

std::filesystem::path sqliteFile(const std::filesystem::path& dir) {
  return dir / readBagMetadata(dir).relative_file_paths.at(0);
}

/// The messages table without NOT NULL, so rows can hold NULLs as a foreign tool may write.
void loosenMessages(const std::filesystem::path& db3) {
  sqlExec(db3,
          "CREATE TABLE m2(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, data BLOB);"
          "INSERT INTO m2 SELECT id, topic_id, timestamp, data FROM messages; DROP TABLE messages;"
          "ALTER TABLE m2 RENAME TO messages;"
          "CREATE INDEX timestamp_idx ON messages (timestamp ASC);");
}

/// A writer killed before its first checkpoint on a file system that lost the .db3's pages:
/// an empty .db3 beside a -wal holding everything. sqlite deletes such a log when it opens the
/// file; reading must not, and reindex must recover every message from it.
TEST(SqliteBadInput, EmptyFileWithWriteAheadLogKeepsTheLog) {
  const auto dir = smallBag("sqlite_wal_only", "sqlite3");
  const auto f = sqliteFile(dir);
  const auto full = dir / "full.tmp";
  std::filesystem::rename(f, full);
  std::filesystem::path wal = f;
  wal += "-wal";
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(f.c_str(), &db), SQLITE_OK);
    const std::string attach = "ATTACH '" + full.string() + "' AS src;";
    ASSERT_EQ(sqlite3_exec(db,
                           ("PRAGMA journal_mode=WAL; PRAGMA wal_autocheckpoint=0;" + attach +
                            "CREATE TABLE topics AS SELECT * FROM src.topics;"
                            "CREATE TABLE message_definitions AS SELECT * FROM "
                            "src.message_definitions;"
                            "CREATE TABLE messages AS SELECT * FROM src.messages; DETACH src;")
                               .c_str(),
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    // The state a kill -9 leaves: the log as it is now, the .db3 empty.
    std::filesystem::copy_file(wal, dir / "wal.tmp");
    sqlite3_close(db);
  }
  std::filesystem::remove(full);
  std::filesystem::resize_file(f, 0);
  std::filesystem::rename(dir / "wal.tmp", wal);
  const auto wal_size = std::filesystem::file_size(wal);
  ASSERT_GT(wal_size, 12000u);
  expectInputError([&] { BagReader r(dir); }, {f.string(), "write-ahead log", "reindex"});
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(anyHas(w, {f.string(), "write-ahead log"})) << joined(w);
  ASSERT_TRUE(std::filesystem::exists(wal)) << "the log was deleted";
  EXPECT_EQ(std::filesystem::file_size(wal), wal_size);
  std::vector<std::string> log;
  const BagMetadata m = BagReindexer::reindex(dir, &log);
  EXPECT_EQ(m.message_count, 40u) << joined(log);
  EXPECT_EQ(test::readAll(dir).size(), 40u);
}

/// Rows whose topic_id names no topic used to be skipped without a word when a topic filter
/// was set (mcvio run reads three topics): they may be lost messages of those topics.
TEST(SqliteBadInput, RowsOfAnUnknownTopicAreAnErrorAlsoWithAFilter) {
  for (const std::string bad : {"99", "NULL", "'six'"}) {
    const auto dir = smallBag("sqlite_unknown_topic", "sqlite3");
    const auto f = sqliteFile(dir);
    loosenMessages(f);
    sqlExec(f, "UPDATE messages SET topic_id=" + bad + " WHERE id=5;");
    BagReaderOptions o;
    o.topics = {"/a"};
    expectInputError(
        [&] {
          BagReader r(dir, o);
          BagMessage m;
          while (r.next(m)) {
          }
        },
        {f.string(), "messages row id 5"});
    std::vector<std::string> w;
    bagInfo(dir, &w);
    EXPECT_TRUE(anyHas(w, {f.string(), "topic"})) << joined(w);
  }
}

/// Timestamps that are NULL, TEXT, REAL or negative used to come back as 0 or as given (play
/// then slept for decades or mis-timed everything); they name the row, topic and value now.
TEST(SqliteBadInput, TimestampsThatAreNotNonNegativeIntegers) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"NULL", "timestamp is NULL"},
      {"'abc'", "timestamp is TEXT"},
      {"1000.5", "timestamp is a REAL"},
      {"-7", "negative timestamp -7"}};
  for (const auto& [value, expected] : cases) {
    const auto dir = smallBag("sqlite_bad_time", "sqlite3");
    const auto f = sqliteFile(dir);
    loosenMessages(f);
    sqlExec(f, "UPDATE messages SET timestamp=" + value + " WHERE id=7;");
    expectInputError([&] { test::readAll(dir); },
                     {f.string(), "messages row id 7 on /a", expected});
    std::vector<std::string> w;
    bagInfo(dir, &w);
    EXPECT_TRUE(anyHas(w, {f.string(), "/a", "timestamp"})) << value << ": " << joined(w);
    expectInputError([&] { BagReindexer::reindex(dir); }, {f.string(), "timestamp"});
  }
}

/// NULL or TEXT data used to reach the player and decoder as an empty or foreign payload.
TEST(SqliteBadInput, DataThatIsNotABlob) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"NULL", "data is NULL"}, {"'hello'", "data is TEXT"}, {"42", "data is an INTEGER"}};
  for (const auto& [value, expected] : cases) {
    const auto dir = smallBag("sqlite_bad_data", "sqlite3");
    const auto f = sqliteFile(dir);
    loosenMessages(f);
    sqlExec(f, "UPDATE messages SET data=" + value + " WHERE id=9;");
    expectInputError([&] { test::readAll(dir); },
                     {f.string(), "messages row id 9 on /a", expected});
    std::vector<std::string> w;
    bagInfo(dir, &w);
    EXPECT_TRUE(anyHas(w, {f.string(), "not a BLOB", "row id 9"})) << joined(w);
  }
}

/// A topic name declared twice with two types made the second id's messages go out under the
/// first type; an empty type reached the player's type mapping without a file name.
TEST(SqliteBadInput, TopicsRowsThatCannotBeRead) {
  const auto dir = smallBag("sqlite_dup_topic", "sqlite3");
  const auto f = sqliteFile(dir);
  sqlExec(f,
          "INSERT INTO topics SELECT 7, name, type, serialization_format, offered_qos_profiles,"
          " type_description_hash FROM topics WHERE id=1;"
          "UPDATE messages SET topic_id=7 WHERE id<=10;");
  // Same name and type: one topic with all its messages.
  const auto all = test::readAll(dir);
  EXPECT_EQ(all.size(), 40u);
  EXPECT_EQ(BagReader(dir).topics().size(), 1u);
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(w.empty()) << joined(w);
  sqlExec(f, "UPDATE topics SET type='sensor_msgs/msg/Imu' WHERE id=7;");
  expectInputError([&] { BagReader r(dir); },
                   {f.string(), "topic /a", "std_msgs/msg/String", "sensor_msgs/msg/Imu"});
  sqlExec(f, "DELETE FROM topics WHERE id=7; UPDATE messages SET topic_id=1;"
             "UPDATE topics SET type='' WHERE id=1;");
  expectInputError([&] { BagReader r(dir); }, {f.string(), "topic /a", "empty type"});
}

/// Files without offered_qos_profiles (rosbag2 before Foxy) are read; a missing required
/// column names its table.
TEST(SqliteBadInput, OldAndBrokenTableLayouts) {
  const auto dir = smallBag("sqlite_old_layout", "sqlite3");
  const auto f = sqliteFile(dir);
  sqlExec(f,
          "CREATE TABLE t2(id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT);"
          "INSERT INTO t2 SELECT id, name, type, serialization_format FROM topics;"
          "DROP TABLE topics; ALTER TABLE t2 RENAME TO topics;");
  EXPECT_EQ(test::readAll(dir).size(), 40u);
  sqlExec(f,
          "CREATE TABLE m2(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER);"
          "INSERT INTO m2 SELECT id, topic_id, timestamp FROM messages;"
          "DROP TABLE messages; ALTER TABLE m2 RENAME TO messages;");
  expectInputError([&] { BagReader r(dir); }, {f.string(), "table messages has no column data"});
}

/// An unknown schema version or a serialization format other than CDR is read, with a
/// warning naming the file (and topic) for play, run and bag info.
TEST(SqliteBadInput, UnknownSchemaVersionAndSerializationWarn) {
  const auto dir = smallBag("sqlite_schema_99", "sqlite3");
  const auto f = sqliteFile(dir);
  sqlExec(f, "UPDATE schema SET schema_version=99; UPDATE topics SET serialization_format='json';");
  BagReader r(dir);
  EXPECT_TRUE(anyHas(r.warnings(), {f.string(), "schema_version 99"})) << joined(r.warnings());
  EXPECT_TRUE(anyHas(r.warnings(), {f.string(), "topic /a", "'json'"})) << joined(r.warnings());
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(anyHas(w, {f.string(), "schema_version 99"})) << joined(w);
  EXPECT_TRUE(anyHas(w, {f.string(), "topic /a", "'json'"})) << joined(w);
}

/// metadata.yaml naming the other storage: bag info used to open the file by its extension and
/// report nothing (or message counts of 0).
TEST(SqliteBadInput, StorageOfTheOtherKind) {
  const auto dir = smallBag("sqlite_says_mcap", "sqlite3");
  const auto f = sqliteFile(dir);
  BagMetadata m = readBagMetadata(dir);
  m.storage_identifier = "mcap";
  writeBagMetadata(dir, m);
  expectInputError([&] { BagReader r(dir); }, {f.string(), "is an sqlite3 database", "mcap"});
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(anyHas(w, {f.string(), "is an sqlite3 database"})) << joined(w);
  // An MCAP file under a .db3 name.
  const auto mcap_dir = smallBag("sqlite_is_mcap", "mcap");
  std::filesystem::remove(f);
  std::filesystem::copy_file(sqliteFile(mcap_dir), f);
  m.storage_identifier = "sqlite3";
  writeBagMetadata(dir, m);
  expectInputError([&] { BagReader r(dir); }, {f.string(), "is an MCAP file"});
}

/// Message compression that metadata.yaml gets wrong: zstd frames read as plain CDR used to
/// reach the decoder as nonsense, and bag info said nothing about any of these.
TEST(SqliteBadInput, MessageCompressionThatMetadataGetsWrong) {
  const auto dir = smallBag("sqlite_zstd", "sqlite3", Compression::Zstd);
  const auto f = sqliteFile(dir);
  BagMetadata m = readBagMetadata(dir);
  ASSERT_EQ(m.compression_mode, "MESSAGE");
  m.compression_mode = "";
  m.compression_format = "";
  writeBagMetadata(dir, m);
  expectInputError([&] { test::readAll(dir); }, {f.string(), "/a", "zstd frame"});
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(anyHas(w, {f.string(), "zstd frame"})) << joined(w);
  m.compression_mode = "MESSAGE";
  m.compression_format = "bz2";
  writeBagMetadata(dir, m);
  w.clear();
  bagInfo(dir, &w);
  EXPECT_TRUE(anyHas(w, {"metadata.yaml", "compression_format", "bz2"})) << joined(w);
  // reindex takes the compression from the messages, whatever metadata.yaml said.
  for (const std::string said : {"bz2", "", "lz4"}) {
    m.compression_mode = said.empty() ? "" : "MESSAGE";
    m.compression_format = said;
    writeBagMetadata(dir, m);
    std::vector<std::string> log;
    BagReindexer::reindex(dir, &log);
    EXPECT_TRUE(anyHas(log, {"WARNING", "the messages are zstd"})) << said << ": " << joined(log);
    EXPECT_EQ(readBagMetadata(dir).compression_format, "zstd");
    EXPECT_EQ(test::readAll(dir).size(), 40u);
  }
  // A plain bag whose metadata.yaml claims zstd gets "none" back.
  const auto plain = smallBag("sqlite_plain_said_zstd", "sqlite3");
  BagMetadata pm = readBagMetadata(plain);
  pm.compression_mode = "MESSAGE";
  pm.compression_format = "zstd";
  writeBagMetadata(plain, pm);
  std::vector<std::string> log;
  BagReindexer::reindex(plain, &log);
  EXPECT_TRUE(anyHas(log, {"the messages are none"})) << joined(log);
  EXPECT_EQ(readBagMetadata(plain).compression_mode, "");
  EXPECT_EQ(test::readAll(plain).size(), 40u);
}

/// A hot rollback journal (a killed writer in rollback mode) made every reader fail with
/// "attempt to write a readonly database".
TEST(SqliteBadInput, LeftoverRollbackJournal) {
  const auto dir = smallBag("sqlite_journal", "sqlite3");
  const auto f = sqliteFile(dir);
  std::filesystem::path journal = f;
  journal += "-journal";
  spit(journal, test::payload(3, 3000));
  EXPECT_EQ(test::readAll(dir).size(), 40u);
}

/// bag info: a topic only the storage knows, and a files entry whose count disagrees.
TEST(SqliteBadInput, InfoReportsTopicsAndFileCountsMetadataLacks) {
  const auto dir = smallBag("sqlite_info_extra", "sqlite3");
  const auto f = sqliteFile(dir);
  sqlExec(f,
          "INSERT INTO topics SELECT 2, '/extra', type, serialization_format, offered_qos_profiles,"
          " type_description_hash FROM topics WHERE id=1;"
          "INSERT INTO messages(topic_id, timestamp, data) SELECT 2, timestamp, data FROM messages"
          " WHERE id<=3;");
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(anyHas(w, {"topic /extra", "not in metadata.yaml"})) << joined(w);
  EXPECT_TRUE(anyHas(w, {"files entry", f.filename().string(), "43"})) << joined(w);
}

/// reindex used to call any .db3 fine after folding its log in (quick_check's answer was
/// ignored) and dropped files the old metadata.yaml listed without a word.
TEST(SqliteBadInput, ReindexReportsADamagedFileAndLostFiles) {
  const auto dir = smallBag("sqlite_reindex_damage", "sqlite3");
  const auto f = sqliteFile(dir);
  BagMetadata m = readBagMetadata(dir);
  m.relative_file_paths.push_back("gone_1.db3");
  writeBagMetadata(dir, m);
  std::vector<std::string> log;
  BagReindexer::reindex(dir, &log);
  EXPECT_TRUE(anyHas(log, {"gone_1.db3", "left out"})) << joined(log);
  EXPECT_TRUE(anyHas(log, {f.filename().string(), "intact"})) << joined(log);
  // Damage the timestamp index only: counting still works, reading in time order does not.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(f.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT rootpage FROM sqlite_master WHERE name='timestamp_idx';",
                               -1, &st, nullptr),
            SQLITE_OK);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  const int root = sqlite3_column_int(st, 0);
  sqlite3_finalize(st);
  ASSERT_EQ(sqlite3_prepare_v2(db, "PRAGMA page_size;", -1, &st, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  const int page = sqlite3_column_int(st, 0);
  sqlite3_finalize(st);
  sqlite3_close(db);
  auto b = slurp(f);
  for (int i = 8; i < page; ++i) b[static_cast<std::size_t>((root - 1) * page + i)] = 0xA5;
  spit(f, b);
  expectInputError([&] { BagReindexer::reindex(dir); }, {f.string(), "integrity check failed"});
}

}  // namespace
}  // namespace mcvio::bag

namespace mcvio::bag {
namespace {

/// `bag info` decompresses only the first message of an sqlite3 file: a damaged payload further
/// on passed it, and play or run failed later. `bag info --verify` reads every row: it counts
/// the damaged one under its topic and names its row id, says reindex cannot recover it, and
/// leaves the file as it was.
TEST(SqliteBadInput, VerifyFindsADamagedMessageInTheMiddle) {
  for (const Compression c : {Compression::Zstd, Compression::Lz4}) {
    SCOPED_TRACE(toString(c));
    const auto dir = smallBag("sqlite_verify_" + toString(c), "sqlite3", c);
    const auto f = sqliteFile(dir);
    std::vector<std::string> w;
    BagInfoOptions verify;
    verify.verify = true;
    const std::string text = bagInfo(dir, &w, verify);
    EXPECT_TRUE(w.empty()) << joined(w);
    EXPECT_NE(text.find("Verified:          40 messages read intact, 0 unreadable"),
              std::string::npos)
        << text;
    // Row 20 of 40 loses the second half of its compressed frame.
    sqlExec(f, "UPDATE messages SET data=substr(data, 1, length(data) / 2) WHERE id=20;");
    const auto before = slurp(f);
    w.clear();
    const BagVerification v = test::verifyBag(dir, &w);
    EXPECT_EQ(v.readable, 39u);
    EXPECT_EQ(v.unreadable, 1u);
    EXPECT_FALSE(v.clean());
    ASSERT_EQ(v.topics.count("/a"), 1u);
    const TopicVerification& a = v.topics.at("/a");
    EXPECT_EQ(a.unreadable, 1u);
    EXPECT_NE(a.first_unreadable.find("messages row id 20"), std::string::npos)
        << a.first_unreadable;
    EXPECT_NE(a.first_unreadable.find("does not decompress"), std::string::npos)
        << a.first_unreadable;
    EXPECT_TRUE(anyHas(w, {"topic /a", "1 of 40 messages unreadable", f.string(), "row id 20"}))
        << joined(w);
    EXPECT_TRUE(test::reindexAdvice(w).empty()) << joined(w);
    EXPECT_EQ(slurp(f), before) << "verify changed the file";
  }
}

/// bag info used to add "see `mcvio bag reindex`" to every storage file problem. A damaged
/// payload is not something reindex repairs (it keeps the rows as they are); metadata.yaml
/// naming the wrong message compression is (reindex takes it from the messages).
TEST(SqliteBadInput, InfoNamesReindexOnlyWhenItRepairsTheProblem) {
  const auto dir = smallBag("sqlite_hint", "sqlite3", Compression::Zstd);
  const auto f = sqliteFile(dir);
  sqlExec(f, "UPDATE messages SET data=substr(data, 1, 6) WHERE id=1;");  // the first message
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_TRUE(anyHas(w, {f.string(), "messages row id 1", "cannot recover"})) << joined(w);
  EXPECT_TRUE(test::reindexAdvice(w).empty()) << joined(w);
  BagReindexer::reindex(dir);  // indeed: the row stays unreadable
  expectInputError([&] { test::readAll(dir); }, {"messages row id 1", "does not decompress"});

  const auto wrong = smallBag("sqlite_hint_compression", "sqlite3", Compression::Zstd);
  BagMetadata m = readBagMetadata(wrong);
  m.compression_format = "lz4";
  writeBagMetadata(wrong, m);
  w.clear();
  bagInfo(wrong, &w);
  EXPECT_TRUE(anyHas(test::reindexAdvice(w), {"mcvio bag reindex " + wrong.string(), "zstd"}))
      << joined(w);
  BagReindexer::reindex(wrong);
  w.clear();
  EXPECT_TRUE(test::verifyBag(wrong, &w).clean()) << joined(w);
}

}  // namespace
}  // namespace mcvio::bag
