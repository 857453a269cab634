#include "longterm_mapper2d/core/common/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace longterm_mapper2d {
namespace {

TEST(ParallelFor, RunsEveryIndexOnce) {
  for (int threads : {0, 1, 2, 4}) {
    for (std::size_t count : {0u, 1u, 2u, 1000u}) {
      std::vector<std::atomic<int>> runs(count);
      ParallelFor(count, threads, [&](std::size_t i) { ++runs[i]; });
      for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(runs[i].load(), 1) << threads << " " << i;
    }
  }
}

TEST(ParallelFor, OneThreadRunsInOrderOnTheCaller) {
  std::vector<std::size_t> order;
  ParallelFor(5, 1, [&](std::size_t i) { order.push_back(i); });
  EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
}

TEST(ParallelFor, AnExceptionComesBackAfterAllThreadsStop) {
  std::atomic<int> started{0};
  EXPECT_THROW(ParallelFor(200, 2,
                           [&](std::size_t i) {
                             ++started;
                             if (i == 3) throw std::runtime_error("alignment failed");
                           }),
               std::runtime_error);
  EXPECT_GE(started.load(), 4);
}

}  // namespace
}  // namespace longterm_mapper2d
