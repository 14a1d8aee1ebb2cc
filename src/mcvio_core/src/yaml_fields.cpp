#include "mcvio/core/yaml_fields.hpp"

#include <sstream>

namespace mcvio {

YamlFields::YamlFields(const YAML::Node& node, std::string prefix, std::string what)
    : node_(node), prefix_(std::move(prefix)), what_(std::move(what)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) {
    if (prefix_.empty()) throw InputError("expected a map of " + what_ + "s");
    throw InputError("'" + prefix_.substr(0, prefix_.size() - 1) + "' must be a map of " + what_ + "s");
  }
}

bool YamlFields::lookUp(const std::string& key, YAML::Node* value) {
  known_.insert(key);
  if (!node_ || !node_.IsMap()) return false;
  const YAML::Node& map = node_;  // the const operator[] never adds the key
  const YAML::Node v = map[key];
  if (!v) return false;
  *value = v;
  return true;
}

bool YamlFields::has(const std::string& key) {
  YAML::Node ignored;
  return lookUp(key, &ignored);
}

std::string YamlFields::text(const YAML::Node& v) {
  if (v.IsScalar()) return v.Scalar();
  return v.IsSequence() ? "<a list>" : v.IsMap() ? "<a map>" : "<null>";
}

void YamlFields::getVector3(const std::string& key, Eigen::Vector3d* value) {
  YAML::Node n;
  if (!lookUp(key, &n)) return;
  if (!n.IsSequence() || n.size() != 3) throw InputError(what_ + " '" + name(key) + "' must be a list of 3 numbers");
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    try {
      out[i] = n[i].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(what_ + " '" + name(key) + "': element " + std::to_string(i) + " is not a number");
    }
    if (!std::isfinite(out[i])) throw InputError(what_ + " '" + name(key) + "' must be finite");
  }
  *value = out;
}

YAML::Node YamlFields::child(const std::string& key) {
  YAML::Node n;
  return lookUp(key, &n) ? n : YAML::Node();
}

void YamlFields::rejectUnknown() const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("<not a scalar>");
    if (known_.count(key) == 0) throw InputError("unknown " + what_ + " '" + name(key) + "'");
  }
}

void requireOption(bool ok, const std::string& what, const std::string& key, const std::string& rule, double value) {
  if (ok && std::isfinite(value)) return;
  std::ostringstream os;
  os << what << " '" << key << "' " << rule << " (got " << value << ")";
  throw InputError(os.str());
}

void requireOption(bool ok, const std::string& what, const std::string& key, const std::string& rule) {
  if (!ok) throw InputError(what + " '" + key + "' " + rule);
}

}  // namespace mcvio
