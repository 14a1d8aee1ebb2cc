#pragma once

namespace mcvio::pipeline {

/// Text of config/vio_pipeline.yaml, compiled in by CMake (shipped_config.cpp.in).
extern const char* const kShippedConfigYaml;

}  // namespace mcvio::pipeline
