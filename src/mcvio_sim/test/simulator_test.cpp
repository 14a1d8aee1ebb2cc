#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/sim/image_injector.hpp"
#include "mcvio/sim/simulator.hpp"

namespace mcvio::sim {
namespace {

SimulatorOptions shortRun(ScenarioKind kind, double duration = 8.0, double onset = 2.0,
                          double conflict = 4.0) {
  SimulatorOptions o;
  o.duration_s = duration;
  o.camera_rate_hz = 10.0;
  o.texture_size = 256;
  o.scenario.kind = kind;
  o.scenario.onset_s = onset;
  o.scenario.duration_s = conflict;
  return o;
}

TEST(Simulator, SameSeedGivesIdenticalDataAndAnotherSeedDoesNot) {
  const SimulatorOptions o = shortRun(ScenarioKind::kPedestrian);
  Simulator a(o), b(o);
  ASSERT_EQ(a.imu().size(), b.imu().size());
  for (size_t k = 0; k < a.imu().size(); ++k) {
    ASSERT_EQ(a.imu()[k].gyro, b.imu()[k].gyro);
    ASSERT_EQ(a.imu()[k].accel, b.imu()[k].accel);
  }
  const StereoRender fa = a.renderFrame(40), fb = b.renderFrame(40);
  EXPECT_EQ(cv::norm(fa.cam0, fb.cam0, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.cam1, fb.cam1, cv::NORM_INF), 0.0);
  EXPECT_EQ(fa.label.covered_fraction, fb.label.covered_fraction);

  SimulatorOptions one_thread = o;
  one_thread.threads = 1;
  const StereoRender f1 = Simulator(one_thread).renderFrame(40);
  EXPECT_EQ(cv::norm(fa.cam0, f1.cam0, cv::NORM_INF), 0.0) << "thread count must not change the images";

  SimulatorOptions other = o;
  other.seed = 2;
  Simulator c(other);
  EXPECT_NE(a.imu()[100].accel, c.imu()[100].accel);
  EXPECT_GT(cv::norm(fa.cam0, c.renderFrame(40).cam0, cv::NORM_L1), 0.0);
}

TEST(Simulator, ElevatorFramesAreInConflictExactlyDuringTheRide) {
  SimulatorOptions o = shortRun(ScenarioKind::kElevator);
  o.scenario.coverage = 1.0;
  Simulator sim(o);
  const Timestamp onset = sim.frameTimes().front() + fromSeconds(2.0);
  const Timestamp end = onset + fromSeconds(4.0);
  int in_conflict = 0;
  for (size_t k = 0; k < sim.frameTimes().size(); ++k) {
    StereoRender f;
    f.t = sim.frameTimes()[k];
    f.label = sim.labelFor(f.t, sim.renderCamera(k, 0));
    const bool riding = f.t > onset && f.t < end;
    EXPECT_EQ(f.label.in_conflict, riding) << "frame " << k;
    if (riding) {
      EXPECT_GT(f.label.covered_fraction, 0.95) << "closed cabin fills the view";
      EXPECT_EQ(f.label.motion, "elevator");
      ++in_conflict;
    } else {
      EXPECT_EQ(f.label.covered_fraction, 0.0);
    }
  }
  EXPECT_EQ(in_conflict, 39);  // 10 Hz frames strictly inside a 4 s ride
  // The cabin rose 12 m; the camera saw it standing still.
  EXPECT_NEAR(sim.groundTruth().back().p_WB.z() - sim.world().trajectory_in_frame->evaluate(sim.groundTruth().back().t).p_wb.z(),
              12.0, 1e-9);
}

struct ScenarioCase {
  ScenarioKind kind;
  double min_fraction, max_fraction;
};

TEST(Simulator, EveryScenarioShowsItsConflictingMotionOnlyDuringItsInterval) {
  const ScenarioCase cases[] = {{ScenarioKind::kVehicle, 0.15, 0.97},
                                {ScenarioKind::kSelfOcclusion, 0.35, 0.9},
                                {ScenarioKind::kPedestrian, 0.01, 0.8},
                                {ScenarioKind::kSlowObject, 0.01, 0.9}};
  for (const auto& c : cases) {
    Simulator sim(shortRun(c.kind, 8.0, 2.0, 4.0));
    const StereoRender before = sim.renderFrame(10);  // 1 s
    const StereoRender middle = sim.renderFrame(40);  // 4 s: mid-conflict
    const StereoRender after = sim.renderFrame(70);   // 7 s
    EXPECT_FALSE(before.label.in_conflict) << toString(c.kind);
    EXPECT_FALSE(after.label.in_conflict) << toString(c.kind);
    EXPECT_TRUE(middle.label.in_conflict) << toString(c.kind);
    EXPECT_EQ(middle.label.motion, toString(c.kind));
    EXPECT_GE(middle.label.covered_fraction, c.min_fraction) << toString(c.kind);
    EXPECT_LE(middle.label.covered_fraction, c.max_fraction) << toString(c.kind);
    // The fraction is what the image shows: count the conflicting body's pixels.
    int counted = 0;
    for (int b : sim.world().conflict_bodies) counted += cv::countNonZero(middle.cam0_body_ids == b);
    EXPECT_NEAR(middle.label.covered_fraction, counted / (752.0 * 480.0), 1e-12);
  }
}

TEST(Simulator, NoneScenarioHasNoConflictAndATexturedView) {
  Simulator sim(shortRun(ScenarioKind::kNone, 4.0, 0.0, 0.0));
  const StereoRender f = sim.renderFrame(20);
  EXPECT_FALSE(f.label.in_conflict);
  cv::Scalar mean, stddev;
  cv::meanStdDev(f.cam0, mean, stddev);
  EXPECT_GT(stddev[0], 20.0) << "the view should be textured, not flat";
  EXPECT_GT(mean[0], 40.0);
  EXPECT_LT(mean[0], 215.0);
}

TEST(Simulator, WritesAEurocFolderThatReadsBack) {
  const std::string dir = (std::filesystem::temp_directory_path() / "mcvio_sim_test_write").string();
  std::filesystem::remove_all(dir);
  SimulatorOptions o = shortRun(ScenarioKind::kElevator, 2.0, 0.5, 1.0);
  o.output_dir = dir;
  const SimulationSummary s = runSimulation(o);
  EXPECT_EQ(s.frames, 21u);
  EXPECT_EQ(s.imu_samples, 401u);
  const auto data = dataset::EurocDataset::open(dir);
  EXPECT_EQ(data.stereoFrames().size(), 21u);
  EXPECT_EQ(data.imu().size(), 401u);
  EXPECT_EQ(data.groundTruth().size(), 401u);
  ASSERT_EQ(data.labels().size(), 21u);
  size_t conflicts = 0;
  for (const auto& l : data.labels()) conflicts += l.in_conflict ? 1 : 0;
  EXPECT_EQ(conflicts, s.conflict_frames);
  EXPECT_EQ(conflicts, 9u);
  EXPECT_EQ(data.loadImage(data.stereoFrames()[3], 1).cols, 752);
  std::filesystem::remove_all(dir);
}

TEST(Simulator, AnExistingOutputIsNotOverwrittenAndAFailingCallbackStopsTheRun) {
  const std::string dir = (std::filesystem::temp_directory_path() / "mcvio_sim_test_exists").string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/mav0");
  SimulatorOptions o = shortRun(ScenarioKind::kNone, 1.0, 0.0, 0.0);
  o.output_dir = dir;
  EXPECT_THROW(runSimulation(o), InputError);
  o.overwrite = true;
  EXPECT_THROW(runSimulation(o, [](std::size_t done, std::size_t) {
                 if (done == 3) throw std::runtime_error("stop");
               }),
               std::runtime_error);
  std::filesystem::remove_all(dir);
}

TEST(SimulatorOptions, YamlKeysAreReadAndMistakesAreNamed) {
  const SimulatorOptions o = SimulatorOptions::fromYaml(YAML::Load(
      "seed: 7\nscenario: {kind: vehicle, onset_s: 5, duration_s: 10, coverage: 0.5}\n"
      "imu: {noise: false, initial_gyro_bias: [0.01, 0, 0]}\nimage: {noise_sigma: 1.5, texture_filter: anisotropic}\n"));
  EXPECT_EQ(o.seed, 7u);
  EXPECT_EQ(o.scenario.kind, ScenarioKind::kVehicle);
  EXPECT_EQ(o.scenario.coverage, 0.5);
  EXPECT_FALSE(o.imu_noise_enabled);
  EXPECT_EQ(o.initial_gyro_bias.x(), 0.01);
  EXPECT_EQ(o.pixel_noise_sigma, 1.5);
  EXPECT_EQ(o.texture_filter, TextureFilter::kAnisotropic);
  EXPECT_EQ(o.duration_s, 60.0);
  EXPECT_EQ(SimulatorOptions::fromYaml(YAML::Load("seed: 2")).texture_filter, TextureFilter::kIsotropic);

  auto message = [](const std::string& yaml) {
    try {
      SimulatorOptions::fromYaml(YAML::Load(yaml));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("scenario: {kind: submarine}").find("scenario.kind"), std::string::npos);
  EXPECT_NE(message("scenario: {coverage: 1.5}").find("scenario.coverage"), std::string::npos);
  EXPECT_NE(message("image: {noise_sigmaa: 1}").find("image.noise_sigmaa"), std::string::npos);
  EXPECT_NE(message("image: {texture_filter: trilinear}").find("image.texture_filter: unknown texture filter 'trilinear'"),
            std::string::npos);
  EXPECT_NE(message("duration_s: abc").find("duration_s"), std::string::npos);
  EXPECT_NE(message("imu: {initial_gyro_bias: [1, 2]}").find("imu.initial_gyro_bias"), std::string::npos);
  EXPECT_NE(message("duration_s: 10\nscenario: {kind: elevator, onset_s: 8, duration_s: 5}").find("scenario.duration_s"),
            std::string::npos);
  // A clean sequence has no conflict to end after it (the default 20 + 15 s once refused 10 s).
  EXPECT_EQ(message("duration_s: 10\nscenario: {kind: none}"), "no error");
  EXPECT_NE(message("semi_real: {imu_csv: x.csv}").find("semi_real.groundtruth_csv"), std::string::npos);
}

TEST(SimulatorOptions, ShippedExamplesAreValid) {
  const std::string dir = MCVIO_SIM_CONFIG_DIR;
  EXPECT_EQ(SimulatorOptions::fromYamlFile(dir + "/sim_elevator.yaml").scenario.kind, ScenarioKind::kElevator);
  const SimulatorOptions semi = SimulatorOptions::fromYamlFile(dir + "/sim_semi_real_vehicle.yaml");
  EXPECT_TRUE(semi.semiReal());
  EXPECT_EQ(InjectOptions::fromYamlFile(dir + "/inject_moving_image.yaml").depth_m, 1.2);
  try {
    SimulatorOptions::fromYamlFile(dir + "/does_not_exist.yaml");
    FAIL() << "a missing file must throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does_not_exist.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace mcvio::sim
