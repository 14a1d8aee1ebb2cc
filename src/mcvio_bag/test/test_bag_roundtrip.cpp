#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <tuple>

#include "bag_test_util.hpp"
#include "byte_io.hpp"
#include "file_output.hpp"
#include "mcap_summary.hpp"
#include "mcvio/bag/bag_info.hpp"
#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/bag/bag_writer.hpp"
#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {
namespace {

using test::payload;

struct Written {
  std::string topic;
  Timestamp log;
  Timestamp pub;
  std::vector<std::uint8_t> data;
};

/// Writes `n` messages on three topics with sizes 0..~3 KB; log times mostly increasing with
/// some out-of-order arrivals, as a recorder sees them.
std::vector<Written> writeBag(const std::filesystem::path& dir, const BagWriterOptions& o, int n) {
  BagWriter w(dir, o);
  w.addTopic(test::stringTopic("/chatter"));
  w.addTopic(test::poseStampedTopic("/pose"));
  w.addTopic(test::stringTopic("/other"));
  const char* names[] = {"/chatter", "/pose", "/other"};
  std::vector<Written> out;
  const Timestamp t0 = 1700000000000000000;
  for (int i = 0; i < n; ++i) {
    Written m;
    m.topic = names[i % 3];
    m.log = t0 + i * 1000000 - (i % 7 == 3 ? 2500000 : 0);
    m.pub = m.log - 12345;
    m.data = payload(static_cast<std::uint64_t>(i), static_cast<std::size_t>((i * 37) % 3000));
    w.write(m.topic, m.log, m.pub, m.data.data(), m.data.size());
    out.push_back(std::move(m));
  }
  w.close();
  std::stable_sort(out.begin(), out.end(),
                   [](const Written& a, const Written& b) { return a.log < b.log; });
  return out;
}

class RoundTrip : public ::testing::TestWithParam<std::tuple<std::string, Compression>> {};

TEST_P(RoundTrip, EveryMessageComesBackInTimeOrder) {
  const auto [storage, compression] = GetParam();
  BagWriterOptions o;
  o.storage = storage;
  o.compression = compression;
  o.chunk_size = 8 * 1024;  // many chunks
  const auto dir = test::freshPath("rt_" + storage + "_" + toString(compression));
  const auto expected = writeBag(dir, o, 400);

  BagReader r(dir);
  EXPECT_EQ(r.metadata().message_count, 400u);
  EXPECT_EQ(r.metadata().storage_identifier, storage);
  ASSERT_EQ(r.topics().size(), 3u);
  for (const auto& t : r.topics()) {
    const auto ref = t.type == "std_msgs/msg/String" ? test::stringTopic(t.name)
                                                     : test::poseStampedTopic(t.name);
    EXPECT_EQ(t.message_definition, ref.message_definition) << t.name;
    EXPECT_EQ(t.offered_qos_profiles, ref.offered_qos_profiles) << t.name;
    EXPECT_EQ(t.type_description_hash, ref.type_description_hash) << t.name;
  }
  std::size_t i = 0;
  BagMessage m;
  while (r.next(m)) {
    ASSERT_LT(i, expected.size());
    EXPECT_EQ(m.topic, expected[i].topic) << i;
    EXPECT_EQ(m.log_time, expected[i].log) << i;
    // sqlite3 storage keeps no publish time.
    EXPECT_EQ(m.publish_time, storage == "mcap" ? expected[i].pub : expected[i].log) << i;
    EXPECT_EQ(m.data, expected[i].data) << i;
    ++i;
  }
  EXPECT_EQ(i, expected.size());
  const auto& md = r.metadata();
  EXPECT_EQ(md.starting_time, expected.front().log);
  EXPECT_EQ(md.duration, expected.back().log - expected.front().log);
  ASSERT_EQ(md.topics_with_message_count.size(), 3u);
  std::uint64_t sum = 0;
  for (const auto& t : md.topics_with_message_count) sum += t.message_count;
  EXPECT_EQ(sum, 400u);
  if (storage == "mcap") {
    McapReader mr(dir / md.relative_file_paths.at(0));
    EXPECT_TRUE(mr.usedSummary());
    EXPECT_GT(mr.chunks().size(), 10u);
    for (const auto& c : mr.chunks()) EXPECT_EQ(c.compression, mcapCompressionName(compression));
  }
}

INSTANTIATE_TEST_SUITE_P(StorageByCompression, RoundTrip,
                         ::testing::Combine(::testing::Values("mcap", "sqlite3"),
                                            ::testing::Values(Compression::None, Compression::Zstd,
                                                              Compression::Lz4)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_" + toString(std::get<1>(info.param));
                         });

TEST(BagReader, TopicFilterSelectsOnlyThoseTopics) {
  for (const std::string storage : {"mcap", "sqlite3"}) {
    BagWriterOptions o;
    o.storage = storage;
    const auto dir = test::freshPath("filter_" + storage);
    const auto all = writeBag(dir, o, 90);
    BagReaderOptions ro;
    ro.topics = {"/pose"};
    BagReader r(dir, ro);
    std::size_t n = 0;
    BagMessage m;
    while (r.next(m)) {
      EXPECT_EQ(m.topic, "/pose");
      ++n;
    }
    EXPECT_EQ(n, 30u) << storage;
  }
}

TEST(BagWriter, SplitsBySizeAndReadsAcrossFiles) {
  for (const std::string storage : {"mcap", "sqlite3"}) {
    BagWriterOptions o;
    o.storage = storage;
    o.compression = Compression::None;
    o.chunk_size = 16 * 1024;
    o.max_bagfile_size = 100 * 1024;
    const auto dir = test::freshPath("split_size_" + storage);
    const auto expected = writeBag(dir, o, 600);
    const BagMetadata md = readBagMetadata(dir);
    EXPECT_GE(md.relative_file_paths.size(), 4u) << storage;
    ASSERT_EQ(md.files.size(), md.relative_file_paths.size());
    std::uint64_t sum = 0;
    for (const auto& f : md.files) {
      EXPECT_TRUE(std::filesystem::exists(dir / f.path)) << f.path;
      EXPECT_GT(f.message_count, 0u);
      sum += f.message_count;
    }
    EXPECT_EQ(sum, 600u);
    const auto got = test::readAll(dir);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].log_time, expected[i].log) << i;
      EXPECT_EQ(got[i].data, expected[i].data) << i;
    }
  }
}

TEST(BagWriter, SplitsByDuration) {
  BagWriterOptions o;
  o.max_bagfile_duration = 100000000;  // 0.1 s of log time = ~100 messages
  const auto dir = test::freshPath("split_duration");
  writeBag(dir, o, 350);
  const BagMetadata md = readBagMetadata(dir);
  EXPECT_EQ(md.files.size(), 4u);
  for (const auto& f : md.files) EXPECT_LE(f.duration, o.max_bagfile_duration + 3000000);
  EXPECT_EQ(test::readAll(dir).size(), 350u);
}

// Small chunks: messages bigger than a chunk take the uncopied path, the others are batched.
TEST(BagWriter, McapBigMessagesWithAndWithoutCrcs) {
  for (bool crc : {true, false}) {
    BagWriterOptions o;
    o.crc = crc;
    o.compression = Compression::None;
    o.chunk_size = 1000;
    const std::string name = crc ? "big_crc" : "big_no_crc";
    const auto dir = test::freshPath(name);
    const auto expected = writeBag(dir, o, 90);
    const auto got = test::readAll(dir);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].data, expected[i].data) << i;
    McapReader r(dir / (name + "_0.mcap"));
    std::size_t single = 0;
    for (const auto& c : r.chunks()) {
      EXPECT_EQ(c.uncompressed_crc == 0, !crc);
      std::size_t n = 0;
      for (const auto& [id, e] : c.message_index) n += e.size();
      single += n == 1 && c.uncompressed_size > 1000 ? 1 : 0;
    }
    EXPECT_GT(single, 20u);
    // A linear scan (no summary) checks the chunk CRCs and sees the same messages.
    std::ifstream in(dir / (name + "_0.mcap"), std::ios::binary);
    std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in),
                                    std::istreambuf_iterator<char>()};
    std::memset(bytes.data() + bytes.size() - 37 + 9, 0, 8);  // footer summary_start = 0
    McapReader linear(bytes, name);
    EXPECT_FALSE(linear.usedSummary());
    BagMessage m;
    std::size_t k = 0;
    while (linear.next(m)) {
      ASSERT_LT(k, expected.size());
      EXPECT_EQ(m.data, expected[k].data) << k;
      EXPECT_EQ(m.log_time, expected[k].log) << k;
      ++k;
    }
    EXPECT_EQ(k, expected.size());
  }
}

TEST(BagReader, ReadsASingleMcapFile) {
  BagWriterOptions o;
  const auto dir = test::freshPath("single_file");
  writeBag(dir, o, 30);
  BagReader r(dir / "single_file_0.mcap");
  std::size_t n = 0;
  while (r.next()) ++n;
  EXPECT_EQ(n, 30u);
}

TEST(BagInfo, FormatsLikeRos2BagInfo) {
  BagWriterOptions o;
  const auto dir = test::freshPath("info");
  writeBag(dir, o, 30);
  const std::string info = bagInfo(dir);
  EXPECT_NE(info.find("Files:             info_0.mcap"), std::string::npos) << info;
  EXPECT_NE(info.find("Storage id:        mcap"), std::string::npos) << info;
  EXPECT_NE(info.find("Messages:          30"), std::string::npos) << info;
  EXPECT_NE(info.find("Duration:          0.029000000s"), std::string::npos) << info;
  EXPECT_NE(info.find("Topic: /pose | Type: geometry_msgs/msg/PoseStamped | Count: 10 | "
                      "Serialization Format: cdr"),
            std::string::npos)
      << info;
  EXPECT_NE(info.find("Start:             Nov 14 2023 22:13:20.000000000 UTC"), std::string::npos)
      << info;
}

TEST(BagWriterOptions, LoadsFromYamlAndNamesBadKeys) {
  const auto o = BagWriterOptions::fromYaml(
      "storage: sqlite3\ncompression: lz4\nchunk_size: 4096\nmax_bagfile_duration: 2.5\ncrc: "
      "false\n",
      "t.yaml");
  EXPECT_FALSE(o.crc);
  EXPECT_EQ(o.storage, "sqlite3");
  EXPECT_EQ(o.compression, Compression::Lz4);
  EXPECT_EQ(o.chunk_size, 4096u);
  EXPECT_EQ(o.max_bagfile_duration, 2500000000);
  try {
    BagWriterOptions::fromYaml("compresion: zstd\n", "t.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'compresion'"), std::string::npos);
  }
  try {
    BagWriterOptions::fromYaml("storage: rosbag1\n", "t.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("storage"), std::string::npos) << e.what();
  }
  try {
    BagWriterOptions::fromYaml("compression: brotli\n", "t.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'compression'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mcvio::bag

namespace mcvio::bag {
namespace {

// Another writer may put messages outside chunks; they have no index, so the reader must not
// trust the summary alone.
TEST(McapReader, ReadsMessagesOutsideChunks) {
  const auto path = test::freshPath("unchunked.mcap");
  {
    detail::FileOutput out(path);
    out.write(mcap::kMagic, 8);
    std::vector<std::uint8_t> header;
    detail::ByteWriter hw(header);
    hw.str("ros2");
    hw.str("other-writer");
    detail::writeMcapRecord(out, mcap::kHeader, header);
    mcap::Schema s{1, "std_msgs/msg/String", "ros2msg", "string data\n"};
    mcap::Channel c{3, 1, "/plain", "cdr", {{"offered_qos_profiles", ""}}};
    detail::writeMcapRecord(out, mcap::kSchema, detail::mcapSchemaContent(s));
    detail::writeMcapRecord(out, mcap::kChannel, detail::mcapChannelContent(c));
    for (std::uint32_t i = 0; i < 3; ++i) {
      std::vector<std::uint8_t> m;
      detail::ByteWriter w(m);
      w.u16(3);
      w.u32(i);
      w.u64(50 - i * 10);  // out of order on purpose
      w.u64(7);
      const auto d = test::payload(i, 40);
      w.raw(d.data(), d.size());
      detail::writeMcapRecord(out, mcap::kMessage, m);
    }
    detail::McapStatistics stats;
    stats.message_count = 3;
    stats.message_start_time = 30;
    stats.message_end_time = 50;
    stats.channel_message_counts[3] = 3;
    detail::writeMcapTail(out, {s}, {c}, {}, stats, true);
  }
  McapReader r(path);
  EXPECT_FALSE(r.usedSummary());
  EXPECT_EQ(r.unchunkedMessages(), 3u);
  BagMessage m;
  std::vector<Timestamp> times;
  while (r.next(m)) {
    EXPECT_EQ(m.topic, "/plain");
    EXPECT_EQ(m.data, test::payload(m.sequence, 40));
    times.push_back(m.log_time);
  }
  EXPECT_EQ(times, (std::vector<Timestamp>{30, 40, 50}));
}

}  // namespace
}  // namespace mcvio::bag
