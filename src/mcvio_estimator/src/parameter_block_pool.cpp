#include "mcvio/estimator/parameter_block_pool.hpp"

#include <stdexcept>

namespace mcvio::estimator {

ParameterBlockPool::ParameterBlockPool(int block_size, std::size_t reserve_blocks)
    : block_size_(static_cast<std::size_t>(block_size)) {
  if (block_size <= 0) throw std::invalid_argument("ParameterBlockPool: block size must be positive");
  values_.reserve(reserve_blocks * block_size_);
}

std::uint32_t ParameterBlockPool::acquire() {
  moved_ = false;
  if (!free_.empty()) {
    const std::uint32_t slot = free_.top();
    free_.pop();
    return slot;
  }
  const double* before = values_.data();
  values_.resize(values_.size() + block_size_, 0.0);
  moved_ = values_.data() != before && slots_ > 0;
  return static_cast<std::uint32_t>(slots_++);
}

void ParameterBlockPool::release(std::uint32_t slot) {
  if (slot < slots_) free_.push(slot);
}

void ParameterBlockPool::clear() {
  free_ = {};
  values_.clear();
  slots_ = 0;
  moved_ = false;
}

}  // namespace mcvio::estimator
