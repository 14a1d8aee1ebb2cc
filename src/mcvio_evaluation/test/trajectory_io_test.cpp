#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/evaluation/trajectory_io.hpp"
#include "synthetic_trajectory.hpp"

namespace mcvio::evaluation {
namespace {

/// The InputError message of loading `text` as a TUM file (empty if it loads).
std::string tumError(const std::string& name, const std::string& text, std::string* path_out = nullptr) {
  const std::string path = test::freshDir(name) + "/est.tum";
  test::writeText(path, text);
  if (path_out) *path_out = path;
  try {
    loadTum(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

TEST(TrajectoryIo, TumRoundTripKeepsNanoseconds) {
  const Trajectory t = test::lissajous(3, 20, 1403715273262142976);
  const std::string path = test::freshDir("round_trip") + "/sub/t.tum";
  writeTum(t, path);
  const Trajectory back = loadTum(path);
  ASSERT_EQ(back.size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_EQ(back[i].t, t[i].t);
    EXPECT_LT((back[i].p - t[i].p).norm(), 1e-8);
    EXPECT_LT(back[i].q.angularDistance(t[i].q), 1e-8);
  }
  EXPECT_EQ(back.source(), path);
}

TEST(TrajectoryIo, TumAcceptsCommentsTabsBlankLinesAndShortDecimals) {
  const std::string dir = test::freshDir("tum_forms");
  test::writeText(dir + "/a.tum",
                  "# t x y z qx qy qz qw\n\n"
                  "1403715273.262142976 1 2 3 0 0 0 1\n"
                  "1403715273.3\t1.5\t2\t3\t0 0 0.7071068 0.7071068\r\n"
                  "   # indented comment\n"
                  "1.4037152734e9 2 2 3 0 0 0 1\n");
  const Trajectory t = loadTum(dir + "/a.tum");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].t, 1403715273262142976);
  EXPECT_EQ(t[1].t, 1403715273300000000);
  EXPECT_EQ(t[2].t, 1403715273400000000);
  EXPECT_NEAR(t[1].q.w(), std::sqrt(0.5), 1e-12);  // normalised
  EXPECT_DOUBLE_EQ(t[2].p.x(), 2.0);
}

TEST(TrajectoryIo, MalformedTumLinesNameFileLineAndField) {
  std::string path;
  std::string e = tumError("tum_count", "# header\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n", &path);
  EXPECT_NE(e.find(path + ":3:"), std::string::npos) << e;
  EXPECT_NE(e.find("7 fields, expected 8"), std::string::npos) << e;

  e = tumError("tum_nan_field", "1 0 0 0 0 0 0 1\n2 0 0 0 abc 0 0 1\n", &path);
  EXPECT_NE(e.find(path + ":2:"), std::string::npos) << e;
  EXPECT_NE(e.find("'qx'"), std::string::npos) << e;

  e = tumError("tum_nan", "1 nan 0 0 0 0 0 1\n", &path);
  EXPECT_NE(e.find(path + ":1:"), std::string::npos) << e;
  EXPECT_NE(e.find("'x'"), std::string::npos) << e;

  e = tumError("tum_backwards", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n", &path);
  EXPECT_NE(e.find(path + ":3:"), std::string::npos) << e;
  EXPECT_NE(e.find("does not increase"), std::string::npos) << e;

  e = tumError("tum_nanoseconds", "1600000000050000000 0 0 0 0 0 0 1\n", &path);
  EXPECT_NE(e.find(path + ":1:"), std::string::npos) << e;
  EXPECT_NE(e.find("nanoseconds?"), std::string::npos) << e;

  e = tumError("tum_quaternion", "1 0 0 0 0 0 0 2\n", &path);
  EXPECT_NE(e.find(path + ":1:"), std::string::npos) << e;
  EXPECT_NE(e.find("norm"), std::string::npos) << e;

  e = tumError("tum_empty", "# nothing\n", &path);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("no poses"), std::string::npos) << e;
}

TEST(TrajectoryIo, AHeaderOnlyFileIsEmptyOnlyWhenAllowed) {
  // secondary.tum of a run that never tracked a secondary frame holds its header only.
  const std::string path = test::freshDir("tum_header_only") + "/secondary.tum";
  test::writeText(path, "# the conflicting frame S in world\n");
  EXPECT_THROW(loadTum(path), InputError);
  EXPECT_TRUE(loadTum(path, EmptyTum::kEmptyTrajectory).empty());
  // Allowing an empty file does not let a malformed or a missing one through.
  test::writeText(path, "# header\n1 0 0 0 0 0 0\n");
  EXPECT_THROW(loadTum(path, EmptyTum::kEmptyTrajectory), InputError);
  EXPECT_THROW(loadTum(path + ".missing", EmptyTum::kEmptyTrajectory), InputError);
}

TEST(TrajectoryIo, MissingFilesAreInputErrors) {
  const std::string dir = test::freshDir("missing");
  EXPECT_THROW(loadTum(dir + "/nope.tum"), InputError);
  EXPECT_THROW(loadEurocGroundTruth(dir), InputError);
  EXPECT_THROW(loadTrajectory(dir + "/nope"), InputError);
}

TEST(TrajectoryIo, MalformedGroundTruthCsvNamesFileAndLine) {
  const std::string dir = test::freshDir("bad_gt");
  const std::string csv = dir + "/mav0/state_groundtruth_estimate0/data.csv";
  std::filesystem::create_directories(std::filesystem::path(csv).parent_path());
  test::writeText(csv,
                  "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z,v_x,v_y,v_z,bw_x,bw_y,bw_z,ba_x,ba_y,ba_z\n"
                  "1000,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n"
                  "2000,0,x,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n");
  try {
    loadEurocGroundTruth(dir);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(csv + ":3"), std::string::npos) << m;
    EXPECT_NE(m.find("p_y"), std::string::npos) << m;
  }
}

TEST(TrajectoryIo, LoadTrajectoryPicksTheFormat) {
  const std::string dir = test::freshDir("auto");
  const Trajectory t = test::lissajous(1, 20);
  writeTum(t, dir + "/run/trajectory.tum");
  EXPECT_EQ(loadTrajectory(dir + "/run").size(), t.size());
  EXPECT_EQ(loadTrajectory(dir + "/run/trajectory.tum").size(), t.size());
  const std::string csv = dir + "/gt/mav0/state_groundtruth_estimate0/data.csv";
  std::filesystem::create_directories(std::filesystem::path(csv).parent_path());
  test::writeText(csv, "#t\n1000,1,2,3,1,0,0,0,0,0,0,0,0,0,0,0,0\n2000,1,2,4,1,0,0,0,0,0,0,0,0,0,0,0,0\n");
  const Trajectory gt = loadTrajectory(dir + "/gt");
  ASSERT_EQ(gt.size(), 2u);
  EXPECT_EQ(gt[1].t, 2000);
  EXPECT_DOUBLE_EQ(gt[1].p.z(), 4.0);
  EXPECT_EQ(loadTrajectory(csv).size(), 2u);
  EXPECT_EQ(loadTrajectory(dir + "/gt/mav0").size(), 2u);
}

TEST(TrajectoryIo, OnlineTrajectoryOnlyWhereTheRunWroteOne) {
  const std::string dir = test::freshDir("online");
  const Trajectory t = test::lissajous(1, 20);
  writeTum(t, dir + "/run/trajectory.tum");
  EXPECT_FALSE(loadOnlineTrajectory(dir + "/run").has_value());
  writeTum(test::lissajous(1, 10), dir + "/run/trajectory_online.tum");
  const auto online = loadOnlineTrajectory(dir + "/run");
  ASSERT_TRUE(online.has_value());
  EXPECT_EQ(online->size(), test::lissajous(1, 10).size());
  test::writeText(dir + "/run/trajectory_online.tum", "1.0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n");
  EXPECT_THROW(loadOnlineTrajectory(dir + "/run"), InputError);  // a damaged one is an error, not "absent"
}

TEST(TrajectoryIo, RealEurocGroundTruth) {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  const std::string dir = shared ? std::string(shared) + "/data/euroc_V1_01_excerpt" : "";
  if (dir.empty() || !std::filesystem::exists(dir)) GTEST_SKIP() << "no shared data";
  const Trajectory gt = loadEurocGroundTruth(dir);
  ASSERT_GT(gt.size(), 100u);
  EXPECT_EQ(gt[0].t, 1403715273262142976);
  EXPECT_NEAR(gt[0].p.x(), 0.878895, 1e-9);
  EXPECT_NEAR(gt[0].q.w(), 0.069433, 1e-4);
  // Compare against itself through TUM: a written-and-read copy has zero ATE.
  const std::string tum = test::freshDir("real_gt") + "/gt.tum";
  writeTum(gt, tum);
  const Trajectory back = loadTum(tum);
  ASSERT_EQ(back.size(), gt.size());
  EXPECT_EQ(back[back.size() - 1].t, gt[gt.size() - 1].t);
}

}  // namespace
}  // namespace mcvio::evaluation
