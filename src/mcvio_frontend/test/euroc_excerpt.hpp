#pragma once
#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/frontend/stereo_input.hpp"

namespace mcvio::frontend::testing {

/// The real EuRoC V1_01 excerpt under $MCVIO_SHARED_DIR, read with mcvio_dataset's EurocDataset
/// (which pairs cam0/cam1 by timestamp and skips the cam1 rows without an image).
class EurocExcerpt {
 public:
  /// Folder of the excerpt, or nothing when MCVIO_SHARED_DIR or the data is absent.
  static std::optional<std::string> locate();
  explicit EurocExcerpt(const std::string& dir) : data_(dataset::EurocDataset::open(dir)) {}

  std::size_t size() const { return data_.stereoFrames().size(); }
  const StereoRigCalibration& calibration() const { return data_.calibration(); }
  const dataset::EurocDataset& dataset() const { return data_; }
  /// Frame i with the IMU samples in (t_{i-1}, t_i] (samples up to t_0 for i = 0).
  StereoInput frame(std::size_t i) const;
  /// Ground-truth body pose T_WB at exactly time t, if the ground truth has that stamp.
  std::optional<Eigen::Isometry3d> groundTruthPose(Timestamp t) const;

 private:
  dataset::EurocDataset data_;
};

}  // namespace mcvio::frontend::testing
