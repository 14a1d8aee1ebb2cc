#include "mcvio/core/yaml_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "input_error_message.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio {
namespace {

using test::errorOf;

TEST(YamlFile, ARepeatedKeyIsAnErrorNamingBothLines) {
  const std::string text = "frontend:\n  max_features: 200\n  fast_threshold: 20\n  max_features: 300\n";
  const std::string message = errorOf([&] { parseYamlText(text, "my.yaml"); });
  EXPECT_NE(message.find("my.yaml:4: key 'max_features' appears twice (first at line 2)"), std::string::npos)
      << message;
}

TEST(YamlFile, RepeatedKeysInsideSequencesAreFoundAndEqualKeysInSiblingsAreFine) {
  EXPECT_NO_THROW(parseYamlText("a: {x: 1}\nb: {x: 2}\nc: [{x: 1}, {x: 2}]\n", "ok.yaml"));
  const std::string message = errorOf([] { parseYamlText("c:\n  - {x: 1, y: 2, x: 3}\n", "seq.yaml"); });
  EXPECT_NE(message.find("seq.yaml:2: key 'x' appears twice"), std::string::npos) << message;
}

TEST(YamlFile, MissingAndMalformedFilesNameTheFile) {
  const auto dir = std::filesystem::temp_directory_path() / "mcvio_yaml_file_test";
  std::filesystem::create_directories(dir);
  const std::string missing = (dir / "none.yaml").string();
  EXPECT_EQ(errorOf([&] { loadYamlFile(missing, "options file"); }),
            missing + ": cannot open options file (missing or unreadable)");
  const std::string bad = (dir / "bad.yaml").string();
  std::ofstream(bad) << "a: 1\nb: [1, 2\n";
  const std::string message = errorOf([&] { loadYamlFile(bad, "options file"); });
  EXPECT_EQ(message.rfind(bad + ":", 0), 0u) << message;
  EXPECT_NE(message.find("YAML syntax error"), std::string::npos) << message;
  const std::string dup = (dir / "dup.yaml").string();
  std::ofstream(dup) << "a: 1\nb: 2\na: 3\n";
  EXPECT_EQ(errorOf([&] { loadYamlFile(dup, "options file"); }).rfind(dup + ":3: key 'a' appears twice", 0), 0u);
  EXPECT_EQ(errorOf([&] { loadYamlFile(dir.string(), "options file"); }),
            dir.string() + ": is a folder; the options file must be a YAML file");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mcvio
