#include "longterm_mapper2d/core/registration/nicp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"
#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CastScan;
using test_support::SyntheticLaser;

struct Scene {
  Cloud reference, current;
  LaserScan current_scan;
};

// Reference: a scan from the origin, in the map frame. Current: a scan from `truth`, in its own
// base frame (laser at the base origin).
Scene MakeSetup(const std::vector<Segment>& world, const Pose2& truth, double noise_m,
                SyntheticLaser laser = {}) {
  laser.range_noise_m = noise_m;
  Scene s;
  const CloudOptions options;
  s.reference = CloudFromScan(CastScan(world, {}, Pose2(), laser, 1), Pose2(), options);
  s.current_scan = CastScan(world, {}, truth, laser, 2);
  s.current = CloudFromScan(s.current_scan, Pose2(), options);
  return s;
}

TEST(Nicp, RecoversAKnownOffsetOnCleanData) {
  const Pose2 truth(0.3, -0.2, 0.08);
  const Scene s = MakeSetup(test_support::IrregularRoom(), truth, 0.0);
  Nicp nicp(RegistrationOptions{});
  const auto geometry = ProjectorGeometry::FromScan(s.current_scan, 30.0);
  const auto result =
      nicp.AlignProjective(s.reference, s.current, Pose2(), Pose2(), geometry, std::nullopt);
  ASSERT_TRUE(result.solved);
  EXPECT_TRUE(result.validation.accepted);
  EXPECT_LT((result.reference_T_current.translation() - truth.translation()).norm(), 1e-3);
  EXPECT_LT(std::abs(NormalizeAngle(result.reference_T_current.theta() - truth.theta())),
            0.01 * M_PI / 180.0);
}

TEST(Nicp, RecoversAKnownOffsetWithCentimetreNoise) {
  const Pose2 truth(-0.25, 0.15, -0.06);
  const Scene s = MakeSetup(test_support::IrregularRoom(), truth, 0.01);
  Nicp nicp(RegistrationOptions{});
  const auto geometry = ProjectorGeometry::FromScan(s.current_scan, 30.0);
  const auto result =
      nicp.AlignProjective(s.reference, s.current, Pose2(), Pose2(), geometry, std::nullopt);
  ASSERT_TRUE(result.validation.accepted);
  EXPECT_LT((result.reference_T_current.translation() - truth.translation()).norm(), 0.01);
  EXPECT_LT(std::abs(NormalizeAngle(result.reference_T_current.theta() - truth.theta())), 0.005);
}

TEST(Nicp, NearestNeighbourAlignsWithALargeRotationError) {
  const Pose2 truth(0.4, 0.3, 0.35);
  const Scene s = MakeSetup(test_support::IrregularRoom(), truth, 0.0);
  RegistrationOptions options;
  options.max_correspondence_distance_m = 1.0;
  options.max_normal_angle_rad = 0.8;
  Nicp nicp(options);
  const auto result =
      nicp.AlignNearestNeighbour(s.reference, s.current, Pose2(),
                                 ProjectorGeometry::FullCircle(720, 30.0), Pose2(), std::nullopt);
  EXPECT_LT((result.reference_T_current.translation() - truth.translation()).norm(), 1e-3);
  EXPECT_LT(std::abs(NormalizeAngle(result.reference_T_current.theta() - truth.theta())), 1e-4);
  EXPECT_TRUE(result.validation.accepted);
  // Without a viewpoint the same pose, not validated (the loop closer's coarse step).
  const auto unvalidated = nicp.AlignNearestNeighbour(s.reference, s.current, Pose2(),
                                                      ProjectorGeometry::FullCircle(720, 30.0),
                                                      std::nullopt, std::nullopt);
  EXPECT_LT((unvalidated.reference_T_current.translation() - truth.translation()).norm(), 1e-3);
  EXPECT_FALSE(unvalidated.validation.accepted);
  EXPECT_EQ(unvalidated.validation.correspondences, 0);
}

TEST(Nicp, OdometryPriorHoldsAnAmbiguousCorridorMatch) {
  // In a featureless corridor x is unobservable: the scan says nothing about it, so the estimate
  // must stay where odometry puts it, while y and theta come from the walls.
  const Pose2 truth(1.0, 0.1, 0.02);
  SyntheticLaser laser;
  laser.max_range_m = 8.0;  // the corridor ends are out of range
  const Scene s = MakeSetup(test_support::Corridor(), truth, 0.0, laser);
  const Pose2 odometry(0.7, 0.0, 0.0);
  PosePrior prior{odometry, Eigen::Vector3d(100.0, 100.0, 400.0).asDiagonal()};
  Nicp nicp(RegistrationOptions{});
  const auto geometry = ProjectorGeometry::FromScan(s.current_scan, 30.0);
  const auto result =
      nicp.AlignProjective(s.reference, s.current, odometry, Pose2(), geometry, prior);
  ASSERT_TRUE(result.solved);
  EXPECT_NEAR(result.reference_T_current.x(), odometry.x(), 0.02);
  EXPECT_NEAR(result.reference_T_current.y(), truth.y(), 0.01);
  EXPECT_NEAR(result.reference_T_current.theta(), truth.theta(), 0.005);
  // The information says so: little along x, much across.
  EXPECT_LT(result.information(0, 0), 0.01 * result.information(1, 1));
}

TEST(Nicp, TargetsTheScanSeesThroughAreNoPartners) {
  // A corridor (its ends out of range) with a person who stood 1.4 m ahead of the reference
  // scan and has walked on 0.3 m along the corridor by the current one; odometry is exact. Only
  // the person pins x: paired with where they stood, they drag the scan back along the
  // corridor. The current beams end behind where the person stood: with the check those
  // reference points are left out and x stays where odometry and the walls put it.
  SyntheticLaser laser;
  laser.max_range_m = 8.0;
  const Pose2 truth(0.1, 0.0, 0.0);
  const Eigen::Vector3d stood(1.5, 0.3, 0.25), walked(1.8, 0.3, 0.25);
  const CloudOptions cloud_options;
  Cloud reference = CloudFromScan(CastScan(test_support::Corridor(), {stood}, Pose2(), laser, 1),
                                  Pose2(), cloud_options);
  for (RichPoint& p : reference) p.observations = 2;  // seen in place twice, then moved
  const LaserScan scan = CastScan(test_support::Corridor(), {walked}, truth, laser, 2);
  const Cloud current = CloudFromScan(scan, Pose2(), cloud_options);
  const auto geometry = ProjectorGeometry::FromScan(scan, 30.0);
  const PosePrior prior{truth, Eigen::Vector3d(200.0, 200.0, 400.0).asDiagonal()};
  auto align = [&](const RegistrationOptions& options) {
    Nicp nicp(options);
    return nicp.AlignProjective(reference, current, truth, Pose2(), geometry, prior);
  };
  RegistrationOptions options;
  const auto dragged = align(options);
  ASSERT_TRUE(dragged.solved);
  EXPECT_EQ(dragged.seen_through, 0);
  EXPECT_GT(std::abs(dragged.reference_T_current.x() - truth.x()), 0.1);

  options.see_through_margin_m = 0.15;
  const auto kept = align(options);
  ASSERT_TRUE(kept.solved);
  EXPECT_GT(kept.seen_through, 5);
  EXPECT_NEAR(kept.reference_T_current.x(), truth.x(), 0.01);
  EXPECT_NEAR(kept.reference_T_current.y(), truth.y(), 0.01);
  EXPECT_NEAR(kept.reference_T_current.theta(), truth.theta(), 0.005);

  // Points seen by more scans than see_through_max_observations are trusted to have stayed.
  for (RichPoint& p : reference) p.observations = 4;
  const auto trusted = align(options);
  EXPECT_EQ(trusted.seen_through, 0);
  EXPECT_EQ(trusted.reference_T_current.vector(), dragged.reference_T_current.vector());
}

TEST(Nicp, PositionInformationRatioIsTheWeakOverTheStrongAxis) {
  // The ratio ignores the heading and does not depend on how the weak axis is turned.
  const double c = std::cos(0.7), s = std::sin(0.7);
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  rotation.topLeftCorner<2, 2>() << c, -s, s, c;
  const Eigen::Matrix3d corridor = Eigen::Vector3d(4.0, 1000.0, 1e6).asDiagonal();
  EXPECT_NEAR(PositionInformationRatio(corridor), 0.004, 1e-12);
  EXPECT_NEAR(PositionInformationRatio(rotation * corridor * rotation.transpose()), 0.004, 1e-9);
  EXPECT_NEAR(PositionInformationRatio(Eigen::Matrix3d::Identity()), 1.0, 1e-12);
  // No position content, or a broken one: nothing is pinned.
  EXPECT_EQ(PositionInformationRatio(Eigen::Matrix3d::Zero()), 0.0);
  Eigen::Matrix3d broken = Eigen::Matrix3d::Identity();
  broken(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(PositionInformationRatio(broken) > 0.0);

  // From alignments: a bare corridor pins the position across only, a room in every direction.
  SyntheticLaser laser;
  laser.max_range_m = 8.0;
  Nicp nicp(RegistrationOptions{});
  const Pose2 truth(0.3, 0.05, 0.02);
  const Scene corridor_scene = MakeSetup(test_support::Corridor(), truth, 0.0, laser);
  const auto along = nicp.AlignProjective(
      corridor_scene.reference, corridor_scene.current, Pose2(), Pose2(),
      ProjectorGeometry::FromScan(corridor_scene.current_scan, 30.0), std::nullopt);
  ASSERT_TRUE(along.solved);
  EXPECT_LT(PositionInformationRatio(along.information), 0.005);
  const Scene room_scene = MakeSetup(test_support::IrregularRoom(), truth, 0.0);
  const auto room = nicp.AlignProjective(room_scene.reference, room_scene.current, Pose2(), Pose2(),
                                         ProjectorGeometry::FromScan(room_scene.current_scan, 30.0),
                                         std::nullopt);
  ASSERT_TRUE(room.solved);
  EXPECT_GT(PositionInformationRatio(room.information), 0.05);
}

TEST(Nicp, ReportsThePriorsShareOfTheInformation) {
  // Along a featureless corridor all the information about x is the prior's; across it the
  // walls say much more than the prior.
  const Pose2 truth(1.0, 0.1, 0.02);
  SyntheticLaser laser;
  laser.max_range_m = 8.0;
  const Scene s = MakeSetup(test_support::Corridor(), truth, 0.0, laser);
  const Pose2 odometry(0.7, 0.0, 0.0);
  const PosePrior prior{odometry, Eigen::Vector3d(100.0, 100.0, 400.0).asDiagonal()};
  Nicp nicp(RegistrationOptions{});
  const auto geometry = ProjectorGeometry::FromScan(s.current_scan, 30.0);
  const auto with =
      nicp.AlignProjective(s.reference, s.current, odometry, Pose2(), geometry, prior);
  ASSERT_TRUE(with.solved);
  // The prior's Hessian at the result (the last iteration's point, converged): J' Omega J with
  // J = [[1, 0, -e_y], [0, 1, e_x], [0, 0, 1]].
  const Eigen::Vector3d e = (with.reference_T_current * odometry.inverse()).vector();
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j(0, 2) = -e.y();
  j(1, 2) = e.x();
  const Eigen::Matrix3d expected = j.transpose() * prior.information * j;
  EXPECT_LT((with.prior_information - expected).norm(), 1e-6 * expected.norm());
  const Eigen::Matrix3d scan = with.information - with.prior_information;
  EXPECT_LT(scan(0, 0), 0.01 * with.prior_information(0, 0));
  EXPECT_GT(scan(1, 1), 10.0 * with.prior_information(1, 1));

  const auto without =
      nicp.AlignProjective(s.reference, s.current, odometry, Pose2(), geometry, std::nullopt);
  ASSERT_TRUE(without.solved);
  EXPECT_TRUE(without.prior_information.isZero(0.0));
}

TEST(Nicp, ARobotFramePriorDoesNotDependOnWhereTheReferenceOriginIs) {
  // The corridor above, odometry off in x and in heading, solved once as it is and once with
  // everything moved 500 m away and turned (a tracker frame far from the odometry origin). In the
  // robot frame the prior gives the same answer both times; in the reference frame its second
  // order term |t| dtheta^2 / 2 moves it (7.8 cm, 0.75 deg here).
  const Pose2 truth(1.0, 0.1, 0.02);
  SyntheticLaser laser;
  laser.max_range_m = 8.0;
  const Scene s = MakeSetup(test_support::Corridor(), truth, 0.0, laser);
  const Pose2 odometry(0.7, 0.0, -0.03);
  const Eigen::Matrix3d body_information = Eigen::Vector3d(100.0, 100.0, 400.0).asDiagonal();
  const Pose2 far(400.0, -300.0, 0.7);
  Cloud far_reference = s.reference;
  for (RichPoint& p : far_reference) {
    p.point_m = far * p.point_m;
    p.normal = far.rotation() * p.normal;
  }
  Nicp nicp(RegistrationOptions{});
  const auto geometry = ProjectorGeometry::FromScan(s.current_scan, 30.0);
  auto solve = [&](const Cloud& reference, const Pose2& frame, bool robot_frame) {
    const Pose2 guess = frame * odometry;
    // The reference-frame form carries the body information over by the adjoint of guess^-1.
    const Eigen::Matrix3d ad = Adjoint(guess.inverse());
    const PosePrior prior{
        guess,
        robot_frame ? body_information : Eigen::Matrix3d(ad.transpose() * body_information * ad),
        robot_frame};
    const auto result = nicp.AlignProjective(reference, s.current, guess, Pose2(), geometry, prior);
    EXPECT_TRUE(result.solved);
    return frame.inverse() * result.reference_T_current;
  };
  const Pose2 near_robot = solve(s.reference, Pose2(), true);
  const Pose2 far_robot = solve(far_reference, far, true);
  // What is left (1.1 mm, 2 mrad here) is the damping, applied in the reference frame's
  // coordinates: far from the origin it slows the turn's convergence.
  EXPECT_LT((near_robot.translation() - far_robot.translation()).norm(), 0.005);
  EXPECT_LT(std::abs(NormalizeAngle(near_robot.theta() - far_robot.theta())), 0.005);
  EXPECT_NEAR(near_robot.y(), truth.y(), 0.01);
  EXPECT_NEAR(near_robot.theta(), truth.theta(), 0.005);
  // Near the origin both forms agree; far from it the reference-frame form moves the answer.
  const Pose2 near_reference = solve(s.reference, Pose2(), false);
  const Pose2 far_reference_frame = solve(far_reference, far, false);
  EXPECT_LT((near_reference.translation() - near_robot.translation()).norm(), 0.01);
  EXPECT_GT((far_reference_frame.translation() - near_robot.translation()).norm(), 0.05);
}

TEST(Nicp, RobotFramePriorJacobianMatchesNumericalDerivatives) {
  // d t2v(mean^-1 exp(delta) T) / d delta = blockdiag(R_E, 1) Ad(T^-1), E = mean^-1 T.
  const Pose2 mean(30.0, -12.0, 1.1);
  const Pose2 T(30.3, -11.8, 1.25);
  auto error = [&](const Pose2& X) { return (mean.inverse() * X).vector(); };
  const Pose2 E = mean.inverse() * T;
  const Eigen::Matrix3d analytic = ComposeJacobianRight(E, Pose2()) * Adjoint(T.inverse());
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = h;
    const Eigen::Vector3d numeric =
        (error(Pose2::FromVector(d) * T) - error(Pose2::FromVector(-d) * T)) / (2 * h);
    EXPECT_TRUE(numeric.isApprox(analytic.col(k), 1e-5)) << k << "\n" << numeric;
  }
}

TEST(Nicp, JacobianMatchesNumericalDerivatives) {
  // The solver's linearisation: total chi2 of fixed pairs at T vs exp(delta) T.
  RichPoint r;
  r.point_m = Eigen::Vector2d(2.0, 1.0);
  r.normal = Eigen::Vector2d(-1.0, 0.2).normalized();
  RichPoint c;
  c.point_m = Eigen::Vector2d(1.7, 1.3);
  c.normal = Eigen::Vector2d(-0.9, -0.1).normalized();
  RegistrationOptions o;
  o.robust_chi2 = 1e9;
  const Pose2 T(0.1, -0.2, 0.3);
  auto error = [&](const Pose2& X) {
    Eigen::Matrix<double, 4, 1> e;
    e.head<2>() = X * c.point_m - r.point_m;
    e.tail<2>() = X.rotation() * c.normal - r.normal;
    return e;
  };
  const Eigen::Vector2d q = T * c.point_m, m = T.rotation() * c.normal;
  Eigen::Matrix<double, 4, 3> analytic;
  analytic << 1, 0, -q.y(), 0, 1, q.x(), 0, 0, -m.y(), 0, 0, m.x();
  const double h = 1e-7;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = h;
    const Eigen::Matrix<double, 4, 1> numeric =
        (error(Pose2::FromVector(d) * T) - error(Pose2::FromVector(-d) * T)) / (2 * h);
    EXPECT_TRUE(numeric.isApprox(analytic.col(k), 1e-5)) << k << "\n" << numeric;
  }
}

TEST(Nicp, EmptyCloudsFailCleanly) {
  Nicp nicp(RegistrationOptions{});
  const auto geometry = ProjectorGeometry::FullCircle(360, 30.0);
  const auto result = nicp.AlignProjective({}, {}, Pose2(1, 2, 3), Pose2(), geometry, std::nullopt);
  EXPECT_FALSE(result.solved);
  EXPECT_FALSE(result.validation.accepted);
  EXPECT_TRUE(result.reference_T_current.IsFinite());
  EXPECT_TRUE(result.information.allFinite());
}

TEST(Nicp, ValidationRejectsAWrongAlignment) {
  const Scene s = MakeSetup(test_support::IrregularRoom(), Pose2(), 0.0);
  Nicp nicp(RegistrationOptions{});
  const auto geometry = ProjectorGeometry::FromScan(s.current_scan, 30.0);
  EXPECT_TRUE(nicp.Validate(s.reference, s.current, Pose2(), Pose2(), geometry).accepted);
  EXPECT_FALSE(
      nicp.Validate(s.reference, s.current, Pose2(1.0, 0.5, 0.4), Pose2(), geometry).accepted);
}

}  // namespace
}  // namespace longterm_mapper2d
