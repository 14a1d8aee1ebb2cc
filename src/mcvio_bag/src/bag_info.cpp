#include "mcvio/bag/bag_info.hpp"

#include <ctime>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>

#include "mcvio/bag/mcap_reader.hpp"
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
  return p.extension() == ".db3" ? "sqlite3" : "mcap";
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

}  // namespace

std::string bagInfo(const std::filesystem::path& bag, std::vector<std::string>* warnings) {
  std::vector<std::string> ignored;
  auto& warn = warnings ? *warnings : ignored;
  if (std::filesystem::is_regular_file(bag)) {
    if (bag.extension() != ".mcap" && bag.extension() != ".db3") {
      throw InputError(bag.string() + ": unknown storage (expected a bag directory, .mcap or .db3)");
    }
    const auto r = openStorageFile(bag, storageOfExtension(bag));
    for (const auto& w : r->warnings()) warn.push_back(w);
    return formatBagInfo(describeFile(bag, *r), std::filesystem::file_size(bag));
  }
  const BagMetadata m = readBagMetadata(bag);
  const std::string md = (bag / kMetadataFileName).string();
  if (m.version > 9) warn.push_back(md + ": version " + std::to_string(m.version) + " is newer than the known 5..9");
  if (m.duration < 0) warn.push_back(md + ": negative duration " + std::to_string(m.duration) + " ns");
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
  std::uint64_t size = 0;
  std::uint64_t stored_messages = 0;
  std::map<std::string, std::uint64_t> stored_counts;
  std::map<std::string, std::string> stored_types;
  bool all_read = true;
  for (const auto& rel : m.relative_file_paths) {
    const auto p = bag / rel;
    std::error_code ec;
    const auto s = std::filesystem::file_size(p, ec);
    if (ec) {
      warn.push_back(p.string() + (std::filesystem::exists(p)
                                       ? ": listed in metadata.yaml but unreadable (" +
                                             ec.message() + ")"
                                       : ": listed in metadata.yaml but missing"));
      all_read = false;
      continue;
    }
    size += s;
    try {
      const auto r = openStorageFile(p, m.storage_identifier, compression);
      for (const auto& w : r->warnings()) warn.push_back(w);
      const FileStatistics st = r->statistics();
      stored_messages += st.message_count;
      for (const auto& [t, n] : st.topic_message_counts) stored_counts[t] += n;
      for (const auto& t : r->topics()) stored_types.emplace(t.name, t.type);
      for (const auto& f : m.files) {
        if (f.path == rel && f.message_count != st.message_count) {
          warn.push_back(md + ": files entry " + rel + " has " + std::to_string(f.message_count) +
                         " messages but the file holds " + std::to_string(st.message_count));
        }
      }
      if (m.storage_identifier == "sqlite3") {
        // The first message shows whether the message compression and payloads are readable.
        BagMessage first;
        r->next(first);
      }
    } catch (const std::exception& e) {
      warn.push_back(std::string(e.what()) + " (see `mcvio bag reindex " + bag.string() + "`)");
      all_read = false;
    }
  }
  for (const auto& t : m.topics_with_message_count) {
    const auto it = stored_types.find(t.topic.name);
    if (it != stored_types.end() && !it->second.empty() && it->second != t.topic.type) {
      warn.push_back(md + ": topic " + t.topic.name + " has type " + t.topic.type +
                     " but the storage's schema is " + it->second);
    }
    if (all_read && (stored_counts.count(t.topic.name) ? stored_counts[t.topic.name] : 0) !=
                        t.message_count) {
      warn.push_back(md + ": topic " + t.topic.name + " has " + std::to_string(t.message_count) +
                     " messages but the storage files hold " +
                     std::to_string(stored_counts[t.topic.name]));
    }
  }
  for (const auto& [name, type] : stored_types) {
    bool listed = false;
    for (const auto& t : m.topics_with_message_count) listed = listed || t.topic.name == name;
    if (!listed) {
      warn.push_back(md + ": topic " + name + " (" + type + ", " +
                     std::to_string(stored_counts[name]) +
                     " messages) is in the storage files but not in metadata.yaml");
    }
  }
  if (all_read && stored_messages != m.message_count) {
    warn.push_back(md + ": message_count is " + std::to_string(m.message_count) +
                   " but the storage files hold " + std::to_string(stored_messages));
  }
  return formatBagInfo(m, size);
}

}  // namespace mcvio::bag
