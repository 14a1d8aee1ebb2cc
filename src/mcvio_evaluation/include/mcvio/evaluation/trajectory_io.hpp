#pragma once
#include <optional>
#include <string>

#include "mcvio/evaluation/trajectory.hpp"

namespace mcvio::evaluation {

/// Reads a TUM trajectory: one pose per line, `t x y z qx qy qz qw` separated by spaces or tabs,
/// t in seconds (decimal digits are read exactly to the nanosecond), '#' lines and blank lines
/// skipped. Quaternions within 1e-2 of unit norm are normalised.
/// Throws mcvio::InputError "<path>:<line>: ..." naming the field for a missing file, a wrong
/// field count, a field that is not a finite number, a non-unit quaternion or time that does
/// not strictly increase; and, unless `empty` allows it, for a file without poses.
enum class EmptyTum {
  kError,            ///< a trajectory file must hold poses
  kEmptyTrajectory,  ///< header only is an empty trajectory (secondary.tum of a run that tracked no secondary frame)
};
Trajectory loadTum(const std::string& path, EmptyTum empty = EmptyTum::kError);

/// Reads EuRoC ground truth (state_groundtruth_estimate0/data.csv) of a data set: `dataset_dir`
/// is the folder holding mav0/, mav0/ itself, or the CSV file. Errors as EurocFileReader's.
Trajectory loadEurocGroundTruth(const std::string& dataset_dir);

/// Any trajectory mcvio meets, by what `path` is:
///  - a directory with trajectory.tum (an `mcvio run` output folder) -> that TUM file;
///  - another directory -> EuRoC ground truth below it;
///  - a file ending in .csv -> EuRoC ground-truth CSV; any other file -> TUM.
Trajectory loadTrajectory(const std::string& path);

/// The per-frame output of an `mcvio run` output folder, OUT/trajectory_online.tum, which the run
/// writes only when a conflict window revised earlier frames; nullopt without it.
std::optional<Trajectory> loadOnlineTrajectory(const std::string& run_dir);

/// Writes `trajectory` as TUM (time with 9 decimals, so nanoseconds survive a round trip),
/// creating parent folders. Throws mcvio::InputError if the file cannot be written.
void writeTum(const Trajectory& trajectory, const std::string& path);

}  // namespace mcvio::evaluation
