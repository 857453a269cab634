#include "longterm_mapper2d/tools/scan_prefetcher.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace longterm_mapper2d {
namespace {

// A recording of `count` scans stamped 0, 1, 2, ...; optionally failing after `fail_after`.
class CountingRecording : public RecordedScans {
 public:
  CountingRecording(int count, int fail_after = -1) : count_(count), fail_after_(fail_after) {}
  std::uint64_t scan_count() const override { return count_; }
  Status ForEach(const std::function<void(const ScanInput&)>& visit) override {
    for (int i = 0; i < count_; ++i) {
      if (i == fail_after_) return Status::Error("chunk " + std::to_string(i) + " is corrupt");
      ScanInput input;
      input.scan.stamp_s = i;
      input.scan.ranges.assign(10, 1.0f + i);
      input.odom_T_base = Pose2(i, 0.0, 0.0);
      visit(input);
      ++read_;
    }
    return Status::Ok();
  }
  std::uint64_t scans_without_odometry() const override { return 0; }
  std::vector<std::string> warnings() const override { return {}; }
  int read() const { return read_; }

 private:
  int count_, fail_after_;
  int read_ = 0;
};

TEST(ScanPrefetcher, HandsOnEveryScanInOrder) {
  for (std::size_t capacity : {1u, 3u, 256u}) {
    CountingRecording recording(1000);
    std::vector<double> stamps;
    const Status s = ForEachPrefetched(
        recording,
        [&](const ScanInput& input) {
          stamps.push_back(input.scan.stamp_s);
          EXPECT_EQ(input.scan.ranges.size(), 10u);
          EXPECT_FLOAT_EQ(input.scan.ranges[3], 1.0f + static_cast<float>(input.scan.stamp_s));
          EXPECT_DOUBLE_EQ(input.odom_T_base.x(), input.scan.stamp_s);
        },
        capacity);
    ASSERT_TRUE(s.ok()) << s.message();
    ASSERT_EQ(stamps.size(), 1000u);
    for (int i = 0; i < 1000; ++i) ASSERT_EQ(stamps[i], i);
  }
}

TEST(ScanPrefetcher, AReadErrorComesBackAfterTheScansBeforeIt) {
  CountingRecording recording(100, 40);
  int visited = 0;
  const Status s = ForEachPrefetched(
      recording, [&](const ScanInput&) { ++visited; }, 4);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("chunk 40 is corrupt"), std::string::npos);
  EXPECT_EQ(visited, 40);
}

TEST(ScanPrefetcher, AnExceptionInTheVisitorPropagatesWithoutDeadlock) {
  CountingRecording recording(500);
  int visited = 0;
  EXPECT_THROW(ForEachPrefetched(
                   recording,
                   [&](const ScanInput&) {
                     if (++visited == 7) throw std::runtime_error("mapping failed");
                   },
                   2),
               std::runtime_error);
  EXPECT_EQ(visited, 7);
  EXPECT_EQ(recording.read(), 500);  // the reader ran to its end and was joined
}

TEST(ScanPrefetcher, AnEmptyRecordingIsFine) {
  CountingRecording recording(0);
  int visited = 0;
  EXPECT_TRUE(ForEachPrefetched(recording, [&](const ScanInput&) { ++visited; }).ok());
  EXPECT_EQ(visited, 0);
}

}  // namespace
}  // namespace longterm_mapper2d
