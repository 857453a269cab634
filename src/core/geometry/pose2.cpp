#include "longterm_mapper2d/core/geometry/pose2.h"

#include <Eigen/Geometry>
#include <cstdio>

namespace longterm_mapper2d {

double NormalizeAngleSlow(double angle_rad) {
  double wrapped = std::remainder(angle_rad, 2.0 * M_PI);  // in [-pi, pi]
  if (wrapped <= -M_PI) wrapped += 2.0 * M_PI;
  return wrapped;
}

Pose2::Pose2(double x_m, double y_m, double theta_rad)
    : x_(x_m), y_(y_m), theta_(NormalizeAngle(theta_rad)) {}

Pose2::Pose2(const Eigen::Vector2d& translation_m, double theta_rad)
    : Pose2(translation_m.x(), translation_m.y(), theta_rad) {}

Pose2 Pose2::FromVector(const Eigen::Vector3d& xytheta) {
  return Pose2(xytheta.x(), xytheta.y(), xytheta.z());
}

Eigen::Matrix2d Pose2::rotation() const {
  const double c = std::cos(theta_), s = std::sin(theta_);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

Eigen::Matrix3d Pose2::matrix() const {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  m.topLeftCorner<2, 2>() = rotation();
  m.topRightCorner<2, 1>() = translation();
  return m;
}

Pose2 Pose2::inverse() const {
  const double c = std::cos(theta_), s = std::sin(theta_);
  return Pose2(-c * x_ - s * y_, s * x_ - c * y_, -theta_);
}

Pose2 Pose2::operator*(const Pose2& rhs) const {
  const double c = std::cos(theta_), s = std::sin(theta_);
  return Pose2(x_ + c * rhs.x_ - s * rhs.y_, y_ + s * rhs.x_ + c * rhs.y_, theta_ + rhs.theta_);
}

Eigen::Vector2d Pose2::operator*(const Eigen::Vector2d& point) const {
  const double c = std::cos(theta_), s = std::sin(theta_);
  return {x_ + c * point.x() - s * point.y(), y_ + s * point.x() + c * point.y()};
}

bool Pose2::IsFinite() const {
  return std::isfinite(x_) && std::isfinite(y_) && std::isfinite(theta_);
}

std::string Pose2::ToString() const {
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "(%.4f, %.4f, %.4f)", x_, y_, theta_);
  return buffer;
}

Pose2 Interpolate(const Pose2& a, const Pose2& b, double t) {
  const Eigen::Vector2d translation = (1.0 - t) * a.translation() + t * b.translation();
  const double dtheta = NormalizeAngle(b.theta() - a.theta());
  return Pose2(translation, a.theta() + t * dtheta);
}

Eigen::Matrix3d ComposeJacobianLeft(const Pose2& a, const Pose2& b) {
  const Eigen::Vector2d rotated = a.rotation() * b.translation();
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j(0, 2) = -rotated.y();
  j(1, 2) = rotated.x();
  return j;
}

Eigen::Matrix3d Adjoint(const Pose2& X) {
  // X exp(delta) X^-1 has rotation dtheta and translation R t_delta + dtheta (t_y, -t_x).
  Eigen::Matrix3d ad = Eigen::Matrix3d::Identity();
  ad.topLeftCorner<2, 2>() = X.rotation();
  ad(0, 2) = X.y();
  ad(1, 2) = -X.x();
  return ad;
}

Eigen::Matrix3d ComposeJacobianRight(const Pose2& a, const Pose2& /*b*/) {
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j.topLeftCorner<2, 2>() = a.rotation();
  return j;
}

}  // namespace longterm_mapper2d
