// `mcvio launch`: launch files resolve their arguments, substitutions and conditions into a plan,
// bad launch files name the file, line and key, the shipped config/pipeline.yaml resolves, and a
// lossless launch of it (player, frontend, backend, recorder in one process) records the poses
// `mcvio run` gives on the same data.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/components/launch_file.hpp"
#include "mcvio/components/launcher.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/sim/simulator.hpp"
#include "component_test_support.hpp"

using namespace mcvio;
using components::LaunchFile;
using components::LaunchPlan;

namespace {

const char* kFile = R"(arguments:
  data: {description: "EuRoC folder"}
  mode: {default: selective}
  play: {default: "true"}
  bag: {default: "$(arg data)/bag"}
components:
  - component: recorder
    unless: $(arg play)
    output: $(arg bag)
    all: true
  - component: frontend
    calibration: $(arg data)
    tracks_image: true
  - component: backend
    name: estimator
    calibration: $(arg data)
    mode: $(arg mode)
    world_frame: $(env MCVIO_TEST_LAUNCH_FRAME odom)
  - component: player
    if: $(arg play)
    input: $(dirname)/$(arg data)
    rate: 2.5
)";

std::string errorOf(const std::string& text, const std::map<std::string, std::string>& values = {{"data", "d"}}) {
  try {
    LaunchFile::parse(text, "test.yaml", "/base").resolve(values);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string loadErrorOf(const std::string& path) {
  try {
    LaunchFile::load(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

template <class T>
T deserialize(const std::vector<std::uint8_t>& data) {
  typename interfaces::RosType<T>::PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t p(static_cast<std::uint32_t>(data.size()));
  std::memcpy(p.data, data.data(), data.size());
  p.length = static_cast<std::uint32_t>(data.size());
  T msg;
  EXPECT_TRUE(type.deserialize(&p, &msg));
  return msg;
}

}  // namespace

TEST(LaunchFile, ResolvesArgumentsDefaultsSubstitutionsAndConditions) {
  ::unsetenv("MCVIO_TEST_LAUNCH_FRAME");
  const auto file = LaunchFile::parse(kFile, "test.yaml", "/base");
  ASSERT_EQ(file.arguments().size(), 4u);
  EXPECT_EQ(file.arguments()[0].name, "data");
  EXPECT_FALSE(file.arguments()[0].has_default);
  EXPECT_EQ(file.arguments()[0].description, "EuRoC folder");
  EXPECT_EQ(file.arguments()[1].default_value, "selective");

  auto plan = file.resolve({{"data", "seq"}});
  ASSERT_EQ(plan.entries.size(), 3u);  // the recorder is off while the player plays
  EXPECT_EQ(plan.entries[0].kind, LaunchPlan::Kind::kFrontend);
  EXPECT_EQ(plan.entries[0].frontend.calibration_dir, "seq");
  EXPECT_TRUE(plan.entries[0].frontend.publish_tracks_image);
  EXPECT_EQ(plan.entries[1].name, "estimator");
  EXPECT_EQ(plan.entries[1].node_namespace, "/mcvio");
  EXPECT_EQ(plan.entries[1].backend.estimator.conflict.mode, conflict::ResolutionMode::kSelective);
  EXPECT_EQ(plan.entries[1].backend.world_frame, "odom");  // $(env NAME DEFAULT), unset
  EXPECT_EQ(plan.entries[2].kind, LaunchPlan::Kind::kPlayer);
  EXPECT_EQ(plan.entries[2].input, "/base/seq");
  EXPECT_DOUBLE_EQ(plan.entries[2].player.rate, 2.5);
  EXPECT_TRUE(plan.exit_when_played);

  ::setenv("MCVIO_TEST_LAUNCH_FRAME", "map", 1);
  plan = file.resolve({{"data", "seq"}, {"play", "false"}, {"mode", "reference"}});
  ::unsetenv("MCVIO_TEST_LAUNCH_FRAME");
  ASSERT_EQ(plan.entries.size(), 3u);
  EXPECT_EQ(plan.entries[0].kind, LaunchPlan::Kind::kRecorder);
  EXPECT_EQ(plan.entries[0].output, "seq/bag");  // a default naming another argument
  EXPECT_TRUE(plan.entries[0].recorder.all);
  EXPECT_EQ(plan.entries[2].backend.world_frame, "map");
  EXPECT_EQ(plan.entries[2].backend.estimator.conflict.mode, conflict::ResolutionMode::kReference);
  EXPECT_FALSE(plan.has(LaunchPlan::Kind::kPlayer));

  EXPECT_EQ(LaunchFile::parseAssignment("data:=/tmp/a:=b"), std::make_pair(std::string("data"), std::string("/tmp/a:=b")));
  EXPECT_EQ(LaunchFile::parseAssignment("x:="), std::make_pair(std::string("x"), std::string()));
}

TEST(LaunchFile, BadLaunchFilesNameTheFileLineAndKey) {
  const std::string player = "components:\n  - component: player\n    input: d\n";
  struct Case {
    std::string text;
    std::map<std::string, std::string> values;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {kFile, {}, "test.yaml: give the required argument(s) data:=VALUE (EuRoC folder)"},
      {kFile, {{"data", "d"}, {"dta", "x"}}, "test.yaml: no argument 'dta' is declared (declared: data, mode, play, bag)"},
      {"components:\n  - component: player\n    input: $(arg nope)\n", {}, "test.yaml:3: '$(arg nope)': no argument 'nope' is declared under 'arguments:' (declared: none)"},
      {"components:\n  - component: player\n    input: $(bogus x)\n", {}, "test.yaml:3: '$(bogus x)': unknown substitution 'bogus'"},
      {"components:\n  - component: player\n    input: $(arg data\n", {}, "without its ')'"},
      {"components:\n  - component: player\n    input: $(env MCVIO_TEST_NOT_SET_ANYWHERE)\n", {}, "environment variable MCVIO_TEST_NOT_SET_ANYWHERE is not set"},
      {"components:\n  - component: camera\n", {}, "test.yaml:2: components[0].component 'camera' is not a component (player, frontend, backend or recorder)"},
      {"components:\n  - name: x\n", {}, "components[0].component is missing"},
      {player + "    rat: 2\n", {}, "test.yaml:2: component 'player': unknown launch key 'components[0].rat'"},
      {player + "    rate: fast\n", {}, "launch key 'components[0].rate' has an invalid value 'fast'"},
      {player + "    rate: -1\n", {}, "component 'player': "},
      {player + "    rate: .nan\n", {}, "launch key 'components[0].rate' must be finite"},
      {player + "    if: maybe\n", {}, "test.yaml:4: components[0].if is 'maybe'; it must be true or false"},
      {player + "    topics: [\"bad topic\"]\n", {}, "component 'player': "},
      {"components:\n  - component: player\n", {}, "component 'player': 'input' (a EuRoC folder or a bag) is missing or empty"},
      {player + player.substr(12), {}, "test.yaml:4: two components are named 'player' in /mcvio; give one a 'name:'"},
      {"components: []\n", {}, "test.yaml: 'components:' must list at least one component"},
      {"arguments: {}\n", {}, "'components:' must list at least one component"},
      {"component:\n  - component: player\n", {}, "unknown launch key 'component'"},
      {player + "    if: false\n", {}, "every component is switched off by its if/unless"},
      {"components:\n  - component: backend\n", {}, "component 'backend': 'calibration' (a EuRoC folder with the sensors' sensor.yaml) is missing or empty"},
      {"components:\n  - component: backend\n    calibration: c\n    mode: fast\n", {}, "component 'backend': "},
      {"components:\n  - component: backend\n    calibration: c\n    path_max: -3\n", {}, "launch key 'components[0].path_max' has an invalid value '-3'"},
      {"components:\n  - component: backend\n    calibration: c\n    config: /nonexistent/vio.yaml\n", {}, "/nonexistent/vio.yaml"},
      {"components:\n  - component: frontend\n    calibration: c\n    max_queued_pairs: 0\n", {}, "'max_queued_pairs' must be at least 1"},
      {"components:\n  - component: recorder\n    output: b\n", {}, "component 'recorder': "},
      {"components:\n  - component: recorder\n    output: b\n    all: true\n    storage: rosbag\n", {}, "storage 'rosbag' is not mcap or sqlite3"},
      {"components:\n  - component: recorder\n    all: true\n", {}, "'output' (the bag directory to create) is missing or empty"},
      {"components:\n  - component: player\n    name: \"bad name\"\n    input: d\n", {}, "component 'bad name': "},
      {"components:\n  - component: player\n    namespace: mcvio\n    input: d\n", {}, "namespace 'mcvio' must start with '/'"},
      {"exit_when_played: sometimes\n" + player, {}, "test.yaml:1: 'exit_when_played' must be true or false"},
      {"drain_timeout: 0\n" + player, {}, "test.yaml:1: 'drain_timeout' must be in (0, 86400] seconds"},
      {player + "    respawn: true\n", {}, "test.yaml:2: component 'player': 'respawn' is for frontends and backends: a player started again would play its input again"},
      {"components:\n  - component: recorder\n    output: b\n    all: true\n    respawn: true\n", {}, "'respawn' is for frontends and backends: a recorder started again could not reopen its bag"},
      {"components:\n  - component: backend\n    calibration: c\n    respawn: sometimes\n", {}, "launch key 'components[0].respawn' has an invalid value 'sometimes'"},
      {"components:\n  - component: frontend\n    calibration: c\n    respawn: true\n    respawn_delay: -1\n", {}, "component 'frontend': 'respawn_delay' must be in [0, 3600] seconds"},
      {"arguments: [data]\n" + player, {}, "test.yaml:1: 'arguments' must be a map"},
      {"arguments:\n  data: {defualt: x}\n" + player, {}, "test.yaml:2: unknown launch key 'arguments.data.defualt'"},
      {"arguments:\n  bad-name: {}\n" + player, {}, "test.yaml:2: argument 'bad-name' is not a name"},
      {"- component: player\n", {}, "test.yaml: a launch file is a map with 'components:'"},
      {"components:\n  - component: player\n   input: [\n", {}, "YAML syntax error"},
  };
  for (const auto& c : cases) {
    const std::string message = errorOf(c.text, c.values);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "launch file:\n" << c.text << "\ngave: " << message;
  }

  for (const char* bad : {"data=/tmp/x", ":=x", "1data:=x", "da ta:=x"}) {
    try {
      LaunchFile::parseAssignment(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos) << e.what();
    }
  }
  const std::string dir = ::testing::TempDir() + "/launch_dir_" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  std::string message = loadErrorOf(dir);
  EXPECT_NE(message.find("is a folder; the launch file must be a YAML file"), std::string::npos) << message;
  message = loadErrorOf(dir + "/missing.yaml");
  EXPECT_NE(message.find(dir + "/missing.yaml"), std::string::npos) << message;
  std::filesystem::remove_all(dir);
}

TEST(LaunchFile, TheShippedPipelineFileResolves) {
  const auto file = LaunchFile::load(MCVIO_REPO_ROOT "/config/pipeline.yaml");
  EXPECT_GE(file.arguments().size(), 5u);
  for (const auto& a : file.arguments()) EXPECT_FALSE(a.description.empty()) << a.name;
  auto plan = file.resolve({{"data", "/tmp/seq"}});
  ASSERT_EQ(plan.entries.size(), 3u);
  EXPECT_EQ(plan.entries[0].kind, LaunchPlan::Kind::kFrontend);
  EXPECT_EQ(plan.entries[1].kind, LaunchPlan::Kind::kBackend);
  EXPECT_EQ(plan.entries[1].backend.estimator.conflict.mode, conflict::ResolutionMode::kAuto);
  EXPECT_EQ(plan.entries[2].kind, LaunchPlan::Kind::kPlayer);
  EXPECT_FALSE(plan.entries[2].player.lossless);
  for (const auto& e : plan.entries) EXPECT_FALSE(e.respawn) << e.name;
  plan = file.resolve({{"data", "/tmp/seq"}, {"play", "false"}, {"record", "true"}, {"lossless", "true"}, {"respawn", "true"}});
  ASSERT_EQ(plan.entries.size(), 3u);
  EXPECT_EQ(plan.entries[0].kind, LaunchPlan::Kind::kRecorder);
  EXPECT_FALSE(plan.entries[0].respawn);
  EXPECT_TRUE(plan.entries[1].frontend.lossless);
  EXPECT_TRUE(plan.entries[1].respawn);
  EXPECT_TRUE(plan.entries[2].backend.lossless);
  EXPECT_TRUE(plan.entries[2].respawn);
  EXPECT_FALSE(plan.has(LaunchPlan::Kind::kPlayer));
}

// The shipped launch file, lossless, on a moving simulated sequence: everything played is
// handled before the launch stops, the bag holds every pose, and the poses are `mcvio run`'s.
TEST(Launcher, LosslessLaunchOfTheShippedFileRecordsTheOfflineRunsPoses) {
  const std::string base = ::testing::TempDir() + "/launch_" + std::to_string(getpid());
  std::filesystem::remove_all(base);
  const std::string seq = base + "/seq";
  components::test::writeCleanSequence(seq, 5, 4.0);

  auto plan = LaunchFile::load(MCVIO_REPO_ROOT "/config/pipeline.yaml")
                  .resolve({{"data", seq}, {"lossless", "true"}, {"record", "true"}, {"bag", base + "/bag"},
                            {"mode", "auto"}});
  for (auto& e : plan.entries) e.player.progress = false;
  std::ostringstream log;
  components::Launcher launcher(plan, components::test::testParticipantOptions(61), &log);
  const auto result = launcher.run();
  std::cout << log.str() << components::Launcher::summary(result);
  EXPECT_FALSE(result.interrupted);
  EXPECT_TRUE(result.drained);
  ASSERT_EQ(result.entries.size(), 4u);
  const auto& recorder = result.entries[0];
  const auto& frontend = result.entries[1].frontend;
  const auto& backend = result.entries[2].backend;
  const auto& player = result.entries[3];
  EXPECT_TRUE(player.error.empty()) << player.error;
  const auto data = dataset::EurocDataset::open(seq);
  EXPECT_EQ(player.playback.frames, data.stereoFrames().size());
  EXPECT_EQ(frontend.pairs_received, data.stereoFrames().size());
  EXPECT_EQ(frontend.frames_published + frontend.frames_skipped, frontend.pairs_received);
  EXPECT_EQ(backend.frames_received, frontend.frames_published);
  EXPECT_EQ(backend.frames_processed, backend.frames_received);
  EXPECT_GT(backend.poses_published, 0u);
  EXPECT_EQ(recorder.recording.messages_per_topic.count("/mcvio/odometry"), 1u);
  if (recorder.recording.messages_per_topic.count("/mcvio/odometry")) {
    EXPECT_EQ(recorder.recording.messages_per_topic.at("/mcvio/odometry"), backend.poses_published);
  }
  EXPECT_EQ(recorder.recording.messages_per_topic.count("/cam0/image_raw"), 0u);  // the file's regex leaves images out

  // The recorded odometry against `mcvio run` on the same folder.
  std::vector<std::pair<Timestamp, Eigen::Vector3d>> recorded;
  bag::BagReader reader(base + "/bag");
  bag::BagMessage m;
  while (reader.next(m)) {
    if (m.topic != "/mcvio/odometry") continue;
    const auto o = deserialize<nav_msgs::msg::dds_::Odometry_>(m.data);
    const auto& p = o.pose().pose().position();
    recorded.push_back({components::stampOf(o.header()), {p.x(), p.y(), p.z()}});
  }
  pipeline::OfflineRunOptions ro;
  ro.dataset_dir = seq;
  ro.output_dir = base + "/run";
  ro.mode = "auto";
  ro.progress = false;
  pipeline::runOffline(ro);
  std::vector<std::pair<Timestamp, Eigen::Vector3d>> offline;
  std::ifstream tum(ro.output_dir + "/trajectory.tum");
  for (std::string line; std::getline(tum, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double t, x, y, z;
    s >> t >> x >> y >> z;
    offline.push_back({static_cast<Timestamp>(std::llround(t * 1e9)), {x, y, z}});
  }
  ASSERT_EQ(recorded.size(), offline.size());
  double worst = 0;
  for (std::size_t i = 0; i < offline.size(); ++i) {
    EXPECT_LE(std::abs(recorded[i].first - offline[i].first), 1000) << i;
    worst = std::max(worst, (recorded[i].second - offline[i].second).norm());
  }
  std::cout << "launch vs mcvio run: " << offline.size() << " poses, max position difference " << worst << " m\n";
  EXPECT_LT(worst, 1e-5);  // the tolerance of BackendComponent's own lossless pipeline test
  std::filesystem::remove_all(base);
}

// A player that cannot start (its readers never come) ends the launch with its message; the
// recorder started before it still closes its bag.
TEST(Launcher, AFailingPlayerEndsTheLaunchAndTheBagIsClosed) {
  const std::string base = ::testing::TempDir() + "/launch_fail_" + std::to_string(getpid());
  std::filesystem::remove_all(base);
  const std::string seq = base + "/seq";
  components::test::writeCleanSequence(seq, 2, 2.0);
  const std::string text = "components:\n"
                           "  - component: recorder\n    output: " + base + "/bag\n    topics: [/mcvio/odometry]\n"
                           "  - component: player\n    input: " + seq + "\n    lossless: true\n"
                           "    wait_for_readers: 1\n    progress: false\n";
  const auto plan = LaunchFile::parse(text, "fail.yaml", base).resolve({});
  components::Launcher launcher(plan, components::test::testParticipantOptions(67), nullptr);
  const auto result = launcher.run();
  ASSERT_EQ(result.entries.size(), 2u);
  EXPECT_NE(result.entries[1].error.find("lossless playback needs its readers"), std::string::npos) << result.entries[1].error;
  EXPECT_TRUE(std::filesystem::exists(base + "/bag/metadata.yaml"));
  EXPECT_EQ(result.entries[0].recording.messages, 0u);
  // A bag directory that exists stops the launch before anything plays.
  EXPECT_ANY_THROW(components::Launcher(plan, components::test::testParticipantOptions(67), nullptr).run());
  std::filesystem::remove_all(base);
}
