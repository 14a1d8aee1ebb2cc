#include "mcvio/bag/bag_reader.hpp"

#include <set>

#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/bag/sqlite_reader.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

BagReader::BagReader(const std::filesystem::path& bag, BagReaderOptions options) : bag_(bag) {
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_regular_file(bag)) {
    const auto ext = bag.extension().string();
    if (ext == ".mcap") {
      metadata_.storage_identifier = "mcap";
    } else if (ext == ".db3") {
      metadata_.storage_identifier = "sqlite3";
    } else {
      throw InputError(bag.string() +
                       ": unknown storage (expected a bag directory, .mcap or .db3)");
    }
    metadata_.relative_file_paths.push_back(bag.filename().string());
    files.push_back(bag);
  } else if (std::filesystem::is_directory(bag)) {
    metadata_ = readBagMetadata(bag);
    if (metadata_.storage_identifier != "mcap" && metadata_.storage_identifier != "sqlite3") {
      throw InputError((bag / kMetadataFileName).string() + ": unknown storage_identifier '" +
                       metadata_.storage_identifier + "' (expected mcap or sqlite3)");
    }
    if (metadata_.compression_mode == "FILE") {
      throw InputError((bag / kMetadataFileName).string() +
                       ": file-compressed bags (compression_mode FILE) are not supported");
    }
    for (const auto& rel : metadata_.relative_file_paths) {
      const auto p = bag / rel;
      if (!std::filesystem::exists(p)) {
        throw InputError(p.string() + ": listed in metadata.yaml but missing");
      }
      files.push_back(p);
    }
  } else {
    throw InputError(bag.string() + ": no such bag directory or file");
  }
  openFiles(files, options);
}

BagReader::~BagReader() = default;

bool BagReader::looksLikeBag(const std::filesystem::path& path) {
  const auto isStorage = [](const std::filesystem::path& p) {
    return p.extension() == ".mcap" || p.extension() == ".db3";
  };
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) return isStorage(path);
  if (!std::filesystem::is_directory(path, ec)) return false;
  if (std::filesystem::exists(path / kMetadataFileName, ec)) return true;
  for (const auto& e : std::filesystem::directory_iterator(path, ec)) {
    if (e.is_regular_file(ec) && isStorage(e.path())) return true;
  }
  return false;
}

void BagReader::openFiles(const std::vector<std::filesystem::path>& files,
                          const BagReaderOptions& o) {
  Compression message_compression = Compression::None;
  if (metadata_.storage_identifier == "sqlite3" && metadata_.compression_mode == "MESSAGE") {
    try {
      message_compression = compressionFromString(metadata_.compression_format);
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("metadata.yaml: compression_format: ") + e.what());
    }
  }
  const std::set<std::string> filter(o.topics.begin(), o.topics.end());
  std::set<std::string> seen;
  for (const auto& p : files) {
    std::unique_ptr<StorageFileReader> r;
    if (metadata_.storage_identifier == "mcap") {
      // Otherwise the MCAP reader could only say "wrong magic".
      if (SqliteReader::looksLikeSqlite(p)) {
        throw InputError(p.string() +
                         ": is an sqlite3 database, but metadata.yaml's storage_identifier (or "
                         "the file's extension) says mcap");
      }
      r = std::make_unique<McapReader>(
          p, o.allow_unfinished ? McapReadMode::Recover : McapReadMode::Strict);
    } else {
      r = std::make_unique<SqliteReader>(p, message_compression);
    }
    r->setTopicFilter(filter);
    for (const auto& w : r->warnings()) warnings_.push_back(w);
    for (const auto& t : r->topics()) {
      if (seen.insert(t.name).second) topics_.push_back(t);
    }
    files_.push_back(std::move(r));
    paths_.push_back(p);
  }
  for (const auto& m : metadata_.topics_with_message_count) {
    for (const auto& t : topics_) {
      if (t.name == m.topic.name && !t.type.empty() && t.type != m.topic.type) {
        warnings_.push_back("topic " + t.name + ": metadata.yaml says " + m.topic.type +
                            ", the storage's schema says " + t.type + " (the schema is used)");
      }
    }
  }
  heads_.resize(files_.size());
  has_head_.assign(files_.size(), false);
  for (std::size_t i = 0; i < files_.size(); ++i) has_head_[i] = readHead(i);
}

bool BagReader::readHead(std::size_t i) {
  try {
    return files_[i]->next(heads_[i]);
  } catch (const InputError& e) {
    // Damage met mid-way (a chunk's CRC, a record cut short): say what repairs it, where reindex
    // does. An sqlite3 database it cannot repair, and some messages already name it.
    const std::string what = e.what();
    if (metadata_.storage_identifier != "mcap" || what.find("reindex") != std::string::npos) throw;
    throw InputError(what + "; `mcvio bag reindex " + bag_.string() +
                     "` rewrites the file without the damaged records, keeping every intact chunk, and `mcvio bag "
                     "info --verify " + bag_.string() + "` lists the messages lost");
  }
}

bool BagReader::next(BagMessage& out) {
  std::size_t best = files_.size();
  for (std::size_t i = 0; i < files_.size(); ++i) {
    if (has_head_[i] && (best == files_.size() || heads_[i].log_time < heads_[best].log_time)) {
      best = i;
    }
  }
  if (best == files_.size()) return false;
  std::swap(out, heads_[best]);
  last_file_ = best;
  has_head_[best] = readHead(best);
  return true;
}

std::optional<BagMessage> BagReader::next() {
  BagMessage m;
  if (!next(m)) return std::nullopt;
  return m;
}

std::string BagReader::where(const BagMessage& m) const {
  const std::string file = last_file_ < paths_.size() ? paths_[last_file_].string() : "bag";
  return file + ": topic " + m.topic + ", message at log time " + std::to_string(m.log_time) +
         " ns";
}

FileStatistics BagReader::statistics() const {
  FileStatistics total;
  for (const auto& f : files_) {
    const FileStatistics s = f->statistics();
    for (const auto& [t, n] : s.topic_message_counts) total.topic_message_counts[t] += n;
    if (s.message_count == 0) continue;
    if (total.message_count == 0) {
      total.start_time = s.start_time;
      total.end_time = s.end_time;
    } else {
      total.start_time = std::min(total.start_time, s.start_time);
      total.end_time = std::max(total.end_time, s.end_time);
    }
    total.message_count += s.message_count;
  }
  return total;
}

}  // namespace mcvio::bag
