#include "mcvio/bag/bag_info.hpp"

#include <cstring>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/bag/mcap_records.hpp"
#include "mcvio/bag/sqlite_reader.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

namespace {

std::string humanSize(std::uint64_t bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 4) {
    v /= 1024.0;
    ++u;
  }
  std::ostringstream os;
  os << std::fixed << std::setprecision(u == 0 ? 0 : 1) << v << " " << units[u];
  return os.str();
}

std::string seconds(Timestamp ns) {
  std::ostringstream os;
  const bool neg = ns < 0;
  const std::uint64_t a =
      neg ? static_cast<std::uint64_t>(-(ns + 1)) + 1 : static_cast<std::uint64_t>(ns);
  os << (neg ? "-" : "") << a / 1000000000ull << "." << std::setw(9) << std::setfill('0')
     << a % 1000000000ull;
  return os.str();
}

std::string wallTime(Timestamp ns) {
  const std::time_t s = static_cast<std::time_t>(ns / 1000000000);
  std::tm tm{};
  gmtime_r(&s, &tm);
  std::ostringstream os;
  os << std::put_time(&tm, "%b %e %Y %H:%M:%S") << "." << std::setw(9) << std::setfill('0')
     << (ns % 1000000000 + 1000000000) % 1000000000 << " UTC (" << seconds(ns) << ")";
  return os.str();
}

}  // namespace

std::string formatBagInfo(const BagMetadata& m, std::uint64_t bag_size_bytes) {
  std::ostringstream os;
  const int w = 19;
  auto label = [&](const char* l) { os << std::left << std::setw(w) << l; };
  label("Files:");
  if (m.relative_file_paths.empty()) os << "\n";
  for (std::size_t i = 0; i < m.relative_file_paths.size(); ++i) {
    if (i > 0) os << std::string(w, ' ');
    os << m.relative_file_paths[i] << "\n";
  }
  label("Bag size:");
  os << humanSize(bag_size_bytes) << "\n";
  label("Storage id:");
  os << m.storage_identifier << "\n";
  if (!m.compression_format.empty()) {
    label("Compression:");
    os << m.compression_format << " (" << m.compression_mode << ")\n";
  }
  if (!m.ros_distro.empty()) {
    label("ROS Distro:");
    os << m.ros_distro << "\n";
  }
  label("Duration:");
  os << seconds(m.duration) << "s\n";
  label("Start:");
  os << wallTime(m.starting_time) << "\n";
  label("End:");
  os << wallTime(m.starting_time + m.duration) << "\n";
  label("Messages:");
  os << m.message_count << "\n";
  label("Topic information:");
  if (m.topics_with_message_count.empty()) os << "\n";
  for (std::size_t i = 0; i < m.topics_with_message_count.size(); ++i) {
    const auto& t = m.topics_with_message_count[i];
    if (i > 0) os << std::string(w, ' ');
    os << "Topic: " << t.topic.name << " | Type: " << t.topic.type
       << " | Count: " << t.message_count
       << " | Serialization Format: " << t.topic.serialization_format << "\n";
  }
  return os.str();
}

namespace {

/// Opens one storage file as `storage` says ("mcap" or "sqlite3"; summary only for MCAP: fast
/// on big files). A file of the other storage is an InputError that says so.
std::unique_ptr<StorageFileReader> openStorageFile(const std::filesystem::path& p,
                                                   const std::string& storage,
                                                   Compression compression = Compression::None) {
  if (storage == "sqlite3") return std::make_unique<SqliteReader>(p, compression);
  if (SqliteReader::looksLikeSqlite(p)) {
    throw InputError(p.string() + ": is an sqlite3 database, but metadata.yaml's "
                                  "storage_identifier (or the file's extension) says mcap");
  }
  return std::make_unique<McapReader>(p, McapReadMode::Strict);
}

std::string storageOfExtension(const std::filesystem::path& p) {
  if (p.extension() == ".db3") return "sqlite3";
  return p.extension() == ".mcap" ? "mcap" : "";
}

/// The storage a file's first bytes show: "mcap", "sqlite3" or "".
std::string storageOfContent(const std::filesystem::path& p) {
  if (SqliteReader::looksLikeSqlite(p)) return "sqlite3";
  char head[sizeof(mcap::kMagic)] = {};
  std::ifstream in(p, std::ios::binary);
  in.read(head, sizeof(head));
  return in.gcount() == sizeof(head) && std::memcmp(head, mcap::kMagic, sizeof(head)) == 0 ? "mcap"
                                                                                           : "";
}

/// What to add to the error of a storage file that does not open: what `mcvio bag reindex`
/// (run as `reindex`) does about it, only where it repairs the problem (see BagReindexer:
/// it picks files by extension, finishes or rebuilds MCAP files that start as MCAP, folds an
/// sqlite3 write-ahead log in, rewrites metadata.yaml); otherwise that it cannot.
/// `mcap_recoverable`: an MCAP file whose intact records a recovering scan (reindex) reads.
std::string openFailureHint(const std::filesystem::path& p, const std::string& storage,
                            const std::string& reindex, bool& mcap_recoverable) {
  mcap_recoverable = false;
  const std::string by_extension = storageOfExtension(p);
  const std::string by_content = storageOfContent(p);
  if (!by_content.empty() && by_content == by_extension && by_content != storage) {
    return "; metadata.yaml's storage_identifier is wrong for it: " + reindex +
           " rewrites metadata.yaml from the files";
  }
  if (storage == "mcap" && by_content == "mcap" && by_extension == "mcap") {
    const McapLayout layout = McapReader::layoutOf(p);
    mcap_recoverable = layout != McapLayout::NotMcap;
    switch (layout) {
      case McapLayout::Unfinished:
        return "; " + reindex + " finishes the file, keeping every intact chunk";
      case McapLayout::Finished:
        return "; " + reindex +
               " rebuilds its summary and indexes from the intact records (a damaged record is "
               "dropped with its messages, the original kept as " +
               p.filename().string() + ".orig)";
      case McapLayout::NotMcap:
        break;
    }
  }
  if (storage == "sqlite3" && by_extension == "sqlite3") {
    std::error_code ec;
    std::filesystem::path wal = p;
    wal += "-wal";
    const auto wal_size = std::filesystem::file_size(wal, ec);
    if (!ec && wal_size > 0 && std::filesystem::file_size(p, ec) == 0 && !ec) {
      return "";  // the reader's own message names reindex, which folds the log in
    }
  }
  return "; `mcvio bag reindex` cannot repair this file (none of its messages can be read)";
}

/// What one storage file holds, as metadata.yaml would describe it.
BagMetadata describeFile(const std::filesystem::path& p, const StorageFileReader& r) {
  BagMetadata m;
  m.storage_identifier = p.extension() == ".db3" ? "sqlite3" : "mcap";
  m.relative_file_paths.push_back(p.filename().string());
  const FileStatistics s = r.statistics();
  for (const auto& t : r.topics()) {
    TopicInformation ti;
    ti.topic = t;
    ti.topic.message_definition.clear();
    const auto it = s.topic_message_counts.find(t.name);
    ti.message_count = it == s.topic_message_counts.end() ? 0 : it->second;
    m.topics_with_message_count.push_back(std::move(ti));
  }
  m.message_count = s.message_count;
  m.starting_time = s.start_time;
  m.duration = s.end_time - s.start_time;
  return m;
}

/// Gathers StorageFileReader::verify() results into a BagVerification.
class Collector : public VerifySink {
 public:
  Collector(BagVerification& v, const std::function<void(std::uint64_t)>& progress)
      : v_(v), progress_(progress) {}
  void readable(const std::string& topic) override {
    ++v_.readable;
    ++entry(topic).readable;
    tick();
  }
  void unreadable(const std::string& topic, std::uint64_t count, const std::string& what) override {
    v_.unreadable += count;
    TopicVerification& t = entry(topic);
    if (t.unreadable == 0) t.first_unreadable = what;
    t.unreadable += count;
    tick();
  }
  void problem(const std::string& what) override { v_.problems.push_back(what); }

 private:
  TopicVerification& entry(const std::string& topic) {
    // Messages come in runs of one topic: skip the map lookup for those.
    if (last_ == nullptr || topic != last_name_) {
      last_ = &v_.topics[topic];
      last_name_ = topic;
    }
    return *last_;
  }
  void tick() {
    if (progress_ && (v_.readable + v_.unreadable) >= next_report_) {
      progress_(v_.readable + v_.unreadable);
      next_report_ = v_.readable + v_.unreadable + 20000;
    }
  }
  BagVerification& v_;
  const std::function<void(std::uint64_t)>& progress_;
  TopicVerification* last_ = nullptr;
  std::string last_name_;
  std::uint64_t next_report_ = 20000;
};

/// An MCAP file that does not open strictly but starts as MCAP: reads what a recovering scan
/// keeps (what reindex would keep) and counts the damaged stretches it skips as lost.
void verifyRecovered(const std::filesystem::path& p, VerifySink& sink) {
  McapReader r(p, McapReadMode::Recover);
  for (const auto& d : r.damage()) {
    if (d.unfinished_tail) continue;  // the open error said so already
    const std::string what = p.string() + ": damaged stretch at byte offset " +
                             std::to_string(d.offset) + " (" + std::to_string(d.size) +
                             " bytes): " + d.reason +
                             "; `mcvio bag reindex` drops it and keeps the intact records";
    if (d.messages_lost > 0) {
      sink.unreadable("", static_cast<std::uint64_t>(d.messages_lost), what);
    } else {
      sink.problem(what + (d.messages_lost < 0 ? " (messages lost: unknown)" : ""));
    }
  }
  r.verify(sink);
}

/// The message compression a .db3 file's first message shows, for a file without a
/// metadata.yaml (what reindex would record).
Compression sqliteCompressionOfFile(const std::filesystem::path& p) {
  try {
    return SqliteReader(p).firstMessageCompression().value_or(Compression::None);
  } catch (const InputError&) {
    return Compression::None;  // the open that follows reports it
  }
}

/// The "Verified:" line and the per-topic warnings.
void reportVerification(const BagVerification& v, std::ostream& os,
                        std::vector<std::string>& warn) {
  os << std::left << std::setw(19) << "Verified:" << v.readable << " messages read intact, "
     << v.unreadable << " unreadable";
  if (v.missing > 0) os << ", " << v.missing << " missing";
  if (v.files_unread > 0) os << ", " << v.files_unread << " storage file(s) not readable";
  os << "\n";
  for (const auto& [topic, t] : v.topics) {
    const std::string name =
        topic.empty() ? std::string("messages of unknown topics") : "topic " + topic;
    if (t.unreadable > 0 && topic.empty()) {
      warn.push_back(std::to_string(t.unreadable) +
                     " messages of unknown topics unreadable; the first: " + t.first_unreadable);
    } else if (t.unreadable > 0) {
      warn.push_back(name + ": " + std::to_string(t.unreadable) + " of " +
                     std::to_string(t.readable + t.unreadable) +
                     " messages unreadable; the first: " + t.first_unreadable);
    }
    if (t.missing > 0) {
      warn.push_back(name + ": " + std::to_string(t.missing) + " of the " +
                     std::to_string(t.readable + t.unreadable + t.missing) +
                     " messages metadata.yaml lists were not found (lost with a damaged, cut "
                     "or missing part of the storage files)");
    }
  }
  for (const auto& p : v.problems) warn.push_back(p);
}

/// A single .mcap or .db3 file, described from its own summary.
std::string singleFileInfo(const std::filesystem::path& file, const BagInfoOptions& options,
                           Collector& collector, const BagVerification& verified,
                           std::vector<std::string>& warn) {
  if (file.extension() != ".mcap" && file.extension() != ".db3") {
    throw InputError(file.string() + ": unknown storage (expected a bag directory, .mcap or .db3)");
  }
  const std::string storage = storageOfExtension(file);
  const auto r = openStorageFile(
      file, storage, storage == "sqlite3" ? sqliteCompressionOfFile(file) : Compression::None);
  for (const auto& w : r->warnings()) warn.push_back(w);
  std::string text = formatBagInfo(describeFile(file, *r), std::filesystem::file_size(file));
  if (options.verify) {
    r->verify(collector);
    std::ostringstream os;
    reportVerification(verified, os, warn);
    text += os.str();
  }
  return text;
}

/// metadata.yaml's own fields that look wrong or cannot be read; returns the message
/// compression sqlite3 storage files are read with.
Compression checkMetadataFields(const BagMetadata& m, const std::string& md,
                                std::vector<std::string>& warn) {
  if (m.version > 9) warn.push_back(md + ": version " + std::to_string(m.version) + " is newer than the known 5..9");
  if (m.duration < 0) warn.push_back(md + ": negative duration " + std::to_string(m.duration) + " ns");
  if (m.storage_identifier != "mcap" && m.storage_identifier != "sqlite3") {
    warn.push_back(md + ": unknown storage_identifier '" + m.storage_identifier +
                   "' (expected mcap or sqlite3; `mcvio play` refuses the bag)");
  }
  for (const auto& t : m.topics_with_message_count) {
    if (t.topic.serialization_format != "cdr") {
      warn.push_back(md + ": topic " + t.topic.name + ": unknown serialization_format '" +
                     t.topic.serialization_format + "' (expected cdr)");
    }
  }
  // sqlite3 bags compress each message as metadata.yaml says; reading fails otherwise.
  Compression compression = Compression::None;
  if (m.storage_identifier == "sqlite3" && m.compression_mode == "MESSAGE") {
    try {
      compression = compressionFromString(m.compression_format);
    } catch (const std::invalid_argument& e) {
      warn.push_back(md + ": compression_format: " + e.what());
    }
  } else if (m.compression_mode == "FILE") {
    warn.push_back(md + ": compression_mode FILE (file-compressed bags) cannot be read");
  }
  return compression;
}

/// A bag directory's storage files as opened (and with verify read), against which
/// metadata.yaml is then compared.
struct StoredContent {
  std::uint64_t size = 0;
  std::uint64_t messages = 0;
  std::map<std::string, std::uint64_t> counts;
  std::map<std::string, std::string> types;
  bool all_read = true;            ///< every listed file opened and its statistics read
  bool metadata_disagrees = false; ///< a difference reindex would write into metadata.yaml
};

/// What the file's messages show about metadata.yaml's message compression, and whether its
/// first message reads (sqlite3; `--verify` reads every one). Returns the compression the
/// messages show where metadata.yaml names another.
std::optional<Compression> checkFirstSqliteMessage(SqliteReader& sr, Compression compression,
                                                   const std::string& reindex, StoredContent& stored,
                                                   std::vector<std::string>& warn) {
  std::optional<Compression> shown;
  const auto first_compression = sr.firstMessageCompression();
  if (first_compression && *first_compression != compression) shown = first_compression;
  try {
    BagMessage first;
    sr.next(first);
  } catch (const InputError& e) {
    warn.push_back(e.what() +
                   (shown ? "; metadata.yaml's message compression is not the messages' (" +
                                toString(*shown) + "): " + reindex +
                                " rewrites metadata.yaml from the messages"
                          : std::string("; the stored message itself is damaged and `mcvio bag "
                                        "reindex` cannot recover it")));
    stored.all_read = false;
  }
  return shown;
}

/// What every storage file of one bag directory is read against.
struct BagDirectory {
  const std::filesystem::path& bag;
  const BagMetadata& m;
  std::string md;       ///< metadata.yaml's path, for messages
  std::string reindex;  ///< the `mcvio bag reindex` command for this bag, for hints
  Compression compression;
  const BagInfoOptions& options;
};

/// Opens one storage file metadata.yaml lists (and with verify reads every message), adding
/// what it holds to `stored` and its problems to `warn`.
void inspectListedFile(const BagDirectory& dir, const std::string& rel, Collector& collector,
                       BagVerification& verified, StoredContent& stored, std::vector<std::string>& warn) {
  const BagMetadata& m = dir.m;
  const std::string& md = dir.md;
  const std::string& reindex = dir.reindex;
  const auto p = dir.bag / rel;
  std::error_code ec;
  const auto s = std::filesystem::file_size(p, ec);
  if (ec) {
    warn.push_back(p.string() +
                   (std::filesystem::exists(p)
                        ? ": listed in metadata.yaml but unreadable (" + ec.message() + ")"
                        : ": listed in metadata.yaml but missing (" + reindex +
                              " rewrites metadata.yaml without it; its messages "
                              "stay lost)"));
    stored.all_read = false;
    ++verified.files_unread;
    return;
  }
  stored.size += s;
  std::unique_ptr<StorageFileReader> r;
  try {
    r = openStorageFile(p, m.storage_identifier, dir.compression);
  } catch (const std::exception& e) {
    bool mcap_recoverable = false;
    warn.push_back(e.what() + openFailureHint(p, m.storage_identifier, reindex, mcap_recoverable));
    stored.all_read = false;
    bool recovered = false;
    if (dir.options.verify && mcap_recoverable) {
      try {
        verifyRecovered(p, collector);
        recovered = true;
      } catch (const std::exception&) {
        // Nothing readable: counted as unread below.
      }
    }
    if (!recovered) ++verified.files_unread;
    return;
  }
  for (const auto& w : r->warnings()) warn.push_back(w);
  // Which compression the messages show when metadata.yaml names another (reindex records it).
  std::optional<Compression> shown;
  try {
    const FileStatistics st = r->statistics();
    stored.messages += st.message_count;
    for (const auto& [t, n] : st.topic_message_counts) stored.counts[t] += n;
    for (const auto& t : r->topics()) stored.types.emplace(t.name, t.type);
    for (const auto& f : m.files) {
      if (f.path == rel && f.message_count != st.message_count) {
        warn.push_back(md + ": files entry " + rel + " has " + std::to_string(f.message_count) +
                       " messages but the file holds " + std::to_string(st.message_count));
        stored.metadata_disagrees = true;
      }
    }
    if (m.storage_identifier == "sqlite3") {
      shown = checkFirstSqliteMessage(static_cast<SqliteReader&>(*r), dir.compression, reindex, stored, warn);
    }
  } catch (const InputError& e) {
    // Rows reindex would have to read the same way (unknown topic ids, timestamps or data
    // that are no INTEGER / BLOB) or damaged pages.
    warn.push_back(e.what() + std::string("; `mcvio bag reindex` cannot repair this"));
    stored.all_read = false;
  }
  if (!dir.options.verify) return;
  if (m.storage_identifier == "sqlite3" && shown && *shown != Compression::None) {
    // Check the payloads as the frames they are (metadata.yaml's error is reported above).
    collector.problem(p.string() + ": messages checked as the " + toString(*shown) +
                      " frames they are; readers go by metadata.yaml until " + reindex +
                      " rewrites it");
    static_cast<SqliteReader&>(*r).verify(collector, *shown);
  } else {
    r->verify(collector);
  }
}

/// metadata.yaml's topics, types and counts against what the storage files hold.
void compareWithStorage(const BagMetadata& m, const std::string& md, StoredContent& stored,
                        std::vector<std::string>& warn) {
  for (const auto& t : m.topics_with_message_count) {
    const auto it = stored.types.find(t.topic.name);
    if (it != stored.types.end() && !it->second.empty() && it->second != t.topic.type) {
      warn.push_back(md + ": topic " + t.topic.name + " has type " + t.topic.type +
                     " but the storage's schema is " + it->second);
      stored.metadata_disagrees = true;
    }
    const auto held = stored.counts.find(t.topic.name);
    const std::uint64_t count = held == stored.counts.end() ? 0 : held->second;
    if (stored.all_read && count != t.message_count) {
      warn.push_back(md + ": topic " + t.topic.name + " has " + std::to_string(t.message_count) +
                     " messages but the storage files hold " + std::to_string(count));
      stored.metadata_disagrees = true;
    }
  }
  for (const auto& [name, type] : stored.types) {
    bool listed = false;
    for (const auto& t : m.topics_with_message_count) listed = listed || t.topic.name == name;
    if (!listed) {
      warn.push_back(md + ": topic " + name + " (" + type + ", " +
                     std::to_string(stored.counts[name]) +
                     " messages) is in the storage files but not in metadata.yaml");
      stored.metadata_disagrees = true;
    }
  }
  if (stored.all_read && stored.messages != m.message_count) {
    warn.push_back(md + ": message_count is " + std::to_string(m.message_count) +
                   " but the storage files hold " + std::to_string(stored.messages));
    stored.metadata_disagrees = true;
  }
}

/// With verify and a file that did not open strictly: the messages metadata.yaml lists that no
/// file holds any more. They are lost whatever reindex does. Damaged stretches whose topics are
/// unknown were counted as unreadable already: not again in the total.
void countMissing(const BagMetadata& m, BagVerification& verified) {
  std::uint64_t missing = 0;
  for (const auto& t : m.topics_with_message_count) {
    TopicVerification& v = verified.topics[t.topic.name];
    const std::uint64_t held = v.readable + v.unreadable;
    if (held < t.message_count) {
      v.missing = t.message_count - held;
      missing += v.missing;
    }
  }
  const auto unknown = verified.topics.find("");
  const std::uint64_t unattributed = unknown == verified.topics.end() ? 0 : unknown->second.unreadable;
  verified.missing = missing > unattributed ? missing - unattributed : 0;
}

}  // namespace

std::string bagInfo(const std::filesystem::path& bag, std::vector<std::string>* warnings) {
  return bagInfo(bag, warnings, BagInfoOptions{});
}

std::string bagInfo(const std::filesystem::path& bag, std::vector<std::string>* warnings,
                    const BagInfoOptions& options, BagVerification* verification) {
  std::vector<std::string> ignored;
  auto& warn = warnings ? *warnings : ignored;
  BagVerification local_verification;
  BagVerification& verified = verification ? *verification : local_verification;
  verified = BagVerification{};
  Collector collector(verified, options.progress);
  if (std::filesystem::is_regular_file(bag)) return singleFileInfo(bag, options, collector, verified, warn);

  const BagMetadata m = readBagMetadata(bag);
  BagDirectory dir{bag, m, (bag / kMetadataFileName).string(), "`mcvio bag reindex " + bag.string() + "`",
                   Compression::None, options};
  const std::string& md = dir.md;
  dir.compression = checkMetadataFields(m, md, warn);
  StoredContent stored;
  for (const auto& rel : m.relative_file_paths) inspectListedFile(dir, rel, collector, verified, stored, warn);
  compareWithStorage(m, md, stored, warn);
  if (options.verify && !stored.all_read) countMissing(m, verified);
  if (stored.metadata_disagrees) {
    warn.push_back(md + ": " + dir.reindex + " rewrites it from what the storage files hold");
  }
  std::string text = formatBagInfo(m, stored.size);
  if (options.verify) {
    std::ostringstream os;
    reportVerification(verified, os, warn);
    text += os.str();
  }
  return text;
}

}  // namespace mcvio::bag
