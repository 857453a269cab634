#include "longterm_mapper2d/core/geometry/pose2.h"

#include <gtest/gtest.h>

namespace longterm_mapper2d {
namespace {

void ExpectPoseNear(const Pose2& a, const Pose2& b, double tol = 1e-12) {
  EXPECT_NEAR(a.x(), b.x(), tol);
  EXPECT_NEAR(a.y(), b.y(), tol);
  EXPECT_NEAR(NormalizeAngle(a.theta() - b.theta()), 0.0, tol);
}

TEST(NormalizeAngle, WrapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(NormalizeAngle(0.5), 0.5);
  EXPECT_NEAR(NormalizeAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(NormalizeAngle(2 * M_PI + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-2 * M_PI - 0.1), -0.1, 1e-12);
  EXPECT_NEAR(NormalizeAngle(1e6), std::remainder(1e6, 2 * M_PI), 1e-9);
}

TEST(Pose2, ComposeMatchesHomogeneousMatrices) {
  const Pose2 a(1.0, -2.0, 0.7), b(-0.3, 0.5, -2.9);
  const Eigen::Matrix3d expected = a.matrix() * b.matrix();
  const Pose2 c = a * b;
  EXPECT_TRUE(c.matrix().isApprox(expected, 1e-12));
}

TEST(Pose2, InverseAndBetween) {
  const Pose2 a(1.0, -2.0, 0.7), b(4.0, 1.0, -1.2);
  ExpectPoseNear(a * a.inverse(), Pose2());
  ExpectPoseNear(a * a.Between(b), b);
  const Eigen::Vector2d p(0.3, -0.8);
  EXPECT_TRUE((a.inverse() * (a * p)).isApprox(p, 1e-12));
}

TEST(Pose2, InterpolateTakesShortestArc) {
  const Pose2 a(0, 0, M_PI - 0.1), b(2, 4, -M_PI + 0.1);
  const Pose2 mid = Interpolate(a, b, 0.5);
  EXPECT_NEAR(mid.x(), 1.0, 1e-12);
  EXPECT_NEAR(mid.y(), 2.0, 1e-12);
  EXPECT_NEAR(std::abs(mid.theta()), M_PI, 1e-12);
}

TEST(Pose2, ComposeJacobiansMatchNumericalDerivatives) {
  const Pose2 a(1.0, -2.0, 0.7), b(-0.3, 0.5, -2.9);
  const Eigen::Matrix3d ja = ComposeJacobianLeft(a, b), jb = ComposeJacobianRight(a, b);
  const double h = 1e-7;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = h;
    const Pose2 ap = Pose2::FromVector(a.vector() + d), am = Pose2::FromVector(a.vector() - d);
    const Pose2 bp = Pose2::FromVector(b.vector() + d), bm = Pose2::FromVector(b.vector() - d);
    auto diff = [](const Pose2& p, const Pose2& m) {
      Eigen::Vector3d v = p.vector() - m.vector();
      v[2] = NormalizeAngle(v[2]);
      return v;
    };
    const Eigen::Vector3d num_a = diff(ap * b, am * b) / (2 * h);
    const Eigen::Vector3d num_b = diff(a * bp, a * bm) / (2 * h);
    EXPECT_TRUE(num_a.isApprox(ja.col(k), 1e-6)) << k;
    EXPECT_TRUE(num_b.isApprox(jb.col(k), 1e-6)) << k;
  }
}

TEST(Pose2, AdjointMovesAPerturbationAcrossAPose) {
  // X exp(delta) X^-1 = exp(Adjoint(X) delta), checked by finite differences far from the origin.
  const Pose2 X(350.0, -120.0, 2.2);
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = h;
    const Eigen::Vector3d numeric = ((X * Pose2::FromVector(d) * X.inverse()).vector() -
                                     (X * Pose2::FromVector(-d) * X.inverse()).vector()) /
                                    (2 * h);
    EXPECT_TRUE(numeric.isApprox(Adjoint(X).col(k), 1e-4)) << k << "\n" << numeric;
  }
}

}  // namespace
}  // namespace longterm_mapper2d
