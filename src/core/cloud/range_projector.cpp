#include "longterm_mapper2d/core/cloud/range_projector.h"

#include <cmath>
#include <limits>

#include "longterm_mapper2d/core/geometry/fast_atan2.h"

namespace longterm_mapper2d {

ProjectorGeometry ProjectorGeometry::FromScan(const LaserScan& scan, double max_range_m) {
  ProjectorGeometry g;
  g.angle_min_rad = scan.angle_min_rad;
  g.angle_increment_rad = scan.angle_increment_rad;
  g.num_bins = static_cast<int>(scan.ranges.size());
  g.min_range_m = scan.range_min_m;
  g.max_range_m = std::min(max_range_m, scan.range_max_m);
  // A scan covering the circle (within half a beam) wraps around.
  g.wraps = g.num_bins * g.angle_increment_rad >= 2.0 * M_PI - 0.5 * g.angle_increment_rad;
  return g;
}

ProjectorGeometry ProjectorGeometry::FullCircle(int num_bins, double max_range_m) {
  ProjectorGeometry g;
  g.num_bins = num_bins;
  g.angle_increment_rad = 2.0 * M_PI / num_bins;
  g.angle_min_rad = -M_PI;
  g.max_range_m = max_range_m;
  g.wraps = true;
  return g;
}

void RangeImage::Reset(int num_bins) {
  ranges_m.assign(num_bins, std::numeric_limits<float>::infinity());
  indices.assign(num_bins, -1);
  nearest.assign(num_bins, -1);
}

void ProjectCloud(const ProjectorGeometry& geometry, const Pose2& viewpoint_T_cloud,
                  const Cloud& cloud, RangeImage* image) {
  image->Reset(geometry.num_bins);
  const Eigen::Matrix2d rotation = viewpoint_T_cloud.rotation();
  const Eigen::Vector2d translation = viewpoint_T_cloud.translation();
  for (int i = 0; i < static_cast<int>(cloud.size()); ++i) {
    const Eigen::Vector2d q = rotation * cloud[i].point_m + translation;
    const double range = q.norm();
    if (range <= geometry.min_range_m || range >= geometry.max_range_m) continue;
    const int bin = geometry.BinOf(FastAtan2(q.y(), q.x()));
    if (bin < 0 || range >= image->ranges_m[bin]) continue;
    image->ranges_m[bin] = static_cast<float>(range);
    // Facing the viewpoint: the normal points back along the ray (zero normals count as facing).
    const bool facing = q.dot(rotation * cloud[i].normal) <= 0.0;
    image->indices[bin] = facing ? i : -1;
    image->nearest[bin] = i;
  }
}

}  // namespace longterm_mapper2d
