#include "mcvio/bag/bag_reindexer.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>

#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/bag/mcap_repairer.hpp"
#include "mcvio/bag/sqlite_reader.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

namespace {

/// The split number n of "<name>_<n>.<ext>", or -1.
long splitIndex(const std::filesystem::path& p) {
  const std::string stem = p.stem().string();
  const auto us = stem.rfind('_');
  if (us == std::string::npos || us + 1 == stem.size()) return -1;
  const std::string digits = stem.substr(us + 1);
  if (!std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }) ||
      digits.size() > 9) {
    return -1;
  }
  return std::stol(digits);
}

}  // namespace

BagMetadata BagReindexer::reindex(const std::filesystem::path& bag_dir,
                                  std::vector<std::string>* log,
                                  std::vector<std::string>* damage) {
  if (!std::filesystem::is_directory(bag_dir)) {
    throw InputError(bag_dir.string() + ": not a bag directory");
  }
  BagMetadata old;
  bool have_old = false;
  try {
    old = readBagMetadata(bag_dir);
    have_old = true;
  } catch (const InputError&) {
    // Missing or damaged: rebuilt from the files alone.
  }
  std::vector<std::filesystem::path> mcaps;
  std::vector<std::filesystem::path> dbs;
  for (const auto& e : std::filesystem::directory_iterator(bag_dir)) {
    if (!e.is_regular_file()) continue;
    const auto ext = e.path().extension().string();
    if (ext == ".mcap") mcaps.push_back(e.path());
    if (ext == ".db3") dbs.push_back(e.path());
  }
  if (mcaps.empty() && dbs.empty()) {
    throw InputError(bag_dir.string() + ": no .mcap or .db3 storage files to reindex");
  }
  if (!mcaps.empty() && !dbs.empty()) {
    throw InputError(bag_dir.string() +
                     ": holds both .mcap and .db3 files; which storage is meant?");
  }
  auto files = mcaps.empty() ? dbs : mcaps;
  if (have_old && log) {
    // The new metadata.yaml lists what is there: say which listed files it leaves out.
    for (const auto& rel : old.relative_file_paths) {
      if (std::none_of(files.begin(), files.end(),
                       [&](const auto& f) { return f.filename() == rel; })) {
        log->push_back("WARNING: " + rel +
                       " is listed in the old metadata.yaml but is not here: left out of the "
                       "new one");
      }
    }
  }
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) {
    const long ia = splitIndex(a);
    const long ib = splitIndex(b);
    return ia != ib ? ia < ib : a.filename() < b.filename();
  });

  BagMetadata m;
  m.storage_identifier = mcaps.empty() ? "sqlite3" : "mcap";
  if (have_old) {
    m.ros_distro = old.ros_distro;
    m.custom_data = old.custom_data;
    m.compression_format = old.compression_format;
    m.compression_mode = old.compression_mode;
  }
  std::vector<TopicInformation> topics;
  std::map<std::string, std::size_t> topic_pos;
  bool any = false;
  Timestamp start = 0;
  Timestamp end = 0;
  // A file that cannot be read at all (not MCAP, a damaged sqlite3 database) stays where it is
  // and out of metadata.yaml; the others are indexed. Only when none can be read is it an error.
  std::optional<InputError> first_unreadable;
  for (const auto& path : files) {
    try {
      std::unique_ptr<StorageFileReader> reader;
      if (m.storage_identifier == "mcap") {
        const McapRepairReport rep = McapRepairer::repair(path);
        const std::string file = path.filename().string();
        if (log) {
          log->push_back(file +
                         (rep.was_complete
                              ? ": intact"
                              : ": repaired, kept " + std::to_string(rep.kept_bytes) +
                                    " bytes, dropped " + std::to_string(rep.dropped_bytes)) +
                         ", " + std::to_string(rep.chunks) + " chunks, " +
                         std::to_string(rep.messages) + " messages");
        }
        for (const auto& d : rep.damage) {
          const std::string lost =
              d.messages_lost < 0 ? "messages lost unknown"
                                  : std::to_string(d.messages_lost) + " messages lost";
          const std::string where = " at byte offset " + std::to_string(d.offset) + " (" +
                                    std::to_string(d.size) + " bytes, " + lost + ")";
          if (d.unfinished_tail) {
            if (log) {
              log->push_back(file + ": WARNING: dropped the unfinished record at the end" + where +
                             ": " + d.reason);
            }
          } else if (damage) {
            damage->push_back(file + ": dropped damaged data" + where + ": " + d.reason);
          }
        }
        if (log && !rep.original.empty()) {
          log->push_back(file + ": original kept unchanged as " + rep.original.string());
        }
        reader = std::make_unique<McapReader>(path, McapReadMode::Strict);
      } else {
        const bool folded = SqliteReader::recover(path);
        auto sr = std::make_unique<SqliteReader>(path);
        if (!have_old) {
          // The file's own copy of the metadata knows the message compression.
          const std::string yaml = sr->storedMetadataYaml();
          if (!yaml.empty()) {
            try {
              const BagMetadata stored = bagMetadataFromYaml(yaml, path.string());
              m.compression_format = stored.compression_format;
              m.compression_mode = stored.compression_mode;
              m.ros_distro = stored.ros_distro;
            } catch (const InputError&) {
              // Unreadable copy: keep the defaults.
            }
          }
        }
        // The messages themselves show their compression; a metadata.yaml that says otherwise
        // (edited, or copied from another bag) would make every reader fail.
        if (const auto seen = sr->firstMessageCompression()) {
          Compression said = Compression::None;
          bool known = true;
          try {
            if (m.compression_mode == "MESSAGE") said = compressionFromString(m.compression_format);
          } catch (const std::invalid_argument&) {
            known = false;
          }
          if (!known || said != *seen) {
            if (log) {
              log->push_back("WARNING: " + path.filename().string() + ": metadata.yaml said message compression '" +
                             (m.compression_mode == "MESSAGE" ? m.compression_format : std::string("none")) +
                             "', the messages are " + toString(*seen) + ": the new metadata.yaml says " +
                             toString(*seen));
            }
            m.compression_format = *seen == Compression::None ? "" : toString(*seen);
            m.compression_mode = *seen == Compression::None ? "" : "MESSAGE";
          }
        }
        if (log) {
          log->push_back(path.filename().string() +
                         (folded ? ": a killed writer's write-ahead log or journal folded in"
                                 : ": intact (no write-ahead log)"));
          for (const auto& w : sr->warnings()) log->push_back("WARNING: " + w);
        }
        reader = std::move(sr);
      }
      const FileStatistics s = reader->statistics();
      for (const auto& t : reader->topics()) {
        if (topic_pos.count(t.name)) continue;
        topic_pos[t.name] = topics.size();
        TopicInformation ti;
        ti.topic = t;
        ti.topic.message_definition.clear();
        topics.push_back(std::move(ti));
      }
      for (const auto& [name, n] : s.topic_message_counts) {
        if (topic_pos.count(name)) topics[topic_pos[name]].message_count += n;
      }
      FileInformation fi;
      fi.path = path.filename().string();
      // A complete metadata.yaml from before the damage knows how many messages were lost.
      if (have_old && log) {
        for (const auto& before : old.files) {
          if (before.path == fi.path && before.message_count > s.message_count) {
            log->push_back("WARNING: " + fi.path + ": the old metadata.yaml listed " +
                           std::to_string(before.message_count) + " messages, " +
                           std::to_string(s.message_count) + " are readable: " +
                           std::to_string(before.message_count - s.message_count) + " lost");
          }
        }
      }
      fi.message_count = s.message_count;
      fi.starting_time = s.start_time;
      fi.duration = s.end_time - s.start_time;
      m.relative_file_paths.push_back(fi.path);
      m.files.push_back(fi);
      if (s.message_count > 0) {
        start = any ? std::min(start, s.start_time) : s.start_time;
        end = any ? std::max(end, s.end_time) : s.end_time;
        any = true;
      }
      m.message_count += s.message_count;
    } catch (const InputError& e) {
      if (!first_unreadable) first_unreadable = e;
      if (damage) {
        damage->push_back(path.filename().string() + ": not indexed, none of its messages can be read (" + e.what() +
                          "); the file is left as it was");
      }
    }
  }
  if (m.files.empty() && first_unreadable) throw *first_unreadable;
  m.topics_with_message_count = std::move(topics);
  m.starting_time = start;
  m.duration = end - start;
  writeBagMetadata(bag_dir, m);
  return m;
}

}  // namespace mcvio::bag
