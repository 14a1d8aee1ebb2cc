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
