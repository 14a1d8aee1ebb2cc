#include "mcvio/bag/bag_info.hpp"

#include <ctime>
#include <iomanip>
#include <sstream>

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

std::string bagInfo(const std::filesystem::path& bag_dir) {
  const BagMetadata m = readBagMetadata(bag_dir);
  std::uint64_t size = 0;
  for (const auto& rel : m.relative_file_paths) {
    std::error_code ec;
    const auto s = std::filesystem::file_size(bag_dir / rel, ec);
    if (!ec) size += s;
  }
  return formatBagInfo(m, size);
}

}  // namespace mcvio::bag
