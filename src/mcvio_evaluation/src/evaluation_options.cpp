#include "mcvio/evaluation/evaluation_options.hpp"

#include <cmath>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_fields.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::evaluation {

EvaluationOptions EvaluationOptions::fromYamlFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "evaluation options file");
  EvaluationOptions o;
  const std::string where = path + ": ";
  try {
    YamlFields f(root, "", "evaluation option");
    f.get("rpe_delta_s", &o.rpe_delta_s);
    f.get("rpe_delta_m", &o.rpe_delta_m);
    f.get("rpe_tolerance", &o.rpe_tolerance);
    f.get("baseline", &o.baseline);
    YamlFields a(f.child("association"), "association.", "evaluation option");
    std::string method = o.association.method == AssociationOptions::Method::kNearest ? "nearest" : "interpolate";
    a.get("method", &method);
    if (method == "nearest")
      o.association.method = AssociationOptions::Method::kNearest;
    else if (method == "interpolate")
      o.association.method = AssociationOptions::Method::kInterpolate;
    else
      throw InputError("evaluation option '" + a.name("method") + "' must be interpolate or nearest (got '" + method + "')");
    a.get("max_interpolation_gap_s", &o.association.max_interpolation_gap_s);
    a.get("max_time_difference_s", &o.association.max_time_difference_s);
    a.rejectUnknown();
    YamlFields al(f.child("alignment"), "alignment.", "evaluation option");
    al.get("min_position_spread_m", &o.alignment.min_position_spread_m);
    al.rejectUnknown();
    YamlFields d(f.child("detection"), "detection.", "evaluation option");
    d.get("label_tolerance_s", &o.detection.label_tolerance_s);
    d.get("suspected_is_positive", &o.detection.suspected_is_positive);
    d.rejectUnknown();
    f.rejectUnknown();
  } catch (const InputError& e) {
    throw InputError(where + e.what());
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
    throw std::invalid_argument("alignment.min_position_spread_m must be a finite number >= 0");
  }
  if (!(rpe_delta_s > 0) || !std::isfinite(rpe_delta_s)) throw std::invalid_argument("rpe_delta_s must be a finite number > 0");
  if (!(rpe_delta_m > 0) || !std::isfinite(rpe_delta_m)) throw std::invalid_argument("rpe_delta_m must be a finite number > 0");
  if (!(rpe_tolerance >= 0) || !std::isfinite(rpe_tolerance)) throw std::invalid_argument("rpe_tolerance must be a finite number >= 0");
}

}  // namespace mcvio::evaluation
