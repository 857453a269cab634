#include "longterm_mapper2d/core/mapping/local_map_merger.h"

#include <cmath>
#include <limits>

namespace longterm_mapper2d {
namespace {

// Fewer points than this make no virtual scan worth aligning or merging.
constexpr std::size_t kMinVirtualScanPoints = 10;

MergerOptions WithDistance(MergerOptions options, double merge_distance_m) {
  options.merge_distance_m = merge_distance_m;
  return options;
}

bool Covered(const Waypoint& w, const std::vector<Waypoint>& by, double distance_m,
             double angle_rad) {
  for (const Waypoint& other : by) {
    const Pose2 d = other.node_T_base.Between(w.node_T_base);
    if (d.translation().norm() <= distance_m && std::abs(d.theta()) <= angle_rad) return true;
  }
  return false;
}

}  // namespace

LocalMapMerger::LocalMapMerger(const MaintenanceOptions& maintenance, const MergerOptions& merger,
                               const RegistrationOptions& registration, double max_range_m)
    : options_(maintenance),
      max_range_m_(max_range_m),
      merger_(WithDistance(merger, maintenance.merge_distance_m)),
      nicp_(registration) {}

LocalMapMergeStats LocalMapMerger::Merge(const LocalMapNode& old_node, const Pose2& new_T_old,
                                         LocalMapNode* new_node) {
  LocalMapMergeStats stats;
  Cloud merged = Transform(new_T_old, old_node.cloud);
  // The old map's points are the new node's by inheritance until its own scans see them again.
  for (RichPoint& point : merged) point.inherited = true;

  for (const Waypoint& w : new_node->waypoints) {
    if (w.scan.ranges.empty()) continue;
    const Pose2 node_T_laser = w.node_T_base * w.base_T_laser;
    const ProjectorGeometry geometry = ProjectorGeometry::FromScan(w.scan, max_range_m_);
    ProjectCloud(geometry, node_T_laser.inverse(), new_node->cloud, &image_);
    // The virtual scan: the new map's visible points, bin by bin in the waypoint scan's own
    // beams. A bin the raw scan saw as no-return stays free space; any other empty bin is
    // unobserved and leaves the old map alone.
    LaserScan virtual_scan = w.scan;
    Cloud points;
    std::vector<int> beams;
    for (int bin = 0; bin < geometry.num_bins; ++bin) {
      float& range = virtual_scan.ranges[bin];
      const int index = image_.indices[bin];
      const float raw = w.scan.ranges[bin];
      if (index >= 0 && std::isfinite(image_.ranges_m[bin])) {
        range = image_.ranges_m[bin];
        points.push_back(new_node->cloud[index]);
        beams.push_back(bin);
      } else if (image_.nearest[bin] < 0 && !std::isnan(raw) &&
                 (!std::isfinite(raw) || raw >= w.scan.range_max_m)) {
        range = std::numeric_limits<float>::infinity();
      } else {
        range = std::numeric_limits<float>::quiet_NaN();
      }
    }
    if (points.size() < kMinVirtualScanPoints) continue;
    ++stats.virtual_scans;

    // The graph put the two maps together at node accuracy; the scan-level alignment refines
    // that where the old map still looks like the new one.
    Pose2 correction;
    if (options_.align_virtual_scans && !merged.empty()) {
      const RegistrationResult aligned = nicp_.AlignNearestNeighbour(
          merged, points, Pose2(), geometry, node_T_laser, std::nullopt);
      if (aligned.solved && aligned.reference_T_current.IsFinite() &&
          aligned.validation.inlier_ratio > options_.align_min_inlier_ratio &&
          aligned.validation.correspondences > options_.align_min_correspondences) {
        correction = aligned.reference_T_current;
        ++stats.aligned;
      }
    }
    const MergeStats merge = merger_.Merge(merged, Transform(correction, points), beams,
                                           virtual_scan, correction * node_T_laser, max_range_m_);
    stats.merge.added += merge.added;
    stats.merge.fused += merge.fused;
    stats.merge.replaced += merge.replaced;
    stats.merge.erased += merge.erased;
    stats.merge.thinned += merge.thinned;
  }
  if (stats.virtual_scans == 0) {
    // No viewpoint saw the new map (a node without waypoints): keep both clouds.
    merged.insert(merged.end(), new_node->cloud.begin(), new_node->cloud.end());
  }
  new_node->cloud = std::move(merged);

  for (const Waypoint& w : old_node.waypoints) {
    Waypoint moved = w;
    moved.node_T_base = new_T_old * w.node_T_base;
    if (Covered(moved, new_node->waypoints, options_.waypoint_merge_distance_m,
                options_.waypoint_merge_angle_rad)) {
      continue;
    }
    new_node->waypoints.push_back(std::move(moved));
    ++stats.old_waypoints_kept;
  }
  return stats;
}

}  // namespace longterm_mapper2d
