#pragma once
#include <cstdint>
#include <functional>
#include <queue>
#include <vector>

namespace mcvio::estimator {

/// Parameter blocks of one size in one contiguous array, the lowest free slot handed out first.
///
/// Ceres orders the blocks of an elimination group by address. Blocks at heap addresses made the
/// order of the Schur complement's sums, and with it the last bits of every solve, depend on all
/// the process had allocated before (a chaotic run, such as a reference VIO dragged along by a
/// pedestrian, then ended anywhere between 0.14 and 0.79 m ATE on the same input). In slots the
/// addresses follow the estimator's own history only.
class ParameterBlockPool {
 public:
  explicit ParameterBlockPool(int block_size, std::size_t reserve_blocks = 1024);

  /// A free slot. When the array has to grow every block moves: data() pointers taken before are
  /// invalid (see moved()).
  std::uint32_t acquire();
  void release(std::uint32_t slot);
  /// Frees every slot (the storage stays).
  void clear();

  double* data(std::uint32_t slot) { return values_.data() + static_cast<std::size_t>(slot) * block_size_; }
  /// Whether the last acquire() moved the blocks.
  bool moved() const { return moved_; }
  std::size_t inUse() const { return slots_ - free_.size(); }

 private:
  std::size_t block_size_;
  std::vector<double> values_;
  std::size_t slots_ = 0;
  std::priority_queue<std::uint32_t, std::vector<std::uint32_t>, std::greater<>> free_;
  bool moved_ = false;
};

}  // namespace mcvio::estimator
