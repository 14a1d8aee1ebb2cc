// Writes MCAP bags with known std_msgs/msg/String and geometry_msgs/msg/PoseStamped messages
// (CDR, little endian) for an independent reader to check, plus expected.json describing them.
//   bag_check_generator OUT_DIR      -> OUT_DIR/{none,zstd,lz4}/ and OUT_DIR/expected.json
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

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

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: bag_check_generator OUT_DIR\n";
    return 2;
  }
  const std::filesystem::path out(argv[1]);
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  std::ostringstream json;
  json << "{\"messages\": [\n";
  bool first = true;
  const std::int64_t t0 = 1700000000000000000;
  for (auto c : {mcvio::bag::Compression::None, mcvio::bag::Compression::Zstd,
                 mcvio::bag::Compression::Lz4}) {
    mcvio::bag::BagWriterOptions o;
    o.compression = c;
    o.chunk_size = 2048;  // several chunks, so indexes matter
    const auto dir = out / mcvio::bag::toString(c);
    mcvio::bag::BagWriter w(dir, o);
    w.addTopic({"/chatter", "std_msgs/msg/String", "cdr", kQos, "string data\n",
                "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"});
    w.addTopic({"/pose", "geometry_msgs/msg/PoseStamped", "cdr", kQos, kPoseStamped, ""});
    for (int i = 0; i < 120; ++i) {
      const std::int64_t log = t0 + i * 5000000LL;
      const std::int64_t pub = log - 1000;
      std::string value;
      std::string topic;
      Cdr cdr;
      if (i % 2 == 0) {
        topic = "/chatter";
        const std::string text = "hello mcvio " + std::to_string(i) + std::string(i % 13, 'x');
        cdr.putString(text);
        value = "{\"data\": " + jsonString(text) + "}";
      } else {
        topic = "/pose";
        const std::int32_t sec = 1700000000 + i;
        const std::uint32_t nsec = static_cast<std::uint32_t>(i * 1000);
        const std::string frame = i % 3 ? "map" : "odom_frame";
        const double x = i * 0.25, y = -i * 0.5, z = 1.0 + i, qx = 0.0, qy = 0.0,
                     qz = (i % 2) * 0.5, qw = 0.75;
        cdr.put(sec);
        cdr.put(nsec);
        cdr.putString(frame);
        for (double v : {x, y, z, qx, qy, qz, qw}) cdr.put(v);
        value = "{\"header\": {\"stamp\": {\"sec\": " + std::to_string(sec) +
                ", \"nanosec\": " + std::to_string(nsec) + "}, \"frame_id\": " + jsonString(frame) +
                "}, \"pose\": {\"position\": {\"x\": " + num(x) + ", \"y\": " + num(y) +
                ", \"z\": " + num(z) + "}, \"orientation\": {\"x\": " + num(qx) +
                ", \"y\": " + num(qy) + ", \"z\": " + num(qz) + ", \"w\": " + num(qw) + "}}}";
      }
      w.write(topic, log, pub, cdr.bytes().data(), cdr.bytes().size());
      json << (first ? "" : ",\n") << "{\"bag\": \"" << mcvio::bag::toString(c)
           << "\", \"topic\": \"" << topic << "\", \"log_time\": \"" << log
           << "\", \"publish_time\": \"" << pub << "\", \"value\": " << value << "}";
      first = false;
    }
    w.close();
  }
  json << "\n]}\n";
  std::ofstream(out / "expected.json") << json.str();
  return 0;
}
