#pragma once
// For the reader fuzz targets: verify() must report, never throw; what it reports is not checked.
#include <cstdint>
#include <string>

#include "mcvio/bag/storage_file_reader.hpp"

struct IgnoringVerifySink : mcvio::bag::VerifySink {
  void readable(const std::string&) override {}
  void unreadable(const std::string&, std::uint64_t, const std::string&) override {}
  void problem(const std::string&) override {}
};
