#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"

#include <algorithm>
#include <cmath>

namespace longterm_mapper2d {
namespace {

// Unit eigenvector of the smallest eigenvalue of a symmetric 2x2 matrix [[a, b], [b, c]], and
// the ratio of the eigenvalues.
Eigen::Vector2d SmallestEigenvector(double a, double b, double c, double* ratio) {
  const double mean = 0.5 * (a + c);
  const double diff = 0.5 * (a - c);
  const double radius = std::sqrt(diff * diff + b * b);
  const double lambda_min = mean - radius, lambda_max = mean + radius;
  *ratio = lambda_max > 0.0 ? lambda_min / lambda_max : 1.0;
  // (A - lambda_min I) v = 0: v is orthogonal to either row of A - lambda_min I.
  Eigen::Vector2d v;
  if (std::abs(a - lambda_min) >= std::abs(c - lambda_min)) {
    v = Eigen::Vector2d(-b, a - lambda_min);
  } else {
    v = Eigen::Vector2d(c - lambda_min, -b);
  }
  const double norm = v.norm();
  return norm > 0.0 ? Eigen::Vector2d(v / norm) : Eigen::Vector2d(1.0, 0.0);
}

}  // namespace

Cloud PointsFromScan(const LaserScan& scan, const CloudOptions& options, std::vector<int>* beams) {
  Cloud cloud;
  cloud.reserve(scan.ranges.size());
  if (beams) {
    beams->clear();
    beams->reserve(scan.ranges.size());
  }
  const double max_range = std::min<double>(options.max_range_m, scan.range_max_m);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const float r = scan.ranges[i];
    if (!scan.IsValidRange(r) || r >= max_range || r <= 0.0f) continue;
    const double angle = scan.BeamAngle(i);
    RichPoint p;
    p.point_m = Eigen::Vector2d(r * std::cos(angle), r * std::sin(angle));
    p.weight = 1.0 / r;
    cloud.push_back(p);
    if (beams) beams->push_back(static_cast<int>(i));
  }
  return cloud;
}

void EstimateNormals(Cloud& cloud, const CloudOptions& options, double angle_increment_rad) {
  const double radius_per_m = options.normal_radius_beams * std::abs(angle_increment_rad);
  const int n = static_cast<int>(cloud.size());
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& centre = cloud[i].point_m;
    const double radius = std::max(options.normal_radius_m, radius_per_m * centre.norm());
    const double radius_sq = radius * radius;
    // Walk left and right over consecutive returns while they stay within the radius.
    int lo = i, hi = i;
    while (lo - 1 >= 0 && (cloud[lo - 1].point_m - centre).squaredNorm() < radius_sq) --lo;
    while (hi + 1 < n && (cloud[hi + 1].point_m - centre).squaredNorm() < radius_sq) ++hi;
    const int count = hi - lo + 1;
    if (count < options.normal_min_points) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (int k = lo; k <= hi; ++k) mean += cloud[k].point_m;
    mean /= count;
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (int k = lo; k <= hi; ++k) {
      const Eigen::Vector2d d = cloud[k].point_m - mean;
      sxx += d.x() * d.x();
      sxy += d.x() * d.y();
      syy += d.y() * d.y();
    }
    double ratio = 1.0;
    Eigen::Vector2d normal = SmallestEigenvector(sxx, sxy, syy, &ratio);
    if (ratio > options.normal_max_curvature) continue;
    // Face the laser (at the origin of this frame).
    if (normal.dot(centre) > 0.0) normal = -normal;
    cloud[i].normal = normal;
  }
}

Cloud CloudFromScan(const LaserScan& scan, const Pose2& base_T_laser, const CloudOptions& options,
                    std::vector<int>* beam_of_point) {
  Cloud cloud = PointsFromScan(scan, options, beam_of_point);
  EstimateNormals(cloud, options, scan.angle_increment_rad);
  return Transform(base_T_laser, cloud);
}

}  // namespace longterm_mapper2d
