#include "mcvio/evaluation/evaluation_options.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::evaluation {

namespace {

template <typename T>
void read(const YAML::Node& map, const std::string& key, const std::string& where, T& out) {
  if (!map[key]) return;
  try {
    out = map[key].as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(where + key + ": '" + YAML::Dump(map[key]) + "' has the wrong type");
  }
}

void rejectUnknown(const YAML::Node& map, const std::set<std::string>& known, const std::string& where) {
  for (const auto& kv : map) {
    const std::string key = kv.first.as<std::string>();
    if (!known.count(key)) throw InputError(where + key + ": unknown key");
  }
}

}  // namespace

EvaluationOptions EvaluationOptions::fromYamlFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "file");
  EvaluationOptions o;
  if (!root || root.IsNull()) return o;
  if (!root.IsMap()) throw InputError(path + ": expected a map of evaluation options");
  const std::string where = path + ": ";
  rejectUnknown(root, {"association", "alignment", "rpe_delta_s", "rpe_delta_m", "rpe_tolerance", "detection", "baseline"}, where);
  read(root, "rpe_delta_s", where, o.rpe_delta_s);
  read(root, "rpe_delta_m", where, o.rpe_delta_m);
  read(root, "rpe_tolerance", where, o.rpe_tolerance);
  read(root, "baseline", where, o.baseline);
  if (const auto a = root["association"]) {
    if (!a.IsMap()) throw InputError(where + "association: expected a map");
    const std::string w = where + "association.";
    rejectUnknown(a, {"method", "max_interpolation_gap_s", "max_time_difference_s"}, w);
    std::string method = o.association.method == AssociationOptions::Method::kNearest ? "nearest" : "interpolate";
    read(a, "method", w, method);
    if (method == "nearest") {
      o.association.method = AssociationOptions::Method::kNearest;
    } else if (method == "interpolate") {
      o.association.method = AssociationOptions::Method::kInterpolate;
    } else {
      throw InputError(w + "method: '" + method + "' is not interpolate or nearest");
    }
    read(a, "max_interpolation_gap_s", w, o.association.max_interpolation_gap_s);
    read(a, "max_time_difference_s", w, o.association.max_time_difference_s);
  }
  if (const auto a = root["alignment"]) {
    if (!a.IsMap()) throw InputError(where + "alignment: expected a map");
    const std::string w = where + "alignment.";
    rejectUnknown(a, {"min_position_spread_m"}, w);
    read(a, "min_position_spread_m", w, o.alignment.min_position_spread_m);
  }
  if (const auto d = root["detection"]) {
    if (!d.IsMap()) throw InputError(where + "detection: expected a map");
    const std::string w = where + "detection.";
    rejectUnknown(d, {"label_tolerance_s", "suspected_is_positive"}, w);
    read(d, "label_tolerance_s", w, o.detection.label_tolerance_s);
    read(d, "suspected_is_positive", w, o.detection.suspected_is_positive);
  }
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(where + e.what());
  }
  return o;
}

void EvaluationOptions::validate() const {
  association.validate();
  detection.validate();
  if (!(alignment.min_position_spread_m >= 0) || !std::isfinite(alignment.min_position_spread_m)) {
    throw std::invalid_argument("alignment.min_position_spread_m must be >= 0");
  }
  if (!(rpe_delta_s > 0) || !std::isfinite(rpe_delta_s)) throw std::invalid_argument("rpe_delta_s must be > 0");
  if (!(rpe_delta_m > 0) || !std::isfinite(rpe_delta_m)) throw std::invalid_argument("rpe_delta_m must be > 0");
  if (!(rpe_tolerance >= 0) || !std::isfinite(rpe_tolerance)) throw std::invalid_argument("rpe_tolerance must be >= 0");
}

}  // namespace mcvio::evaluation
