#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace mcvio {

/// ROS 2 topic remapping (`-r FROM:=TO`, `remap:` in a launch file): a component that would use
/// topic FROM uses TO instead, so mcvio runs on a camera driver's or a bag's own topic names
/// (`/cam0/image_raw:=/camera/infra1/image_rect_raw`). Names are taken absolute ("imu0" is
/// "/imu0"), as everywhere in mcvio. Each FROM may appear once; node-name and namespace rules
/// (`__node:=`, `__ns:=`) are not topic remaps and are refused.
class TopicRemapping {
 public:
  struct Rule {
    std::string from, to;
  };

  TopicRemapping() = default;
  /// Parses "FROM:=TO" rules; throws mcvio::InputError naming the rule and what is wrong with it.
  static TopicRemapping parse(const std::vector<std::string>& rules);

  /// Adds one rule; throws mcvio::InputError for an invalid name or a FROM given twice.
  void add(std::string_view from, std::string_view to);

  /// The topic a component uses for `topic`: the rule's TO, or `topic` (made absolute).
  std::string resolve(std::string_view topic) const;

  bool empty() const { return rules_.empty(); }
  const std::vector<Rule>& rules() const { return rules_; }
  /// "FROM:=TO" of every rule, in the order given (for command lines and messages).
  std::vector<std::string> toStrings() const;

 private:
  std::vector<Rule> rules_;
};

}  // namespace mcvio
