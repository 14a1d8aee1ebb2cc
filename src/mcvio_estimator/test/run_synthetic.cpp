// Small command-line runner for development: prints figures of one synthetic run.
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdlib>

#include "synthetic_vio_sequence.hpp"

int main(int argc, char** argv) {
  using namespace mcvio::estimator;
  testing::SyntheticConfig cfg;
  if (argc > 1) cfg.duration_s = std::atof(argv[1]);
  if (argc > 2) cfg.seed = static_cast<std::uint32_t>(std::atoi(argv[2]));
  if (const char* e = std::getenv("PIX")) cfg.pixel_noise_px = std::atof(e);
  if (const char* e = std::getenv("IMUNOISE")) cfg.imu_noise = std::atoi(e) != 0;
  if (const char* e = std::getenv("NOBIAS"); e && std::atoi(e)) {
    cfg.gyro_bias0.setZero();
    cfg.accel_bias0.setZero();
  }
  EstimatorOptions opt;
  if (argc > 3) opt = EstimatorOptions::fromYamlFile(argv[3]);
  const auto seq = testing::generateSequence(cfg);
  const auto res = testing::runEstimator(seq, opt);
  const int step_env = std::getenv("STEP") ? std::atoi(std::getenv("STEP")) : 20;
  const std::size_t step = static_cast<std::size_t>(std::max(1, step_env));  // STEP=0 or junk: every frame
  for (std::size_t i = 0; i < res.outputs.size(); i += step) {
    const auto& o = res.outputs[i];
    const auto& t = seq.truth[i];
    std::printf("   t: pre %.2f setup %.2f solve %.2f cov %.2f marg %.2f total %.2f\n", o.timings.preintegration_ms, o.timings.setup_ms, o.timings.solve_ms, o.timings.covariance_ms, o.timings.marginalization_ms, o.timings.total_ms);
    std::printf("   sd_p %.4f %.4f %.4f\n", std::sqrt(o.pose_covariance(0, 0)), std::sqrt(o.pose_covariance(1, 1)), std::sqrt(o.pose_covariance(2, 2)));
    std::printf("%4zu st=%d acc=%d err=%.4f vErr=%.4f bgErr=%.5f baErr=%.4f lm=%d vis=%d kf=%d zv=%d it=%d ms=%.2f %s\n", i,
                static_cast<int>(o.status), o.frame_accepted, (o.p_WB - t.p).norm(), (o.v_WB - t.v).norm(),
                (o.bias.gyro - t.bg).norm(), (o.bias.accel - t.ba).norm(), o.num_landmarks, o.num_visual_residuals,
                o.num_keyframes, o.zero_velocity, o.solver_iterations, o.timings.total_ms, o.message.c_str());
  }
  std::printf("frames %zu tracked %d resets %d ATE %.4f m  NEES %.3f  max err %.4f m  median %.2f ms wall, %.2f ms cpu (p90 %.2f)\n",
              res.outputs.size(), res.tracked_frames, res.resets, res.ate_m, res.mean_position_nees,
              res.max_abs_position_error_m, res.median_total_ms, res.median_cpu_ms, res.p90_cpu_ms);
  return 0;
}
