#include "longterm_mapper2d/core/mapping/motion_filter.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"
#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CastScan;
using test_support::IrregularRoom;
using test_support::SyntheticLaser;

// The robot crosses the irregular room (laser on the base origin); people are (x, y, radius) in
// the room. `odom_T_base` is what odometry reports, `truth` where the robot really is.
struct Frame {
  ScanInput input;
  Cloud base_points;
};

Frame Observe(double stamp_s, const Pose2& truth, const Pose2& odom_T_base,
              const std::vector<Eigen::Vector3d>& people) {
  SyntheticLaser laser;
  laser.beams = 360;
  laser.range_noise_m = 0.005;
  Frame frame;
  frame.input.scan = CastScan(IrregularRoom(), people, truth, laser, 17 + stamp_s * 10);
  frame.input.scan.stamp_s = stamp_s;
  frame.input.odom_T_base = odom_T_base;
  std::vector<int> beams;
  frame.base_points = PointsFromScan(frame.input.scan, CloudOptions(), &beams);
  EstimateNormals(frame.base_points, CloudOptions());
  return frame;
}

// Moving points of the second of two frames (the first is the reference), and how many of them lie
// within radius + 5 cm of `person` (in the room frame).
struct Marked {
  int total = 0;
  int on_person = 0;
  int person_points = 0;
};

Marked MarkAfter(MotionFilter& filter, const Frame& earlier, const Frame& now,
                 const Pose2& truth_now, const Eigen::Vector3d& person) {
  filter.Remember(earlier.input);
  std::vector<char> moving;
  Marked marked;
  marked.total = filter.FindMoving(now.input, now.base_points, &moving);
  EXPECT_EQ(moving.size(), now.base_points.size());
  EXPECT_EQ(marked.total, std::count(moving.begin(), moving.end(), 1));
  for (std::size_t i = 0; i < now.base_points.size(); ++i) {
    const Eigen::Vector2d p = truth_now * now.base_points[i].point_m;
    if ((p - person.head<2>()).norm() > person.z() + 0.05) continue;
    ++marked.person_points;
    if (moving[i]) ++marked.on_person;
  }
  return marked;
}

const Pose2 kStart(-2.0, 0.0, 0.0);
const Pose2 kOneSecondLater(-1.5, 0.1, 0.05);

TEST(MotionFilter, AStaticRoomHasNothingMoving) {
  MotionFilter filter{MotionFilterOptions()};
  const Frame earlier = Observe(0.0, kStart, kStart, {});
  const Frame now = Observe(1.0, kOneSecondLater, kOneSecondLater, {});
  EXPECT_EQ(MarkAfter(filter, earlier, now, kOneSecondLater, Eigen::Vector3d(9, 9, 0.1)).total, 0);
}

TEST(MotionFilter, APersonWhereTheEarlierScanSawFreeSpaceMovedIn) {
  MotionFilter filter{MotionFilterOptions()};
  const Eigen::Vector3d person(1.0, -1.5, 0.25);
  const Frame earlier = Observe(0.0, kStart, kStart, {Eigen::Vector3d(1.6, -1.9, 0.25)});
  const Frame now = Observe(1.0, kOneSecondLater, kOneSecondLater, {person});
  const Marked marked = MarkAfter(filter, earlier, now, kOneSecondLater, person);
  ASSERT_GE(marked.person_points, 5);
  EXPECT_EQ(marked.on_person, marked.person_points);  // the whole person, edges included
  EXPECT_EQ(marked.total, marked.on_person);          // and nothing else
}

TEST(MotionFilter, APersonWalkingAwayIsSeenWhereItHidItself) {
  MotionFilter filter{MotionFilterOptions()};
  // Straight ahead, 0.3 m farther after a second: its new front was behind its old front.
  const Eigen::Vector3d person(1.3, 0.05, 0.25);
  const Frame earlier = Observe(0.0, kStart, kStart, {Eigen::Vector3d(1.0, 0.0, 0.25)});
  const Frame now = Observe(1.0, kOneSecondLater, kOneSecondLater, {person});
  const Marked marked = MarkAfter(filter, earlier, now, kOneSecondLater, person);
  ASSERT_GE(marked.person_points, 5);
  EXPECT_EQ(marked.on_person, marked.person_points);
  EXPECT_EQ(marked.total, marked.on_person);
}

TEST(MotionFilter, ThePersonIsFoundDespiteOdometryErrorAndTheRoomIsNot) {
  MotionFilter filter{MotionFilterOptions()};
  const Eigen::Vector3d person(1.0, -1.5, 0.25);
  // Odometry: 4 cm short and 1 degree off over the half metre.
  const Pose2 odometry(-1.54, 0.1, 0.05 + 0.0175);
  const Frame earlier = Observe(0.0, kStart, kStart, {Eigen::Vector3d(1.6, -1.9, 0.25)});
  const Frame now = Observe(1.0, kOneSecondLater, odometry, {person});
  const Marked marked = MarkAfter(filter, earlier, now, kOneSecondLater, person);
  EXPECT_GE(marked.on_person, marked.person_points - 2);
  EXPECT_EQ(marked.total, marked.on_person);
}

TEST(MotionFilter, WrongOdometryMarksNothing) {
  // A kidnapped robot: odometry says it stayed, it moved 1.5 m. Most of the room would "move".
  MotionFilter filter{MotionFilterOptions()};
  const Frame earlier = Observe(0.0, kStart, kStart, {});
  const Frame now = Observe(1.0, Pose2(-0.5, 1.0, 0.6), kStart, {});
  EXPECT_EQ(MarkAfter(filter, earlier, now, kOneSecondLater, Eigen::Vector3d(9, 9, 0.1)).total, 0);
}

TEST(MotionFilter, NeedsAnEarlierScanOldEnoughAndNotTooOld) {
  const Eigen::Vector3d person(1.0, -1.5, 0.25);
  const Frame earlier = Observe(0.0, kStart, kStart, {});
  auto marked_at = [&](double stamp_s) {
    MotionFilter filter{MotionFilterOptions()};
    Frame now = Observe(1.0, kOneSecondLater, kOneSecondLater, {person});
    now.input.scan.stamp_s = stamp_s;
    return MarkAfter(filter, earlier, now, kOneSecondLater, person).total;
  };
  EXPECT_GT(marked_at(1.0), 0);
  EXPECT_EQ(marked_at(0.2), 0);   // below min_baseline_s: the person could not have moved much
  EXPECT_EQ(marked_at(10.0), 0);  // beyond max_age_s: odometry has drifted
  EXPECT_EQ(marked_at(-1.0), 0);  // time went backwards: the history is dropped
}

TEST(MotionFilter, OffMarksNothing) {
  MotionFilterOptions options;
  options.enabled = false;
  MotionFilter filter(options);
  const Eigen::Vector3d person(1.0, -1.5, 0.25);
  const Frame earlier = Observe(0.0, kStart, kStart, {});
  const Frame now = Observe(1.0, kOneSecondLater, kOneSecondLater, {person});
  EXPECT_EQ(MarkAfter(filter, earlier, now, kOneSecondLater, person).total, 0);
}

}  // namespace
}  // namespace longterm_mapper2d
