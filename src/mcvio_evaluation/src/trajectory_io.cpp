#include "mcvio/evaluation/trajectory_io.hpp"

#include <cerrno>
#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/write_failure.hpp"
#include "mcvio/dataset/euroc_file_reader.hpp"

namespace mcvio::evaluation {

namespace fs = std::filesystem;

namespace {

constexpr const char* kTumFields[8] = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};

std::vector<std::string_view> splitWhitespace(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size()) break;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    out.push_back(line.substr(start, i - start));
  }
  return out;
}

bool parseDouble(std::string_view f, double& value) {
  const char* first = f.data();
  if (!f.empty() && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, f.data() + f.size(), value);
  return !f.empty() && ec == std::errc() && ptr == f.data() + f.size();
}

/// "1403715273.262142976" -> exact nanoseconds; other forms (exponents) through a double.
bool parseSecondsExact(std::string_view f, Timestamp& t) {
  std::size_t i = 0;
  bool negative = false;
  if (i < f.size() && (f[i] == '+' || f[i] == '-')) negative = f[i++] == '-';
  std::int64_t whole = 0;
  std::size_t digits = 0;
  while (i < f.size() && f[i] >= '0' && f[i] <= '9') {
    if (whole > (INT64_MAX / 10 - 10) / 1000000000) return false;
    whole = whole * 10 + (f[i++] - '0');
    ++digits;
  }
  std::int64_t frac = 0;
  std::size_t frac_digits = 0;
  bool round_up = false;
  if (i < f.size() && f[i] == '.') {
    ++i;
    while (i < f.size() && f[i] >= '0' && f[i] <= '9') {
      if (frac_digits < 9) {
        frac = frac * 10 + (f[i] - '0');
      } else if (frac_digits == 9) {
        round_up = f[i] >= '5';
      }
      ++frac_digits;
      ++i;
    }
  }
  if (i != f.size() || digits + frac_digits == 0) return false;
  for (std::size_t k = frac_digits; k < 9; ++k) frac *= 10;
  t = whole * 1000000000 + frac + (round_up ? 1 : 0);
  if (negative) t = -t;
  return true;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file (missing or unreadable)");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

Trajectory loadTum(const std::string& path, EmptyTum empty) {
  if (fs::is_directory(path)) throw InputError(path + ": is a directory, expected a TUM file");
  const std::string content = readFile(path);
  Trajectory trajectory({}, path);
  std::size_t pos = 0, line_number = 0, previous_line = 0;
  while (pos < content.size()) {
    const std::size_t end = std::min(content.find('\n', pos), content.size());
    const std::string_view line(content.data() + pos, end - pos);
    pos = end + 1;
    ++line_number;
    const auto fields = splitWhitespace(line);
    if (fields.empty() || fields.front().front() == '#') continue;
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    if (fields.size() != 8) {
      throw InputError(where + "TUM pose has " + std::to_string(fields.size()) +
                       " fields, expected 8 (t x y z qx qy qz qw)");
    }
    StampedPose pose;
    double v[8];
    for (int k = 0; k < 8; ++k) {
      if (!parseDouble(fields[k], v[k])) {
        throw InputError(where + "field '" + kTumFields[k] + "': '" + std::string(fields[k]) +
                         "' is not a number");
      }
      if (!std::isfinite(v[k])) {
        throw InputError(where + "field '" + kTumFields[k] + "': '" + std::string(fields[k]) +
                         "' is not finite");
      }
    }
    // 9.2e9 s is where nanoseconds leave int64; a time past it is nanoseconds written as seconds.
    if (std::abs(v[0]) > 9.0e9) {
      throw InputError(where + "field 't': " + std::string(fields[0]) +
                       " s is out of range (TUM times are seconds; nanoseconds?)");
    }
    if (!parseSecondsExact(fields[0], pose.t)) pose.t = fromSeconds(v[0]);
    pose.p = {v[1], v[2], v[3]};
    pose.q = Eigen::Quaterniond(v[7], v[4], v[5], v[6]);
    const double norm = pose.q.norm();
    if (std::abs(norm - 1.0) > 1e-2) {
      throw InputError(where + "quaternion (qx qy qz qw) has norm " + std::to_string(norm) +
                       ", expected 1");
    }
    pose.q.normalize();
    if (!trajectory.empty() && pose.t <= trajectory.poses().back().t) {
      throw InputError(where + "field 't': time " + std::string(fields[0]) +
                       " s does not increase (line " + std::to_string(previous_line) + " has " +
                       std::to_string(toSeconds(trajectory.poses().back().t)) + " s)");
    }
    trajectory.append(pose);
    previous_line = line_number;
  }
  if (trajectory.empty() && empty == EmptyTum::kError) throw InputError(path + ": contains no poses");
  return trajectory;
}

Trajectory loadEurocGroundTruth(const std::string& dataset_dir) {
  const fs::path p(dataset_dir);
  fs::path csv;
  if (fs::is_regular_file(p)) {
    csv = p;
  } else if (fs::exists(p / "mav0" / "state_groundtruth_estimate0" / "data.csv")) {
    csv = p / "mav0" / "state_groundtruth_estimate0" / "data.csv";
  } else if (fs::exists(p / "state_groundtruth_estimate0" / "data.csv")) {
    csv = p / "state_groundtruth_estimate0" / "data.csv";
  } else {
    throw InputError(dataset_dir + ": no EuRoC ground truth (expected " +
                     (p / "mav0" / "state_groundtruth_estimate0" / "data.csv").string() + ")");
  }
  const auto states = dataset::EurocFileReader::readGroundTruth(csv.string());
  if (states.empty()) throw InputError(csv.string() + ": contains no ground-truth states");
  Trajectory trajectory({}, csv.string());
  for (const auto& s : states) trajectory.append({s.t, s.p_WB, s.q_WB});
  return trajectory;
}

Trajectory loadTrajectory(const std::string& path) {
  const fs::path p(path);
  if (!fs::exists(p)) throw InputError(path + ": no such file or directory");
  if (fs::is_directory(p)) {
    if (fs::is_regular_file(p / "trajectory.tum")) return loadTum((p / "trajectory.tum").string());
    return loadEurocGroundTruth(path);
  }
  if (p.extension() == ".csv") return loadEurocGroundTruth(path);
  return loadTum(path);
}

std::optional<Trajectory> loadOnlineTrajectory(const std::string& run_dir) {
  const fs::path p = fs::path(run_dir) / "trajectory_online.tum";
  if (!fs::is_regular_file(p)) return std::nullopt;
  return loadTum(p.string());
}

void writeTum(const Trajectory& trajectory, const std::string& path) {
  const fs::path p(path);
  if (p.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
  }
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throwCannotWrite(path, errno);
  std::fprintf(f, "# t x y z qx qy qz qw  (body pose in world; t in seconds)\n");
  for (const auto& pose : trajectory.poses()) {
    const Timestamp sec = pose.t >= 0 ? pose.t / 1000000000 : -((-pose.t) / 1000000000);
    const Timestamp ns = pose.t >= 0 ? pose.t % 1000000000 : (-pose.t) % 1000000000;
    std::fprintf(f, "%s%" PRId64 ".%09" PRId64 " %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                 (pose.t < 0 && sec == 0) ? "-" : "", sec, ns, pose.p.x(), pose.p.y(),
                 pose.p.z(), pose.q.x(), pose.q.y(), pose.q.z(), pose.q.w());
  }
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) throwCannotWrite(path, errno);
}

}  // namespace mcvio::evaluation
