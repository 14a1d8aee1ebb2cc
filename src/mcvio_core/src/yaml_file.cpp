#include "mcvio/core/yaml_file.hpp"

#include <filesystem>
#include <map>
#include <system_error>

#include "mcvio/core/input_error.hpp"

namespace mcvio {

namespace {

std::string lineOf(const YAML::Mark& mark) { return std::to_string(mark.line + 1); }

}  // namespace

void rejectDuplicateYamlKeys(const YAML::Node& node, const std::string& source) {
  if (node.IsSequence()) {
    for (const YAML::Node& item : node) rejectDuplicateYamlKeys(item, source);
    return;
  }
  if (!node.IsMap()) return;
  std::map<std::string, YAML::Mark> first_seen;
  for (const auto& kv : node) {
    // Complex keys (maps as keys) do not occur in our files; compare only scalar keys.
    if (kv.first.IsScalar()) {
      const std::string key = kv.first.Scalar();
      const auto [it, inserted] = first_seen.emplace(key, kv.first.Mark());
      if (!inserted) {
        throw InputError(source + ":" + lineOf(kv.first.Mark()) + ": key '" + key +
                         "' appears twice (first at line " + lineOf(it->second) +
                         "); only the first would be used, remove one");
      }
    }
    rejectDuplicateYamlKeys(kv.second, source);
  }
}

YAML::Node parseYamlText(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ":" + lineOf(e.mark) + ": YAML syntax error: " + e.msg);
  }
  rejectDuplicateYamlKeys(root, source);
  return root;
}

YAML::Node loadYamlFile(const std::string& path, const std::string& what) {
  // yaml-cpp opens a folder as an empty stream and then fails inside the C++ library's reader.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a folder; the " + what + " must be a YAML file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path + ": cannot open " + what + " (missing or unreadable)");
  } catch (const YAML::Exception& e) {
    throw InputError(path + ":" + lineOf(e.mark) + ": YAML syntax error: " + e.msg);
  }
  rejectDuplicateYamlKeys(root, path);
  return root;
}

}  // namespace mcvio
