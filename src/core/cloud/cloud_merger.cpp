#include "longterm_mapper2d/core/cloud/cloud_merger.h"

#include <cmath>
#include <optional>

#include "longterm_mapper2d/core/geometry/fast_atan2.h"

namespace longterm_mapper2d {
namespace {

void Compact(Cloud& cloud, const std::vector<char>& remove) {
  std::size_t out = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!remove[i]) cloud[out++] = cloud[i];
  }
  cloud.resize(out);
}

// How far beam `beam` of `scan` proves space free: nothing if the reading observes nothing (NaN,
// below range_min); a no-return beam up to `free_space_max_range_m`; a return at or past
// `returns_from_m` up to the return; a nearer return 0 (it became a point: the point rules
// decide).
std::optional<double> FreeUntil(const LaserScan& scan, int beam, double returns_from_m,
                                double free_space_max_range_m) {
  const float r = scan.ranges[beam];
  if (std::isnan(r) || (std::isfinite(r) && r < scan.range_min_m)) return std::nullopt;
  if (!std::isfinite(r) || r >= scan.range_max_m) return free_space_max_range_m;
  return r >= returns_from_m ? static_cast<double>(r) : 0.0;
}

// The scan's own beams as the projector's bins (bin i is beam i), down to the sensor.
ProjectorGeometry BeamsOf(const LaserScan& scan) {
  ProjectorGeometry geometry = ProjectorGeometry::FromScan(scan, 1e9);
  geometry.min_range_m = 0.0;
  return geometry;
}

}  // namespace

RichPoint Fuse(const RichPoint& a, const RichPoint& b, double max_weight) {
  RichPoint out;
  const double weight = a.weight + b.weight;
  out.point_m = (a.weight * a.point_m + b.weight * b.point_m) / weight;
  const Eigen::Vector2d normal = a.weight * a.normal + b.weight * b.normal;
  const double norm = normal.norm();
  out.normal = norm > 1e-9 ? Eigen::Vector2d(normal / norm) : Eigen::Vector2d::Zero();
  out.weight = std::min(weight, max_weight);
  out.observations = std::min(a.observations + b.observations, kMaxObservations);
  // Seen again from this node's own viewpoints: its own point, if placed partly by the merge.
  out.inherited = a.inherited && b.inherited;
  return out;
}

MergeStats CloudMerger::Merge(Cloud& map, const Cloud& scan_points,
                              const std::vector<int>& scan_beams, const LaserScan& scan,
                              const Pose2& frame_T_laser, double max_point_range_m) {
  MergeStats stats;
  // The map is seen through the scan's own beams: bin i is beam i.
  const ProjectorGeometry geometry = BeamsOf(scan);
  const Pose2 laser_T_frame = frame_T_laser.inverse();
  ProjectCloud(geometry, laser_T_frame, map, &image_);
  src_of_beam_.assign(scan.ranges.size(), -1);
  for (std::size_t i = 0; i < scan_points.size(); ++i)
    src_of_beam_[scan_beams[i]] = static_cast<int>(i);

  const double tau = options_.merge_distance_m;
  const double cos_angle = std::cos(options_.merge_normal_angle_rad);
  const std::size_t old_size = map.size();
  remove_.assign(old_size, 0);
  for (int beam = 0; beam < geometry.num_bins; ++beam) {
    const int old_index = image_.nearest[beam];
    const double r_old = image_.ranges_m[beam];
    const int src = src_of_beam_[beam];
    if (src >= 0) {
      const RichPoint& p = scan_points[src];
      const double r_new = scan.ranges[beam];
      if (old_index < 0 || r_old - r_new > tau ||
          (!options_.free_space_reasoning && r_old - r_new < -tau)) {
        map.push_back(p);
        // In front of a known surface: space an earlier beam crossed, now occupied. Something
        // moved in (or an occlusion edge); not a registration target until seen in place again.
        if (old_index >= 0 && r_old - r_new > tau) map.back().observations = 0;
        ++stats.added;
      } else if (r_old - r_new < -tau) {
        remove_[old_index] = 1;
        map.push_back(p);
        map.back().observations = 0;  // what was there moved away (or was seen past)
        ++stats.replaced;
      } else {
        RichPoint& old = map[old_index];
        const bool compatible =
            !old.has_normal() || !p.has_normal() || old.normal.dot(p.normal) >= cos_angle;
        if (compatible && old.has_normal() == p.has_normal()) {
          // Point-to-line offset of the return from the old surface (point-to-point without
          // normals): a wall seen again from elsewhere stays on its line, a person walking along
          // the beam does not.
          const Eigen::Vector2d offset = p.point_m - old.point_m;
          const double moved_m =
              old.has_normal() ? std::abs(old.normal.dot(offset)) : offset.norm();
          const double static_m =
              options_.static_distance_m + options_.static_distance_per_m * r_new;
          // A return already known to move (observations 0, see MotionFilter) resets too.
          const int observations =
              moved_m <= static_m && p.observations > 0 ? old.observations + 1 : 0;
          old = Fuse(old, p, options_.max_weight);
          old.observations = observations;
          ++stats.fused;
        } else if (!old.has_normal() && p.has_normal()) {
          old = p;
          ++stats.replaced;
        }
      }
      continue;
    }
    if (old_index < 0 || !options_.free_space_reasoning) continue;
    // No new point in this bin: what did the beam see? (A return too far to keep as a point
    // still proves the space before it free.)
    const auto free_until =
        FreeUntil(scan, beam, max_point_range_m, options_.free_space_max_range_m);
    if (free_until && r_old + tau < *free_until) {
      remove_[old_index] = 1;
      ++stats.erased;
    }
  }
  remove_.resize(map.size(), 0);
  Compact(map, remove_);
  if (options_.radial_merge) stats.thinned = RadialMerge(map, geometry, laser_T_frame);
  return stats;
}

int CloudMerger::EraseSeenThrough(Cloud& map, const LaserScan& scan, const Pose2& frame_T_laser,
                                  int max_observations) {
  const ProjectorGeometry geometry = BeamsOf(scan);
  ProjectCloud(geometry, frame_T_laser.inverse(), map, &image_);
  remove_.assign(map.size(), 0);
  int erased = 0;
  for (int beam = 0; beam < geometry.num_bins; ++beam) {
    const int old_index = image_.nearest[beam];
    if (old_index < 0 || map[old_index].observations > max_observations) continue;
    // Every return counts here: the snapshot takes no new points.
    const auto free_until = FreeUntil(scan, beam, 0.0, options_.free_space_max_range_m);
    if (free_until && image_.ranges_m[beam] + options_.merge_distance_m < *free_until) {
      remove_[old_index] = 1;
      ++erased;
    }
  }
  Compact(map, remove_);
  return erased;
}

int CloudMerger::RadialMerge(Cloud& map, const ProjectorGeometry& geometry,
                             const Pose2& laser_T_frame) {
  ProjectCloud(geometry, laser_T_frame, map, &image_);
  remove_.assign(map.size(), 0);
  const Eigen::Matrix2d R = laser_T_frame.rotation();
  const Eigen::Vector2d t = laser_T_frame.translation();
  const double cos_angle = std::cos(options_.merge_normal_angle_rad);
  int thinned = 0;
  for (int i = 0; i < static_cast<int>(map.size()); ++i) {
    const Eigen::Vector2d q = R * map[i].point_m + t;
    const int bin = geometry.BinOf(FastAtan2(q.y(), q.x()));
    if (bin < 0) continue;
    const int winner = image_.indices[bin];
    if (winner < 0 || winner == i || remove_[winner]) continue;
    if (std::abs(q.norm() - image_.ranges_m[bin]) > options_.merge_distance_m) continue;
    RichPoint& w = map[winner];
    if (w.has_normal() && map[i].has_normal() && w.normal.dot(map[i].normal) < cos_angle) continue;
    w = Fuse(w, map[i], options_.max_weight);
    remove_[i] = 1;
    ++thinned;
  }
  Compact(map, remove_);
  return thinned;
}

void CloudMerger::Clip(Cloud& map, const Eigen::Vector2d& centre, double range_m) {
  const double range_sq = range_m * range_m;
  std::size_t out = 0;
  for (std::size_t i = 0; i < map.size(); ++i) {
    if ((map[i].point_m - centre).squaredNorm() <= range_sq) map[out++] = map[i];
  }
  map.resize(out);
}

}  // namespace longterm_mapper2d
