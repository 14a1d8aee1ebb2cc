#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include "bag_test_util.hpp"
#include "mcvio/bag/bag_info.hpp"
#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/bag/bag_reindexer.hpp"
#include "mcvio/bag/bag_writer.hpp"
#include "mcvio/bag/crc32.hpp"
#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {
namespace {

constexpr Timestamp kT0 = 1700000000000000000;

std::size_t messageSize(int i) { return 200 + static_cast<std::size_t>((i * 131) % 1500); }

void writeMessage(BagWriter& w, int i) {
  const auto data = test::payload(static_cast<std::uint64_t>(i), messageSize(i));
  w.write(i % 2 ? "/a" : "/b", kT0 + i * 1000, kT0 + i * 1000, data.data(), data.size());
}

/// Topics /a and /b, then messages 0 .. count-1 alternating between them.
void writeTopicsAndMessages(BagWriter& w, int count) {
  w.addTopic(test::stringTopic("/a"));
  w.addTopic(test::stringTopic("/b"));
  for (int i = 0; i < count; ++i) writeMessage(w, i);
}

/// Every message read back is message i of the sequence, in order, and there are `n` of them.
void expectPrefix(const std::vector<BagMessage>& got, std::size_t n) {
  ASSERT_EQ(got.size(), n);
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].log_time, kT0 + static_cast<Timestamp>(i) * 1000) << i;
    ASSERT_EQ(got[i].data, test::payload(i, messageSize(static_cast<int>(i)))) << i;
  }
}

/// Writes 120 messages in small chunks to `<dir>/<dir name>_0.mcap` and returns that file.
std::filesystem::path writeChunkedBag(const std::filesystem::path& dir, Compression c) {
  BagWriterOptions o;
  o.compression = c;
  o.chunk_size = 4096;
  {
    BagWriter w(dir, o);
    writeTopicsAndMessages(w, 120);
  }
  return dir / (dir.filename().string() + "_0.mcap");
}

void truncateFile(const std::filesystem::path& p, std::uint64_t size) {
  std::filesystem::resize_file(p, size);
}

/// Cuts a finished MCAP bag at many points; reindex must recover exactly the messages of the
/// chunks that end before the cut.
TEST(Recovery, TruncatedMcapKeepsEveryCompleteChunk) {
  for (Compression c : {Compression::None, Compression::Zstd, Compression::Lz4}) {
    const auto src = test::freshPath("trunc_src_" + toString(c));
    const auto mcap_name = writeChunkedBag(src, c).filename().string();
    McapReader intact(src / mcap_name);
    const auto chunks = intact.chunks();
    ASSERT_GT(chunks.size(), 8u);
    const auto metadata = McapReader(src / mcap_name, McapReadMode::Recover).metadataRecords();
    ASSERT_EQ(metadata.size(), 1u);
    EXPECT_EQ(metadata[0].name, "rosbag2");
    const std::uint64_t metadata_end = metadata[0].offset + metadata[0].length;
    // Cut points: inside a chunk, right after a chunk (indexes missing), inside its indexes,
    // after its indexes, inside the summary.
    std::vector<std::pair<std::uint64_t, std::size_t>> cuts;  // (size, messages expected)
    std::size_t before = 0;
    for (std::size_t k = 0; k < chunks.size(); k += 3) {
      const auto& ch = chunks[k];
      std::size_t in_chunk = 0;
      for (const auto& [id, e] : ch.message_index) in_chunk += e.size();
      const std::uint64_t end = ch.start_offset + ch.length;
      cuts.emplace_back(ch.start_offset + ch.length / 2, before);
      cuts.emplace_back(end - 1, before);
      cuts.emplace_back(end, before + in_chunk);
      cuts.emplace_back(end + 5, before + in_chunk);
      cuts.emplace_back(end + ch.message_index_length, before + in_chunk);
      for (std::size_t j = k; j < std::min(k + 3, chunks.size()); ++j) {
        for (const auto& [id, e] : chunks[j].message_index) before += e.size();
      }
    }
    cuts.emplace_back(intact.fileSize() - 10, 120);  // summary damaged, all chunks intact
    for (const auto& [cut, expected] : cuts) {
      const auto dir = test::freshPath("trunc_" + toString(c));
      std::filesystem::create_directories(dir);
      std::filesystem::copy_file(src / mcap_name, dir / mcap_name);
      truncateFile(dir / mcap_name, cut);
      // A strict read refuses the unfinished file with its name and an offset.
      try {
        McapReader strict(dir / mcap_name);
        FAIL() << "strict read of a truncated file must fail (cut " << cut << ")";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(mcap_name), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
      }
      const BagMetadata md = BagReindexer::reindex(dir);
      EXPECT_EQ(md.message_count, expected) << "cut " << cut;
      // Only an unfinished end: repaired in place, no copy of the original left behind.
      EXPECT_FALSE(std::filesystem::exists(dir / (mcap_name + ".orig"))) << "cut " << cut;
      McapReader repaired(dir / mcap_name);
      EXPECT_TRUE(repaired.usedSummary());
      // Chunks and the rosbag2 Metadata record (written at close) survive a damaged summary.
      const std::size_t metadata_records =
          McapReader(dir / mcap_name, McapReadMode::Recover).metadataRecords().size();
      EXPECT_EQ(metadata_records, cut >= metadata_end ? 1u : 0u);
      SCOPED_TRACE("cut at " + std::to_string(cut) + " " + toString(c));
      expectPrefix(test::readAll(dir), expected);
    }
  }
}

/// Writes 100 messages to a bag in a child process that flushes and exits without close() or
/// destructors, like a kill after the flush; with `buffered_tail` one more message, smaller than
/// a chunk, stays buffered and is never persisted. False when the child did not exit normally.
bool writeWithoutClosing(const std::filesystem::path& dir, const std::string& storage, bool buffered_tail) {
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    BagWriterOptions o;
    o.storage = storage;
    o.chunk_size = 2048;
    BagWriter w(dir, o);
    writeTopicsAndMessages(w, 100);
    w.flush();
    if (buffered_tail) writeMessage(w, 100);
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status);
}

/// A writer that never closes (process gone after flushing) leaves data the reader refuses
/// strictly, reads with allow_unfinished, and reindex restores fully.
TEST(Recovery, UnclosedWritersInAChildProcess) {
  for (const std::string storage : {"mcap", "sqlite3"}) {
    const auto dir = test::freshPath("unclosed_" + storage);
    ASSERT_TRUE(writeWithoutClosing(dir, storage, /*buffered_tail=*/true));
    if (storage == "mcap") {
      EXPECT_THROW(test::readAll(dir), InputError);
      BagReaderOptions ro;
      ro.allow_unfinished = true;
      BagReader r(dir, ro);
      std::size_t n = 0;
      while (r.next()) ++n;
      EXPECT_EQ(n, 100u);
    }
    const BagMetadata md = BagReindexer::reindex(dir);
    EXPECT_EQ(md.message_count, 100u) << storage;
    EXPECT_EQ(md.topics_with_message_count.size(), 2u);
    expectPrefix(test::readAll(dir), 100);
  }
}

/// An sqlite3 bag whose writer process ended without close(): 100 messages committed, most of
/// them only in `<file>.db3-wal` (the writer checkpoints at close). Returns the .db3.
std::filesystem::path killedSqliteBag(const std::filesystem::path& dir) {
  EXPECT_TRUE(writeWithoutClosing(dir, "sqlite3", /*buffered_tail=*/false));
  return dir / (dir.filename().string() + "_0.db3");
}

/// Messages in the .db3 alone, its -wal ignored (immutable: opened without touching any file).
long long messagesWithoutWal(const std::filesystem::path& db3) {
  sqlite3* db = nullptr;
  long long n = -1;
  const std::string uri = "file:" + db3.string() + "?immutable=1";
  if (sqlite3_open_v2(uri.c_str(), &db, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr) ==
      SQLITE_OK) {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT COUNT(*) FROM messages;", -1, &st, nullptr) == SQLITE_OK &&
        sqlite3_step(st) == SQLITE_ROW) {
      n = sqlite3_column_int64(st, 0);
    }
    sqlite3_finalize(st);
  }
  sqlite3_close(db);
  return n;
}

std::vector<std::uint8_t> fileBytes(const std::filesystem::path& p);

/// "<size> bytes, CRC-32 <crc>", or "missing": readable when a comparison fails.
std::string checksum(const std::filesystem::path& p) {
  if (!std::filesystem::exists(p)) return "missing";
  const auto bytes = fileBytes(p);
  return std::to_string(bytes.size()) + " bytes, CRC-32 " +
         std::to_string(Crc32::update(0, bytes.data(), bytes.size()));
}

/// bag info's warnings, one per line.
std::string joined(const std::vector<std::string>& warnings) {
  std::string out;
  for (const auto& w : warnings) out += w + "\n";
  return out;
}

std::filesystem::path withSuffix(std::filesystem::path p, const char* suffix) {
  p += suffix;
  return p;
}

/// Reading (BagReader, bag info) must not fold a killed writer's -wal into the .db3 or delete
/// it, yet must return the messages that live only in the -wal. Also without a -shm (a copied
/// bag), which sqlite then creates beside the file.
TEST(Recovery, ReadingSqliteLeavesTheWriteAheadLogAndFileUntouched) {
  for (const bool keep_shm : {true, false}) {
    SCOPED_TRACE(keep_shm ? "with -shm" : "without -shm");
    const auto dir =
        test::freshPath(std::string("sqlite_wal_read_") + (keep_shm ? "shm" : "noshm"));
    const auto db3 = killedSqliteBag(dir);
    const auto wal = withSuffix(db3, "-wal");
    ASSERT_TRUE(std::filesystem::exists(wal));
    if (!keep_shm) std::filesystem::remove(withSuffix(db3, "-shm"));
    const auto db3_sum = checksum(db3);
    const auto wal_sum = checksum(wal);
    ASSERT_LT(messagesWithoutWal(db3), 100) << "the test needs messages only in the -wal";
    expectPrefix(test::readAll(dir), 100);
    std::vector<std::string> w;
    bagInfo(dir, &w);
    // metadata.yaml of a killed writer lists no message; the storage (its -wal) all of them.
    EXPECT_NE(joined(w).find("the storage files hold 100"), std::string::npos) << joined(w);
    // --verify reads every row, those in the -wal too, and also changes nothing.
    EXPECT_EQ(test::verifyBag(dir).readable, 100u);
    EXPECT_EQ(checksum(db3), db3_sum) << "the .db3 was modified";
    EXPECT_EQ(checksum(wal), wal_sum) << "the -wal was modified or deleted";
    // The repair command is the one that folds the log in.
    EXPECT_EQ(BagReindexer::reindex(dir).message_count, 100u);
    EXPECT_FALSE(std::filesystem::exists(wal));
    expectPrefix(test::readAll(dir), 100);
  }
}

/// A killed writer's bag on read-only media (folder and files not writable, no -shm, which
/// sqlite cannot create there) is still read completely, and stays as it was.
TEST(Recovery, SqliteWithWriteAheadLogInAReadOnlyFolderIsReadCompletely) {
  const auto dir = test::freshPath("sqlite_wal_read_only");
  const auto db3 = killedSqliteBag(dir);
  const auto wal = withSuffix(db3, "-wal");
  std::filesystem::remove(withSuffix(db3, "-shm"));
  const auto db3_sum = checksum(db3);
  const auto wal_sum = checksum(wal);
  ASSERT_LT(messagesWithoutWal(db3), 100);
  const auto no_write = std::filesystem::perms::owner_write | std::filesystem::perms::group_write |
                        std::filesystem::perms::others_write;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    std::filesystem::permissions(e.path(), no_write, std::filesystem::perm_options::remove);
  }
  std::filesystem::permissions(dir, no_write, std::filesystem::perm_options::remove);
  const auto readEverything = [&dir] {
    std::vector<BagMessage> got;
    std::vector<std::string> w;
    try {
      got = test::readAll(dir);
      bagInfo(dir, &w);
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
    }
    expectPrefix(got, 100);
    EXPECT_NE(joined(w).find("the storage files hold 100"), std::string::npos) << joined(w);
  };
  if (geteuid() != 0) {
    readEverything();
  } else {
    // Root writes whatever the permissions say (CI runs as root): read as nobody instead, in a
    // child whose failures come back as its exit status.
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      if (setgid(65534) != 0 || setuid(65534) != 0) _exit(2);
      readEverything();
      _exit(::testing::Test::HasFailure() ? 1 : 0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_NE(WEXITSTATUS(status), 2) << "could not drop privileges to uid/gid 65534";
    EXPECT_EQ(WEXITSTATUS(status), 0) << "reading as an unprivileged user failed (see above)";
  }
  std::filesystem::permissions(dir, no_write, std::filesystem::perm_options::add);
  EXPECT_FALSE(std::filesystem::exists(withSuffix(db3, "-shm")));
  EXPECT_EQ(checksum(db3), db3_sum);
  EXPECT_EQ(checksum(wal), wal_sum);
}

/// A real recorder process killed with SIGKILL while writing: reindex recovers at least every
/// message the child reported as flushed, each exactly as written, and nothing else.
TEST(Recovery, Kill9WhileWriting) {
  for (const std::string storage : {"mcap", "sqlite3"}) {
    const auto dir = test::freshPath("kill9_" + storage);
    int fds[2];
    ASSERT_EQ(pipe(fds), 0);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      close(fds[0]);
      BagWriterOptions o;
      o.storage = storage;
      o.chunk_size = 4096;
      BagWriter w(dir, o);
      w.addTopic(test::stringTopic("/a"));
      w.addTopic(test::stringTopic("/b"));
      for (int i = 0;; ++i) {
        if (i == 20000) {
          for (;;) pause();  // bounded disk use if the parent is slow to kill
        }
        writeMessage(w, i);
        if (i % 50 == 49) {
          w.flush();
          const int flushed = i + 1;
          if (write(fds[1], &flushed, sizeof(flushed)) != sizeof(flushed)) _exit(3);
        }
      }
    }
    close(fds[1]);
    int flushed = 0;
    while (flushed < 400) {
      ASSERT_EQ(read(fds[0], &flushed, sizeof(flushed)), static_cast<ssize_t>(sizeof(flushed)));
    }
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    close(fds[0]);
    ASSERT_TRUE(WIFSIGNALED(status));
    const BagMetadata md = BagReindexer::reindex(dir);
    EXPECT_GE(md.message_count, static_cast<std::uint64_t>(flushed)) << storage;
    const auto got = test::readAll(dir);
    expectPrefix(got, got.size());
    EXPECT_GE(got.size(), static_cast<std::size_t>(flushed));
  }
}

void flipByte(const std::filesystem::path& p, std::uint64_t offset) {
  std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(static_cast<std::streamoff>(offset));
  char b = 0;
  f.read(&b, 1);
  b = static_cast<char>(b ^ 0x5A);
  f.seekp(static_cast<std::streamoff>(offset));
  f.write(&b, 1);
}

std::vector<std::uint8_t> fileBytes(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// Message numbers (i of writeMessage) stored in a chunk.
std::set<int> messagesOf(const mcap::ChunkInfo& c) {
  std::set<int> out;
  for (const auto& [ch, e] : c.message_index) {
    for (const auto& [t, off] : e) out.insert(static_cast<int>((static_cast<Timestamp>(t) - kT0) / 1000));
  }
  return out;
}

/// Every message read back is intact and is one of `expected`, all of which are there.
void expectMessages(const std::vector<BagMessage>& got, const std::set<int>& expected) {
  ASSERT_EQ(got.size(), expected.size());
  auto it = expected.begin();
  for (const auto& m : got) {
    const int i = *it++;
    ASSERT_EQ(m.log_time, kT0 + static_cast<Timestamp>(i) * 1000);
    ASSERT_EQ(m.data, test::payload(static_cast<std::uint64_t>(i), messageSize(i))) << i;
  }
}

/// One flipped byte in an early chunk of a truncated file: every other complete chunk is kept
/// (the old recovery cut the file at the damage and kept only the chunks before it), the damage
/// is reported with its offset and lost message count, and the original is kept as .orig.
TEST(Recovery, DamagedChunkKeepsEveryIntactChunkAfterIt) {
  for (Compression c : {Compression::None, Compression::Zstd}) {
    SCOPED_TRACE(toString(c));
    const auto dir = test::freshPath("damaged_" + toString(c));
    const auto file = writeChunkedBag(dir, c);
    const auto chunks = McapReader(file).chunks();
    ASSERT_GT(chunks.size(), 8u);
    const auto& bad = chunks[2];
    const auto& last = chunks[chunks.size() - 2];
    std::set<int> expected;
    for (std::size_t k = 0; k + 2 < chunks.size(); ++k) {
      if (k != 2) for (int i : messagesOf(chunks[k])) expected.insert(i);
    }
    truncateFile(file, last.start_offset + last.length / 2);  // the last chunk but one is cut
    flipByte(file, bad.records_offset + bad.compressed_size / 2);
    const auto before = fileBytes(file);
    std::vector<std::string> log;
    std::vector<std::string> damage;
    const BagMetadata md = BagReindexer::reindex(dir, &log, &damage);
    EXPECT_EQ(md.message_count, expected.size());
    expectMessages(test::readAll(dir), expected);
    ASSERT_EQ(damage.size(), 1u);
    EXPECT_NE(damage[0].find("byte offset " + std::to_string(bad.start_offset)), std::string::npos)
        << damage[0];
    EXPECT_NE(damage[0].find(std::to_string(messagesOf(bad).size()) + " messages lost"),
              std::string::npos)
        << damage[0];
    EXPECT_EQ(fileBytes(file.string() + ".orig"), before);
    bool told = false;
    for (const auto& l : log) told |= l.find(".orig") != std::string::npos;
    EXPECT_TRUE(told);
  }
}

/// A flipped byte inside a chunk of a finished file (summary and footer intact): reindex must
/// not call it intact; it drops that chunk only, and the bag plays again.
TEST(Recovery, BadChunkCrcBehindAnIntactSummaryIsRepaired) {
  const auto dir = test::freshPath("bad_crc");
  const auto file = writeChunkedBag(dir, Compression::Zstd);
  const auto chunks = McapReader(file).chunks();
  const auto& bad = chunks[4];
  std::set<int> expected;
  for (int i = 0; i < 120; ++i) expected.insert(i);
  for (int i : messagesOf(bad)) expected.erase(i);
  flipByte(file, bad.records_offset + 10);
  std::vector<std::string> log;
  std::vector<std::string> damage;
  const BagMetadata md = BagReindexer::reindex(dir, &log, &damage);
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log[0].find("intact"), std::string::npos) << log[0];
  EXPECT_EQ(damage.size(), 1u);
  EXPECT_EQ(md.message_count, expected.size());
  expectMessages(test::readAll(dir), expected);
  // A second reindex finds the repaired file intact and keeps it as it is.
  std::vector<std::string> again;
  BagReindexer::reindex(dir, &again);
  ASSERT_FALSE(again.empty());
  EXPECT_NE(again[0].find("intact"), std::string::npos) << again[0];
}

/// Many flipped bytes anywhere but the footer: reindex never throws, keeps every message of
/// every chunk it did not report as damaged, and each kept message is exactly as written.
TEST(Recovery, ManyRandomFlipsKeepEveryUndamagedChunk) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const auto dir = test::freshPath("flips_" + std::to_string(seed));
    const auto file = writeChunkedBag(dir, seed % 2 ? Compression::Zstd : Compression::None);
    const std::uint64_t size = std::filesystem::file_size(file);
    std::uint64_t x = seed * 0x9E3779B97F4A7C15ull;
    for (int k = 0; k < 8; ++k) {
      x ^= x << 13;
      x ^= x >> 7;
      x ^= x << 17;
      flipByte(file, 200 + x % (size - 200 - mcap::kFooterAndMagic));
    }
    std::vector<std::string> damage;
    BagMetadata md;
    ASSERT_NO_THROW(md = BagReindexer::reindex(dir, nullptr, &damage)) << "seed " << seed;
    const auto got = test::readAll(dir);
    EXPECT_EQ(got.size(), md.message_count);
    EXPECT_GE(got.size(), 30u) << "seed " << seed;  // 8 flips hit at most 8 of ~40 chunks
    for (const auto& m : got) {
      const int i = static_cast<int>((m.log_time - kT0) / 1000);
      ASSERT_EQ(m.data, test::payload(static_cast<std::uint64_t>(i), messageSize(i)));
    }
  }
}

/// 200 messages split over several small files.
std::filesystem::path writeSplitBag(const std::string& name) {
  const auto dir = test::freshPath(name);
  BagWriterOptions o;
  o.max_bagfile_size = 20000;
  BagWriter w(dir, o);
  writeTopicsAndMessages(w, 200);
  return dir;
}

TEST(Recovery, ReindexRebuildsALostMetadataFile) {
  const auto dir = writeSplitBag("lost_metadata");
  const BagMetadata before = readBagMetadata(dir);
  std::filesystem::remove(dir / "metadata.yaml");
  EXPECT_THROW(BagReader r(dir), InputError);
  std::vector<std::string> log;
  const BagMetadata after = BagReindexer::reindex(dir, &log);
  EXPECT_EQ(log.size(), before.relative_file_paths.size());
  EXPECT_EQ(after.relative_file_paths, before.relative_file_paths);
  EXPECT_EQ(after.message_count, 200u);
  EXPECT_EQ(after.starting_time, before.starting_time);
  EXPECT_EQ(after.duration, before.duration);
  expectPrefix(test::readAll(dir), 200);
}

TEST(Recovery, ReindexCountsWhatATruncatedFileLostAgainstTheOldMetadata) {
  const auto dir = test::freshPath("trunc_with_metadata");
  {
    BagWriter w(dir, BagWriterOptions{});
    writeTopicsAndMessages(w, 200);
  }
  const BagMetadata before = readBagMetadata(dir);
  ASSERT_EQ(before.files.size(), 1u);
  const auto file = dir / before.relative_file_paths.front();
  truncateFile(file, std::filesystem::file_size(file) / 2);
  std::vector<std::string> log;
  const BagMetadata after = BagReindexer::reindex(dir, &log);
  ASSERT_LT(after.message_count, 200u);
  const std::string expected = "the old metadata.yaml listed 200 messages, " + std::to_string(after.message_count) +
                               " are readable: " + std::to_string(200 - after.message_count) + " lost";
  EXPECT_TRUE(std::any_of(log.begin(), log.end(), [&](const std::string& l) { return l.find(expected) != std::string::npos; }))
      << "want '" << expected << "' in the log";
}

TEST(Recovery, ReindexKeepsTheReadableFilesNextToAnUnreadableOne) {
  const auto dir = writeSplitBag("one_unreadable");
  const BagMetadata before = readBagMetadata(dir);
  ASSERT_GE(before.relative_file_paths.size(), 3u);
  const auto last = dir / before.relative_file_paths.back();
  const std::uint64_t last_count = before.files.back().message_count;
  {
    std::ofstream garbage(last, std::ios::binary | std::ios::trunc);
    garbage << "not an mcap file at all";
  }
  std::vector<std::string> log, damage;
  const BagMetadata after = BagReindexer::reindex(dir, &log, &damage);
  EXPECT_EQ(after.relative_file_paths.size(), before.relative_file_paths.size() - 1);
  EXPECT_EQ(after.message_count, 200u - last_count);
  ASSERT_EQ(damage.size(), 1u);
  EXPECT_NE(damage[0].find(last.filename().string() + ": not indexed"), std::string::npos) << damage[0];
  EXPECT_TRUE(std::filesystem::exists(last));  // left for whoever can still salvage it
  expectPrefix(test::readAll(dir), 200 - last_count);
}

}  // namespace
}  // namespace mcvio::bag

namespace mcvio::bag {
namespace {

/// Plain `bag info` reads an MCAP file's summary, not its chunks. `bag info --verify`
/// decompresses every chunk and checks its CRC: a damaged chunk behind an intact summary counts
/// its messages per topic as unreadable, named by the chunk's byte offset and the first log
/// time, with what reindex does about it; the file is left as it was.
TEST(Recovery, VerifyFindsADamagedChunkBehindAnIntactSummary) {
  for (Compression c : {Compression::None, Compression::Zstd, Compression::Lz4}) {
    SCOPED_TRACE(toString(c));
    const auto dir = test::freshPath("verify_chunk_" + toString(c));
    const auto file = writeChunkedBag(dir, c);
    std::vector<std::string> w;
    BagVerification v = test::verifyBag(dir, &w);
    EXPECT_TRUE(v.clean()) << joined(w);
    EXPECT_EQ(v.readable, 120u);
    EXPECT_EQ(v.topics["/a"].readable, 60u);
    const auto chunks = McapReader(file).chunks();
    ASSERT_GT(chunks.size(), 8u);
    const auto& bad = chunks[chunks.size() / 2];
    flipByte(file, bad.records_offset + bad.compressed_size / 2);
    const auto before = fileBytes(file);
    std::map<std::string, std::set<int>> lost;  // writeMessage: odd i on /a, even on /b
    for (const int i : messagesOf(bad)) lost[i % 2 ? "/a" : "/b"].insert(i);
    ASSERT_EQ(lost.size(), 2u);
    w.clear();
    v = test::verifyBag(dir, &w);
    EXPECT_EQ(v.unreadable, messagesOf(bad).size());
    EXPECT_EQ(v.readable, 120u - messagesOf(bad).size());
    for (const auto& [topic, numbers] : lost) {
      const TopicVerification& t = v.topics[topic];
      EXPECT_EQ(t.unreadable, numbers.size()) << topic;
      EXPECT_EQ(t.readable, 60u - numbers.size()) << topic;
      EXPECT_NE(t.first_unreadable.find("byte offset " + std::to_string(bad.start_offset)),
                std::string::npos)
          << t.first_unreadable;
      EXPECT_NE(
          t.first_unreadable.find("log time " + std::to_string(kT0 + *numbers.begin() * 1000)),
          std::string::npos)
          << t.first_unreadable;
    }
    EXPECT_NE(joined(w).find("topic /a: " + std::to_string(lost["/a"].size()) + " of 60"),
              std::string::npos)
        << joined(w);
    EXPECT_FALSE(test::reindexAdvice(w).empty()) << joined(w);  // reindex drops that chunk
    EXPECT_EQ(fileBytes(file), before) << "verify changed the file";
  }
}

/// bag info used to add "see `mcvio bag reindex`" to every storage file problem. A killed
/// writer's MCAP file is what reindex finishes (and --verify reads its complete chunks, as
/// reindex keeps them); a file that is no MCAP at all it cannot repair.
TEST(Recovery, InfoNamesReindexOnlyWhenItRepairsTheProblem) {
  const auto dir = test::freshPath("hint_killed_mcap");
  ASSERT_TRUE(writeWithoutClosing(dir, "mcap", /*buffered_tail=*/true));
  std::vector<std::string> w;
  bagInfo(dir, &w);
  EXPECT_NE(joined(test::reindexAdvice(w))
                .find("`mcvio bag reindex " + dir.string() +
                      "` finishes the file, keeping every intact chunk"),
            std::string::npos)
      << joined(w);
  w.clear();
  const BagVerification v = test::verifyBag(dir, &w);
  EXPECT_EQ(v.readable, 100u) << joined(w);
  EXPECT_EQ(v.unreadable, 0u) << joined(w);

  const auto garbage = test::freshPath("hint_not_mcap");
  const auto file = writeChunkedBag(garbage, Compression::Zstd);
  const auto bytes = test::payload(7, 5000);
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  w.clear();
  bagInfo(garbage, &w);
  EXPECT_NE(joined(w).find("wrong magic"), std::string::npos) << joined(w);
  EXPECT_TRUE(test::reindexAdvice(w).empty()) << joined(w);
  EXPECT_THROW(BagReindexer::reindex(garbage), InputError);  // indeed
}

}  // namespace
}  // namespace mcvio::bag
