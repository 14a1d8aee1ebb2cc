#include "revisable_tum_file.hpp"

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <system_error>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/write_failure.hpp"

namespace mcvio::pipeline {

namespace {

// Seconds with all nine decimals of the nanosecond stamp: a double holds EuRoC-epoch times only to
// ~200 ns, which breaks matching poses to other per-frame output by time.
void writeSeconds(std::ostream& out, Timestamp t) {
  if (t < 0) out << '-';
  const auto abs_t = static_cast<unsigned long long>(t < 0 ? -t : t);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%llu.%09llu", abs_t / 1000000000ULL, abs_t % 1000000000ULL);
  out << buf;
}

void writePose(std::ostream& f, const RevisableTumFile::Pose& p) {
  writeSeconds(f, p.t);
  f << ' ' << p.p_WB.x() << ' ' << p.p_WB.y() << ' ' << p.p_WB.z() << ' ' << p.q_WB.x() << ' ' << p.q_WB.y() << ' '
    << p.q_WB.z() << ' ' << p.q_WB.w() << '\n';
}

}  // namespace

RevisableTumFile::RevisableTumFile(std::string path, std::string what)
    : path_(std::move(path)), what_(std::move(what)), file_(path_) {
  if (!file_) throwCannotWrite(path_, errno);
  // A per-frame version left by an earlier run into this folder would not belong to this one.
  std::error_code ignored;
  std::filesystem::remove(onlinePath(), ignored);
  file_ << "# t x y z qx qy qz qw  (" << what_ << "; t in seconds)\n" << std::setprecision(9) << std::fixed;
}

void RevisableTumFile::add(Timestamp t, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  poses_.push_back({t, p, q});
  writePose(file_, poses_.back());
}

void RevisableTumFile::revise(const std::vector<Pose>& revisions) {
  if (estimator::applyPoseRevisions(&poses_, revisions)) revised_ = true;
}

void RevisableTumFile::finish() {
  file_.close();
  if (!revised_) return;
  const std::string online = onlinePath();
  std::filesystem::rename(path_, online);
  std::ofstream final_file(path_);
  final_file << "# t x y z qx qy qz qw  (" << what_
             << "; t in seconds; final estimate, conflict windows smoothed; as published per frame: "
             << std::filesystem::path(online).filename().string() << ")\n"
             << std::setprecision(9) << std::fixed;
  for (const auto& p : poses_) writePose(final_file, p);
  if (!final_file) throwCannotWrite(path_, errno);
}

std::string RevisableTumFile::onlinePath() const {
  std::filesystem::path p(path_);
  return p.replace_filename(p.stem().string() + "_online.tum").string();
}

}  // namespace mcvio::pipeline
