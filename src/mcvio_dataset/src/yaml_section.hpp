#pragma once
// A map of a calibration file being read (internal to mcvio_dataset): every error names the
// file, the section when there is one ("cam1: "), the key and, where known, the line.
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace mcvio::dataset::detail {

class YamlSection {
 public:
  /// `section` empty: the file's top level.
  YamlSection(std::string path, std::string section, YAML::Node node);

  bool has(const std::string& key) const { return static_cast<bool>(node_[key]); }
  YAML::Node require(const std::string& key) const { return require(node_, key); }
  YAML::Node require(const YAML::Node& parent, const std::string& key) const;
  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& what) const;

  double number(const YAML::Node& node, const std::string& key) const;
  double number(const std::string& key) const { return number(require(key), key); }
  double positive(const std::string& key) const;
  std::string text(const std::string& key) const;
  std::vector<double> numbers(const YAML::Node& node, const std::string& key, std::size_t min_count,
                              std::size_t max_count) const;
  std::vector<double> numbers(const std::string& key, std::size_t min_count, std::size_t max_count) const {
    return numbers(require(key), key, min_count, max_count);
  }

  const std::string& path() const { return path_; }
  /// "cam1: " for a section, "" for the top level.
  std::string prefix() const { return section_.empty() ? std::string() : section_ + ": "; }

 private:
  std::string path_, section_;
  YAML::Node node_;
};

}  // namespace mcvio::dataset::detail
