#include "mcvio/core/yaml_fields.hpp"

#include <gtest/gtest.h>

#include <functional>

#include "input_error_message.hpp"

namespace mcvio {
namespace {

using test::errorOf;

TEST(YamlFields, ReadsPresentKeysAndLeavesAbsentOnesAtTheirDefaults) {
  const YAML::Node node = YAML::Load("count: 7\nscale: 0.5\nname: huber\nflag: true\nv: [1, 2, 3]\nsection: {a: 1}\n");
  YamlFields f(node, "", "estimator option");
  int count = 1, missing = 42;
  double scale = 1.0;
  std::string name;
  bool flag = false;
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  f.get("count", &count);
  f.get("missing", &missing);
  f.get("scale", &scale);
  f.get("name", &name);
  f.get("flag", &flag);
  f.getVector3("v", &v);
  EXPECT_TRUE(f.child("section")["a"]);
  EXPECT_NO_THROW(f.rejectUnknown());
  EXPECT_EQ(count, 7);
  EXPECT_EQ(missing, 42);
  EXPECT_DOUBLE_EQ(scale, 0.5);
  EXPECT_EQ(name, "huber");
  EXPECT_TRUE(flag);
  EXPECT_EQ(v, Eigen::Vector3d(1, 2, 3));
}

TEST(YamlFields, ErrorsNameTheKeyWithItsSection) {
  auto read = [](const std::string& yaml, const std::function<void(YamlFields&)>& use) {
    return errorOf([&] {
      YamlFields f(YAML::Load(yaml), "conflict.", "estimator option");
      use(f);
      f.rejectUnknown();
    });
  };
  int i = 0;
  double d = 0;
  Eigen::Vector3d v;
  EXPECT_EQ(read("horizon: many\n", [&](YamlFields& f) { f.get("horizon", &i); }).rfind(
                "estimator option 'conflict.horizon' has an invalid value 'many'", 0),
            0u);
  EXPECT_EQ(read("sigma: .nan\n", [&](YamlFields& f) { f.get("sigma", &d); }),
            "estimator option 'conflict.sigma' must be finite");
  EXPECT_EQ(read("sigma: 1\nsigm: 2\n", [&](YamlFields& f) { f.get("sigma", &d); }),
            "unknown estimator option 'conflict.sigm'");
  EXPECT_EQ(read("g: [1, 2]\n", [&](YamlFields& f) { f.getVector3("g", &v); }),
            "estimator option 'conflict.g' must be a list of 3 numbers");
  EXPECT_EQ(read("g: [1, x, 2]\n", [&](YamlFields& f) { f.getVector3("g", &v); }),
            "estimator option 'conflict.g': element 1 is not a number");
  EXPECT_EQ(errorOf([] { YamlFields f(YAML::Load("[1, 2]"), "conflict.", "estimator option"); }),
            "'conflict' must be a map of estimator options");
  EXPECT_EQ(errorOf([] { YamlFields f(YAML::Load("just text"), "", "key"); }), "expected a map of keys");
}

TEST(YamlFields, ANullNodeReadsAsEmpty) {
  YamlFields f(YAML::Node(), "", "key");
  int i = 3;
  f.get("i", &i);
  EXPECT_EQ(i, 3);
  EXPECT_FALSE(f.has("i"));
  EXPECT_NO_THROW(f.rejectUnknown());
}

}  // namespace
}  // namespace mcvio
