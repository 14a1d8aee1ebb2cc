#include "bag_test_util.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include "mcvio/bag/bag_reader.hpp"

namespace mcvio::bag::test {

const char* const kStringDefinition = "string data\n";

const char* const kPoseStampedDefinition =
    "# A Pose with reference coordinate frame and timestamp\n"
    "\n"
    "std_msgs/Header header\n"
    "Pose pose\n"
    "\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "# Standard metadata for higher-level stamped data types.\n"
    "builtin_interfaces/Time stamp\n"
    "string frame_id\n"
    "\n"
    "================================================================================\n"
    "MSG: builtin_interfaces/Time\n"
    "int32 sec\n"
    "uint32 nanosec\n"
    "\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Pose\n"
    "Point position\n"
    "Quaternion orientation\n"
    "\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Point\n"
    "float64 x\n"
    "float64 y\n"
    "float64 z\n"
    "\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Quaternion\n"
    "float64 x 0\n"
    "float64 y 0\n"
    "float64 z 0\n"
    "float64 w 1\n";

namespace {
const char* const kQos =
    "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 2\n  deadline:\n    sec: "
    "9223372036\n    nsec: 854775807\n  lifespan:\n    sec: 9223372036\n    nsec: 854775807\n  "
    "liveliness: 1\n  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n  "
    "avoid_ros_namespace_conventions: false";
}

TopicInfo stringTopic(const std::string& name) {
  TopicInfo t;
  t.name = name;
  t.type = "std_msgs/msg/String";
  t.offered_qos_profiles = kQos;
  t.message_definition = kStringDefinition;
  t.type_description_hash =
      "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18";
  return t;
}

TopicInfo poseStampedTopic(const std::string& name) {
  TopicInfo t;
  t.name = name;
  t.type = "geometry_msgs/msg/PoseStamped";
  t.offered_qos_profiles = kQos;
  t.message_definition = kPoseStampedDefinition;
  return t;
}

namespace {

std::filesystem::path scratchBase() {
  return std::filesystem::temp_directory_path() / ("mcvio_bag_test_" + std::to_string(::getpid()));
}

/// Removes this process's scratch bags when the tests end.
class ScratchCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(scratchBase(), ec);
  }
};

[[maybe_unused]] const ::testing::Environment* const kCleanup =
    ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

}  // namespace

std::filesystem::path freshPath(const std::string& name) {
  const auto base = scratchBase();
  std::filesystem::create_directories(base);
  const auto p = base / name;
  std::filesystem::remove_all(p);
  return p;
}

std::vector<std::uint8_t> payload(std::uint64_t i, std::size_t size) {
  std::vector<std::uint8_t> v(size);
  std::uint64_t x = i * 0x9E3779B97F4A7C15ull + 12345;
  for (auto& b : v) {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    b = static_cast<std::uint8_t>(x);
  }
  return v;
}

std::vector<BagMessage> readAll(const std::filesystem::path& bag) {
  BagReader r(bag);
  std::vector<BagMessage> out;
  BagMessage m;
  while (r.next(m)) out.push_back(m);
  return out;
}

BagVerification verifyBag(const std::filesystem::path& bag, std::vector<std::string>* warnings) {
  BagInfoOptions o;
  o.verify = true;
  BagVerification v;
  bagInfo(bag, warnings, o, &v);
  return v;
}

std::vector<std::string> reindexAdvice(const std::vector<std::string>& warnings) {
  std::vector<std::string> out;
  for (const auto& w : warnings) {
    if (w.find("mcvio bag reindex") != std::string::npos && w.find("cannot") == std::string::npos) {
      out.push_back(w);
    }
  }
  return out;
}

}  // namespace mcvio::bag::test
