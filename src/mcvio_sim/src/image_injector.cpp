#include "mcvio/sim/image_injector.hpp"

#include <cmath>
#include <filesystem>

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "mcvio/core/yaml_fields.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::sim {

InjectOptions InjectOptions::fromYaml(const YAML::Node& node) {
  InjectOptions o;
  YamlFields f(node, "");
  f.get("input_dir", &o.input_dir);
  f.get("output_dir", &o.output_dir);
  f.get("overwrite", &o.overwrite);
  f.get("onset_s", &o.onset_s);
  f.get("duration_s", &o.duration_s);
  f.get("depth_m", &o.depth_m);
  f.get("width_m", &o.width_m);
  f.get("height_m", &o.height_m);
  Eigen::Vector3d centre(o.center_m.x(), o.center_m.y(), 0.0);
  {
    // center_m is two numbers; read it as such for a precise error message.
    const YAML::Node c = f.child("center_m");
    if (c && !c.IsNull()) {  // child() gives a null node when the key is absent
      if (!c.IsSequence() || c.size() != 2) throw InputError("option 'center_m' must be a list of 2 numbers");
      try {
        centre = {c[0].as<double>(), c[1].as<double>(), 0.0};
      } catch (const YAML::Exception&) {
        throw InputError("option 'center_m' must be a list of 2 numbers");
      }
    }
  }
  o.center_m = centre.head<2>();
  f.getVector3("velocity_mps", &o.velocity_mps);
  f.get("sway_amplitude_m", &o.sway_amplitude_m);
  f.get("sway_hz", &o.sway_hz);
  f.get("spin_rate", &o.spin_rate);
  f.get("texel_size_m", &o.texel_size_m);
  f.get("pixel_noise_sigma", &o.pixel_noise_sigma);
  f.get("seed", &o.seed);
  f.get("motion_name", &o.motion_name);
  f.get("threads", &o.threads);
  f.get("png_compression", &o.png_compression);
  f.rejectUnknown();
  o.validate();
  return o;
}

InjectOptions InjectOptions::fromYamlFile(const std::string& path) {
  return loadOptionsFile(path, [](const YAML::Node& node) { return fromYaml(node); });
}

void InjectOptions::validate() const {
  auto need = [](bool ok, const char* key, const char* rule) {
    if (!ok) throw InputError(std::string("option '") + key + "' " + rule);
  };
  need(onset_s >= 0, "onset_s", "must not be negative");
  need(duration_s > 0, "duration_s", "must be positive");
  need(depth_m >= 0.1 && depth_m <= 100, "depth_m", "must be in [0.1, 100]");
  need(width_m > 0 && width_m <= 100, "width_m", "must be in (0, 100]");
  need(height_m > 0 && height_m <= 100, "height_m", "must be in (0, 100]");
  need(center_m.allFinite(), "center_m", "must be finite");
  need(velocity_mps.allFinite(), "velocity_mps", "must be finite");
  need(sway_amplitude_m >= 0, "sway_amplitude_m", "must not be negative");
  need(sway_hz >= 0, "sway_hz", "must not be negative");
  need(texel_size_m > 1e-5 && texel_size_m < 1, "texel_size_m", "must be in (1e-5, 1)");
  need(pixel_noise_sigma >= 0 && pixel_noise_sigma <= 50, "pixel_noise_sigma", "must be in [0, 50]");
  need(!motion_name.empty() && motion_name.find_first_of(",\"\n\r") == std::string::npos, "motion_name",
       "must be a non-empty name without commas, quotes or line breaks");
  need(threads >= 1 && threads <= 64, "threads", "must be in [1, 64]");
  need(png_compression >= 0 && png_compression <= 9, "png_compression", "must be in [0, 9]");
}

ImageInjector::ImageInjector(InjectOptions options, const StereoRigCalibration& calibration)
    : options_(std::move(options)), calibration_(calibration) {
  options_.validate();
  const int tex = scene_.addTexture(MipmappedTexture::generate(TextureStyle::kPosters, 1024, options_.seed));
  SceneBody plane;
  plane.name = options_.motion_name;
  TexturedQuad q;
  q.origin = {-0.5 * options_.width_m, -0.5 * options_.height_m, 0.0};
  q.size_u = options_.width_m;
  q.size_v = options_.height_m;
  q.texture = tex;
  q.texel_size = options_.texel_size_m;
  q.texture_offset = {static_cast<double>(options_.seed % 512), 0.0};
  plane.quads.push_back(q);
  scene_.addBody(std::move(plane));
  for (int c = 0; c < 2; ++c)
    renderer_[c] = std::make_unique<CameraRenderer>(calibration_.camera(c), options_.threads);
}

Eigen::Isometry3d ImageInjector::planeInCam0(double s) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(options_.spin_rate * s, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(options_.center_m.x(), options_.center_m.y(), options_.depth_m) +
                    s * options_.velocity_mps +
                    Eigen::Vector3d(options_.sway_amplitude_m * std::sin(2.0 * M_PI * options_.sway_hz * s), 0, 0);
  return T;
}

dataset::ConflictLabel ImageInjector::overlay(Timestamp t, Timestamp since_first_frame, cv::Mat& cam0,
                                              cv::Mat& cam1) const {
  dataset::ConflictLabel label;
  label.t = t;
  const double s = toSeconds(since_first_frame) - options_.onset_s;
  if (s < 0 || s >= options_.duration_s) return label;
  // Render in the plane's own frame: the "device" pose is where the rig sits relative to it.
  const Eigen::Isometry3d T_OB = planeInCam0(s).inverse() * calibration_.cam0.T_BC.inverse();
  cv::Mat* images[2] = {&cam0, &cam1};
  for (int c = 0; c < 2; ++c) {
    RenderSettings settings;
    settings.noise_sigma = options_.pixel_noise_sigma;
    settings.noise_seed = static_cast<std::uint64_t>(t) * 2654435761ULL + static_cast<std::uint64_t>(c) + options_.seed;
    const cv::Mat background = images[c]->clone();
    settings.background = &background;
    RenderResult r;
    renderer_[c]->render(scene_, 0, T_OB, settings, &r);
    *images[c] = r.image;
    if (c == 0) {
      label.covered_fraction = static_cast<double>(r.body_pixels[0]) / (static_cast<double>(cam0.rows) * cam0.cols);
      label.in_conflict = r.body_pixels[0] > 0;
      label.motion = label.in_conflict ? options_.motion_name : "none";
    }
  }
  return label;
}

InjectSummary runInjection(const InjectOptions& options,
                           const std::function<void(std::size_t, std::size_t)>& progress) {
  options.validate();
  namespace fs = std::filesystem;
  if (options.input_dir.empty()) throw InputError("option 'input_dir' is required");
  if (options.output_dir.empty()) throw InputError("option 'output_dir' is required");
  std::error_code ec;
  if (fs::exists(options.output_dir) && fs::equivalent(options.input_dir, options.output_dir, ec))
    throw InputError("option 'output_dir' must differ from 'input_dir' (" + options.output_dir + ")");
  const auto data = dataset::EurocDataset::open(options.input_dir);
  if (data.stereoFrames().empty()) throw InputError(options.input_dir + ": no stereo frames to inject into");
  const double input_s = toSeconds(data.stereoFrames().back().t - data.stereoFrames().front().t);
  if (options.onset_s > input_s)
    throw InputError("option 'onset_s' (" + std::to_string(options.onset_s) + " s) is after the end of " +
                     options.input_dir + " (" + std::to_string(input_s) + " s of stereo frames)");
  const ImageInjector injector(options, data.calibration());
  dataset::EurocWriter::Options wo;
  wo.overwrite = options.overwrite;
  wo.png_compression = options.png_compression;
  dataset::EurocWriter writer(options.output_dir, data.calibration(), wo);
  for (const auto& m : data.imu()) writer.addImu(m);
  for (const auto& g : data.groundTruth()) writer.addGroundTruth(g);
  InjectSummary summary;
  summary.warnings = data.warnings().size();
  const Timestamp first = data.stereoFrames().front().t;
  const std::size_t total = data.stereoFrames().size();
  for (std::size_t k = 0; k < total; ++k) {
    const auto& frame = data.stereoFrames()[k];
    cv::Mat left = data.loadImage(frame, 0), right = data.loadImage(frame, 1);
    const dataset::ConflictLabel label = injector.overlay(frame.t, frame.t - first, left, right);
    writer.addImage(0, frame.t, left);
    writer.addImage(1, frame.t_cam1, right);
    writer.addLabel(label);
    if (label.in_conflict) ++summary.injected_frames;
    ++summary.frames;
    if (progress) progress(k + 1, total);
  }
  writer.close();
  return summary;
}

}  // namespace mcvio::sim
