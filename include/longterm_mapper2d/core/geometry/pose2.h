#pragma once

#include <Eigen/Core>
#include <cmath>
#include <string>

namespace longterm_mapper2d {

// Wraps an angle to (-pi, pi]. Inline for the common case of an angle already in range (every
// pose composition and every bin lookup calls it).
double NormalizeAngleSlow(double angle_rad);
inline double NormalizeAngle(double angle_rad) {
  return angle_rad > -M_PI && angle_rad <= M_PI ? angle_rad : NormalizeAngleSlow(angle_rad);
}

// A rigid motion in the plane, SE(2). A pose named a_T_b maps coordinates in frame b to frame a:
// p_a = a_T_b * p_b. Composition follows the frames: a_T_c = a_T_b * b_T_c.
class Pose2 {
 public:
  Pose2() = default;
  Pose2(double x_m, double y_m, double theta_rad);
  Pose2(const Eigen::Vector2d& translation_m, double theta_rad);

  // (x, y, theta) as a vector; theta is normalised.
  static Pose2 FromVector(const Eigen::Vector3d& xytheta);
  static Pose2 Identity() { return Pose2(); }

  double x() const { return x_; }
  double y() const { return y_; }
  double theta() const { return theta_; }
  Eigen::Vector2d translation() const { return {x_, y_}; }
  Eigen::Matrix2d rotation() const;
  Eigen::Vector3d vector() const { return {x_, y_, theta_}; }
  // Homogeneous 3x3 matrix.
  Eigen::Matrix3d matrix() const;

  Pose2 inverse() const;
  Pose2 operator*(const Pose2& rhs) const;
  Eigen::Vector2d operator*(const Eigen::Vector2d& point) const;

  // this^-1 * other: `other` expressed in the frame of this pose.
  Pose2 Between(const Pose2& other) const { return inverse() * other; }

  bool IsFinite() const;
  std::string ToString() const;

 private:
  double x_ = 0.0;
  double y_ = 0.0;
  double theta_ = 0.0;
};

// Linear interpolation of translation and shortest-arc interpolation of the angle; t in [0, 1].
Pose2 Interpolate(const Pose2& a, const Pose2& b, double t);

// Jacobians of the composition c = a * b with respect to a and b, in (x, y, theta) coordinates
// with additive increments, used to propagate covariances: P_c = Ja P_a Ja^T + Jb P_b Jb^T.
//   c.t = a.t + R(a.theta) b.t,  c.theta = a.theta + b.theta
//   dc/da = [[1, 0, -(R b.t)_y], [0, 1, (R b.t)_x], [0, 0, 1]],  dc/db = blockdiag(R(a.theta), 1)
Eigen::Matrix3d ComposeJacobianLeft(const Pose2& a, const Pose2& b);
Eigen::Matrix3d ComposeJacobianRight(const Pose2& a, const Pose2& b);

// SE(2) adjoint: X exp(delta) X^-1 = exp(Adjoint(X) delta) for delta = (dx, dy, dtheta), exp(delta)
// being Pose2(dx, dy, dtheta) to first order.
Eigen::Matrix3d Adjoint(const Pose2& X);

// A pose with a timestamp in seconds.
struct StampedPose2 {
  double stamp_s = 0.0;
  Pose2 pose;
};

}  // namespace longterm_mapper2d
