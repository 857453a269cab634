#include "longterm_mapper2d/core/mapping/trajectory_refiner.h"

#include <cmath>

#include "longterm_mapper2d/core/registration/nicp.h"

namespace longterm_mapper2d {
namespace {

Cloud MapPoints(const std::map<NodeId, LocalMapNode>& nodes, bool own_points_only) {
  std::size_t count = 0;
  for (const auto& [id, node] : nodes) count += node.cloud.size();
  Cloud points;
  points.reserve(count);
  for (const auto& [id, node] : nodes) {
    for (const RichPoint& p : node.cloud) {
      if (own_points_only && p.inherited) continue;
      points.push_back(Transform(node.map_T_node, p));
    }
  }
  return points;
}

}  // namespace

TrajectoryRefiner::TrajectoryRefiner(const TrajectoryRefinementOptions& options,
                                     const RegistrationOptions& registration,
                                     const CloudOptions& cloud,
                                     const std::map<NodeId, LocalMapNode>& nodes)
    : options_(options),
      registration_(registration),
      cloud_(cloud),
      map_points_(MapPoints(nodes, options.own_points_only)),
      grid_(map_points_, options.max_correspondence_distance_m) {
  registration_.max_correspondence_distance_m = options.max_correspondence_distance_m;
}

std::optional<Pose2> TrajectoryRefiner::Align(const LaserScan& scan, const Pose2& base_T_laser,
                                              const Pose2& map_T_base_guess) const {
  const Cloud points = CloudFromScan(scan, base_T_laser, cloud_);
  int with_normal = 0;
  for (const RichPoint& p : points) with_normal += p.has_normal();
  if (with_normal == 0) return std::nullopt;
  // The prior in the robot frame: its error does not grow with the distance from the map origin.
  PosePrior prior;
  prior.reference_T_current = map_T_base_guess;
  prior.information = Eigen::Vector3d(options_.prior_information_xy, options_.prior_information_xy,
                                      options_.prior_information_theta)
                          .asDiagonal();
  prior.robot_frame = true;
  Nicp nicp(registration_);
  const RegistrationResult result =
      nicp.AlignNearestNeighbour(grid_, map_points_, points, map_T_base_guess, prior);
  if (!result.solved || !result.reference_T_current.IsFinite() ||
      result.correspondences < options_.min_correspondence_ratio * with_normal) {
    return std::nullopt;
  }
  const Pose2 correction = map_T_base_guess.Between(result.reference_T_current);
  if (correction.translation().norm() > options_.max_correction_m ||
      std::abs(correction.theta()) > options_.max_correction_rad) {
    return std::nullopt;
  }
  return result.reference_T_current;
}

}  // namespace longterm_mapper2d
