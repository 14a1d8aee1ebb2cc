#pragma once
#include <stdexcept>
#include <string>

namespace mcvio {

/// Bad input from outside (a file, a topic, a field): the message names where it came from.
/// Components catch it, log it and carry on; commands print it and exit non-zero.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mcvio
