#include "euroc_excerpt.hpp"

#include <cstdlib>
#include <filesystem>

namespace mcvio::frontend::testing {

std::optional<std::string> EurocExcerpt::locate() {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  if (!shared) return std::nullopt;
  const std::filesystem::path dir = std::filesystem::path(shared) / "data" / "euroc_V1_01_excerpt";
  if (!std::filesystem::exists(dir / "mav0" / "cam0" / "data.csv")) return std::nullopt;
  return dir.string();
}

StereoInput EurocExcerpt::frame(std::size_t i) const {
  const auto& f = data_.stereoFrames().at(i);
  StereoInput in;
  in.t = f.t;
  in.left = data_.loadImage(f, 0);
  in.right = data_.loadImage(f, 1);
  const Timestamp t0 = i == 0 ? 0 : data_.stereoFrames()[i - 1].t;
  for (const ImuSample& s : data_.imu()) {
    if (s.t > t0 && s.t <= in.t) in.imu.push_back(s);
  }
  return in;
}

std::optional<Eigen::Isometry3d> EurocExcerpt::groundTruthPose(Timestamp t) const {
  for (const auto& g : data_.groundTruth()) {
    if (g.t == t) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = g.q_WB.normalized().toRotationMatrix();
      T.translation() = g.p_WB;
      return T;
    }
  }
  return std::nullopt;
}

}  // namespace mcvio::frontend::testing
