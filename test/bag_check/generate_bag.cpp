// Writes MCAP bags with known std_msgs/msg/String and geometry_msgs/msg/PoseStamped messages
// (CDR, little endian) for an independent reader to check, plus expected.json describing them.
//   bag_check_generator OUT_DIR  -> OUT_DIR/{none,zstd,lz4,repaired}/ and OUT_DIR/expected.json
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/bag/bag_reindexer.hpp"
#include "mcvio/bag/bag_writer.hpp"

namespace {

const char* const kQos =
    "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 2\n  deadline:\n    sec: "
    "9223372036\n    nsec: 854775807\n  lifespan:\n    sec: 9223372036\n    nsec: 854775807\n  "
    "liveliness: 1\n  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n  "
    "avoid_ros_namespace_conventions: false";

const char* const kPoseStamped =
    "# A Pose with reference coordinate frame and timestamp\n\n"
    "std_msgs/Header header\nPose pose\n\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "# Standard metadata for higher-level stamped data types.\n"
    "builtin_interfaces/Time stamp\nstring frame_id\n\n"
    "================================================================================\n"
    "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Pose\nPoint position\nQuaternion orientation\n\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";

/// Minimal little-endian CDR (XCDR1) writer: 4-byte encapsulation header, then fields aligned
/// to their size relative to the end of that header.
class Cdr {
 public:
  Cdr() : buf_{0x00, 0x01, 0x00, 0x00} {}
  template <typename T>
  void put(T v) {
    align(sizeof(T));
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    buf_.insert(buf_.end(), p, p + sizeof(T));
  }
  void putString(const std::string& s) {
    put<std::uint32_t>(static_cast<std::uint32_t>(s.size() + 1));
    buf_.insert(buf_.end(), s.begin(), s.end());
    buf_.push_back(0);
  }
  const std::vector<std::uint8_t>& bytes() const { return buf_; }

 private:
  void align(std::size_t n) {
    while ((buf_.size() - 4) % n != 0) buf_.push_back(0);
  }
  std::vector<std::uint8_t> buf_;
};

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.17g", v);
  return b;
}

std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

}  // namespace

namespace {

struct Generated {
  std::string topic;
  std::int64_t log = 0;
  std::int64_t pub = 0;
  std::vector<std::uint8_t> cdr;
  std::string value_json;
};

std::vector<Generated> generateMessages(int n) {
  std::vector<Generated> out;
  const std::int64_t t0 = 1700000000000000000;
  for (int i = 0; i < n; ++i) {
    Generated g;
    g.log = t0 + i * 5000000LL;
    g.pub = g.log - 1000;
    Cdr cdr;
    if (i % 2 == 0) {
      g.topic = "/chatter";
      const std::string text = "hello mcvio " + std::to_string(i) + std::string(i % 13, 'x');
      cdr.putString(text);
      g.value_json = "{\"data\": " + jsonString(text) + "}";
    } else {
      g.topic = "/pose";
      const std::int32_t sec = 1700000000 + i;
      const auto nsec = static_cast<std::uint32_t>(i * 1000);
      const std::string frame = i % 3 ? "map" : "odom_frame";
      const double x = i * 0.25, y = -i * 0.5, z = 1.0 + i, qx = 0.0, qy = 0.0, qz = (i % 2) * 0.5,
                   qw = 0.75;
      cdr.put(sec);
      cdr.put(nsec);
      cdr.putString(frame);
      for (double v : {x, y, z, qx, qy, qz, qw}) cdr.put(v);
      g.value_json = "{\"header\": {\"stamp\": {\"sec\": " + std::to_string(sec) +
                     ", \"nanosec\": " + std::to_string(nsec) +
                     "}, \"frame_id\": " + jsonString(frame) +
                     "}, \"pose\": {\"position\": {\"x\": " + num(x) + ", \"y\": " + num(y) +
                     ", \"z\": " + num(z) + "}, \"orientation\": {\"x\": " + num(qx) +
                     ", \"y\": " + num(qy) + ", \"z\": " + num(qz) + ", \"w\": " + num(qw) + "}}}";
    }
    g.cdr = cdr.bytes();
    out.push_back(std::move(g));
  }
  return out;
}

void writeBag(const std::filesystem::path& dir, mcvio::bag::Compression c,
              const std::vector<Generated>& messages) {
  mcvio::bag::BagWriterOptions o;
  o.compression = c;
  o.chunk_size = 2048;  // several chunks, so indexes matter
  mcvio::bag::BagWriter w(dir, o);
  w.addTopic({"/chatter", "std_msgs/msg/String", "cdr", kQos, "string data\n",
              "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"});
  w.addTopic({"/pose", "geometry_msgs/msg/PoseStamped", "cdr", kQos, kPoseStamped, ""});
  for (const auto& m : messages) w.write(m.topic, m.log, m.pub, m.cdr.data(), m.cdr.size());
  w.close();
}

void appendJson(std::ostringstream& json, bool& first, const std::string& bag, const Generated& m) {
  json << (first ? "" : ",\n") << "{\"bag\": \"" << bag << "\", \"topic\": \"" << m.topic
       << "\", \"log_time\": \"" << m.log << "\", \"publish_time\": \"" << m.pub
       << "\", \"value\": " << m.value_json << "}";
  first = false;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: bag_check_generator OUT_DIR\n";
    return 2;
  }
  const std::filesystem::path out(argv[1]);
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  const auto messages = generateMessages(240);
  std::ostringstream json;
  json << "{\"messages\": [\n";
  bool first = true;
  for (auto c : {mcvio::bag::Compression::None, mcvio::bag::Compression::Zstd,
                 mcvio::bag::Compression::Lz4}) {
    writeBag(out / mcvio::bag::toString(c), c, messages);
    for (const auto& m : messages) appendJson(json, first, mcvio::bag::toString(c), m);
  }
  // A recording cut short (the file ends inside a chunk, no summary), then reindexed: the
  // independent reader must accept the repaired file and find the recovered messages intact.
  const auto repaired = out / "repaired";
  writeBag(repaired, mcvio::bag::Compression::Zstd, messages);
  const auto file = repaired / "repaired_0.mcap";
  std::filesystem::resize_file(file, std::filesystem::file_size(file) * 6 / 10);
  mcvio::bag::BagReindexer::reindex(repaired);
  mcvio::bag::BagReader reader(repaired);
  std::size_t k = 0;
  for (mcvio::bag::BagMessage m; reader.next(m); ++k) {
    if (k >= messages.size() || m.data != messages[k].cdr || m.log_time != messages[k].log) {
      std::cerr << "repaired bag: message " << k << " differs from what was written\n";
      return 1;
    }
    appendJson(json, first, "repaired", messages[k]);
  }
  if (k == 0 || k == messages.size()) {
    std::cerr << "repaired bag: expected a strict, non-empty prefix, got " << k << "\n";
    return 1;
  }
  json << "\n]}\n";
  std::ofstream(out / "expected.json") << json.str();
  std::cout << "wrote 3 bags of " << messages.size() << " messages and a repaired bag keeping " << k
            << "\n";
  return 0;
}
