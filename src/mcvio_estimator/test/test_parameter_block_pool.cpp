#include <gtest/gtest.h>

#include "mcvio/estimator/parameter_block_pool.hpp"

namespace mcvio::estimator {
namespace {

TEST(ParameterBlockPool, HandsOutTheLowestFreeSlotInOneArray) {
  ParameterBlockPool pool(3, 2);
  EXPECT_EQ(pool.acquire(), 0u);
  EXPECT_EQ(pool.acquire(), 1u);
  EXPECT_EQ(pool.data(1) - pool.data(0), 3);
  EXPECT_EQ(pool.acquire(), 2u);
  EXPECT_EQ(pool.acquire(), 3u);
  pool.release(2);
  pool.release(0);
  EXPECT_EQ(pool.inUse(), 2u);
  EXPECT_EQ(pool.acquire(), 0u);
  EXPECT_FALSE(pool.moved());
  EXPECT_EQ(pool.acquire(), 2u);
  EXPECT_EQ(pool.acquire(), 4u);
  pool.clear();
  EXPECT_EQ(pool.inUse(), 0u);
  EXPECT_EQ(pool.acquire(), 0u);
}

TEST(ParameterBlockPool, ReportsWhenGrowingMovedTheBlocks) {
  ParameterBlockPool pool(2, 1);
  pool.acquire();
  pool.data(0)[0] = 1.5;
  pool.data(0)[1] = -2.0;
  const double* before = pool.data(0);
  bool moved = false;
  for (int i = 0; i < 64 && !moved; ++i) {
    pool.acquire();
    moved = pool.moved();
  }
  ASSERT_TRUE(moved) << "the reserve of one block must have been outgrown";
  EXPECT_NE(pool.data(0), before);
  EXPECT_EQ(pool.data(0)[0], 1.5);  // values move with their slots
  EXPECT_EQ(pool.data(0)[1], -2.0);
  EXPECT_THROW(ParameterBlockPool(0), std::invalid_argument);
}

}  // namespace
}  // namespace mcvio::estimator
