#pragma once

#include <map>
#include <optional>

#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"
#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/mapping/local_map.h"
#include "longterm_mapper2d/core/registration/nearest_neighbour_grid.h"
#include "longterm_mapper2d/core/registration/registration_options.h"

namespace longterm_mapper2d {

// The written trajectory, refined against the finished map (Mapper::Finish). Each scan hangs off
// the local map it was tracked in, through the relative pose the graph had when a merge re-anchored
// it; the local maps agree with each other (pairwise alignments of intel's final map move no node),
// but the scans of a stretch whose node merged into another early keep that early relative pose.
// So at the end, the session's waypoint scans (every input.waypoint_spacing_m) are aligned once
// more, each with the clouds of all local maps at their final poses, from where the trajectory has
// it; the corrections are averaged over half_window_s and applied to every scan's pose. Intel over
// eleven settings: 0.0302 -> 0.0254 m mean relation error, every one better (README, "Accuracy").
struct TrajectoryRefinementOptions {
  bool enabled = true;
  // Nearest-neighbour pairs within this distance (the map is final; the guess is close).
  double max_correspondence_distance_m = 0.2;
  // Align with the points each local map's own scans saw (RichPoint::inherited false), leaving
  // out those a merge carried over from an older local map: those sit where the graph had the
  // older node at the merge, and a stretch refined onto them keeps that moment's error. Intel's
  // eleven settings 0.0268 -> 0.0254 m; the 180 deg patrol 0.0349 -> 0.0331 (interlaced).
  bool own_points_only = true;
  // The trajectory's pose as a prior (NICP weight units, robot frame): holds a scan in a corridor
  // where the map pins it across but not along.
  double prior_information_xy = 100.0;
  double prior_information_theta = 1000.0;
  // An alignment counts if this share of the scan's points with a normal found a partner...
  double min_correspondence_ratio = 0.5;
  // ... and it corrects the pose by at most this much (more is not a refinement).
  double max_correction_m = 0.2;
  double max_correction_rad = 0.05;
  // Each scan takes the mean correction of the aligned scans within this time of it (one scan's
  // alignment has the noise of one scan; the corrections are smooth along the trajectory).
  double half_window_s = 4.0;
  // Scans kept for the refinement per session (one per waypoint, about 5 km of travel; a scan of
  // 361 beams takes 1.5 kB): beyond this the oldest go, and their stretch keeps its unrefined
  // poses. 0: none kept, no refinement.
  int max_scans = 50000;
  int threads = 2;

  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("max_correspondence_distance_m", max_correspondence_distance_m);
    v("own_points_only", own_points_only);
    v("prior_information_xy", prior_information_xy);
    v("prior_information_theta", prior_information_theta);
    v("min_correspondence_ratio", min_correspondence_ratio);
    v("max_correction_m", max_correction_m);
    v("max_correction_rad", max_correction_rad);
    v("half_window_s", half_window_s);
    v("max_scans", max_scans);
    v("threads", threads);
  }
  void Validate(OptionErrors& e) const {
    e.Require(max_correspondence_distance_m > 0.0, "max_correspondence_distance_m",
              "must be positive");
    e.Require(prior_information_xy >= 0.0, "prior_information_xy", "must be non-negative");
    e.Require(prior_information_theta >= 0.0, "prior_information_theta", "must be non-negative");
    e.Require(min_correspondence_ratio >= 0.0 && min_correspondence_ratio <= 1.0,
              "min_correspondence_ratio", "must be in [0, 1]");
    e.Require(max_correction_m >= 0.0, "max_correction_m", "must be non-negative");
    e.Require(max_correction_rad >= 0.0, "max_correction_rad", "must be non-negative");
    e.Require(half_window_s >= 0.0 && half_window_s <= 600.0, "half_window_s",
              "must be in [0, 600] s");
    e.Require(max_scans >= 0, "max_scans", "must be non-negative");
    e.Require(threads >= 1, "threads", "must be at least 1");
  }
};

// Aligns single scans with the union of the local maps' clouds in the map frame (one
// nearest-neighbour grid over all of them, built once). Align() may run on several threads.
class TrajectoryRefiner {
 public:
  TrajectoryRefiner(const TrajectoryRefinementOptions& options,
                    const RegistrationOptions& registration, const CloudOptions& cloud,
                    const std::map<NodeId, LocalMapNode>& nodes);

  // map_T_base of the scan aligned with the map from `map_T_base_guess`, or nothing if too few of
  // its points found a partner or the correction exceeds the gates.
  std::optional<Pose2> Align(const LaserScan& scan, const Pose2& base_T_laser,
                             const Pose2& map_T_base_guess) const;

  std::size_t map_points() const { return map_points_.size(); }

 private:
  TrajectoryRefinementOptions options_;
  RegistrationOptions registration_;
  CloudOptions cloud_;
  Cloud map_points_;
  NearestNeighbourGrid grid_;
};

}  // namespace longterm_mapper2d
