#pragma once

#include <Eigen/Core>
#include <vector>

#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

// Observation counts saturate here (weeks of merges sum them).
inline constexpr int kMaxObservations = 1 << 20;

// A 2D point with a unit normal and an accumulated weight (the "extended point" of NICP).
// A point built from a beam of range r starts with weight 1/r, so far points count less in every
// weighted fusion. A point whose neighbourhood gave no reliable normal has normal = (0, 0).
// `observations` counts the scans that saw the surface at the same place; the merger sets it to 0
// when a return lands off the old surface or appears where a beam had passed (CloudMerger), so
// something that moves between scans stays at 0.
struct RichPoint {
  Eigen::Vector2d point_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  double weight = 1.0;
  int observations = 1;
  // Came with a local map merged into this one and not observed again from this node's own
  // viewpoints: it stands where the merge's relative pose put it, not where this node's scans
  // saw it (see LoopClosingOptions::align_own_points).
  bool inherited = false;

  bool has_normal() const { return normal.squaredNorm() > 0.5; }
};

using Cloud = std::vector<RichPoint>;

// p <- T p, n <- R n; weights are unchanged.
inline RichPoint Transform(const Pose2& a_T_b, const RichPoint& point_b) {
  RichPoint out = point_b;
  out.point_m = a_T_b * point_b.point_m;
  out.normal = a_T_b.rotation() * point_b.normal;
  return out;
}

inline Cloud Transform(const Pose2& a_T_b, const Cloud& cloud_b) {
  Cloud out;
  out.reserve(cloud_b.size());
  const Eigen::Matrix2d rotation = a_T_b.rotation();
  const Eigen::Vector2d translation = a_T_b.translation();
  for (const RichPoint& p : cloud_b) {
    RichPoint q = p;
    q.point_m = rotation * p.point_m + translation;
    q.normal = rotation * p.normal;
    out.push_back(q);
  }
  return out;
}

}  // namespace longterm_mapper2d
