#pragma once
#include <functional>
#include <string>

#include "mcvio/core/input_error.hpp"

namespace mcvio::test {

/// The message of the mcvio::InputError `f` throws; empty if it throws none.
inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace mcvio::test
