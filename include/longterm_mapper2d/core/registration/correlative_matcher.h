#pragma once

#include <optional>
#include <vector>

#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

struct CorrelativeMatcherOptions {
  // Width of a cell of the finest likelihood grid, and the translation step of the search.
  double resolution_m = 0.05;
  // Likelihood of a point at distance d from the nearest reference point: exp(-d^2 / (2 sigma^2)),
  // cut to 0 beyond 3 sigma.
  double kernel_sigma_m = 0.05;
  // Max-pooled grids of the branch and bound: level k pools 2^k x 2^k fine cells. 1..10.
  int levels = 6;
  // The current cloud is thinned (voxel grid, deterministic) to at most this many points.
  int max_points = 400;
  // Mean likelihood (0..1) below which Match returns nothing.
  double min_score = 0.5;
};

struct CorrelativeMatch {
  Pose2 reference_T_current;
  double score = 0.0;  // mean likelihood of the thinned current points, 0..1
};

// The discrete poses that Match searches, for a given current cloud and window:
//   reference_T_current = Pose2(ix * resolution_m, iy * resolution_m, 0) * guess *
//                         Pose2(0, 0, ia * angular_step_rad)
// for |ix|, |iy| <= linear_steps and |ia| <= angular_steps. Rotations are about the current
// frame's origin; translations are in the reference frame.
struct CorrelativeSearchGrid {
  double resolution_m = 0.0;
  int linear_steps = 0;
  double angular_step_rad = 0.0;
  int angular_steps = 0;
};

// Branch-and-bound correlative scan matcher (after Olson's multi-resolution correlative matching
// and Cartographer's fast correlative scan matcher): the pose of a current cloud within a window
// around a guess that maximises the mean likelihood of its points in a grid built from the
// reference. Exhaustive over a discrete search grid, so it finds the alignment from guesses
// metres and tens of degrees off, where NICP's local search fails; its answer is only as fine as
// one cell and one angular step, so NICP refines it afterwards.
//
// The answer equals that of a brute-force evaluation of Score over SearchGrid's poses (among
// equal scores, the first in the search order). Deterministic; the const methods keep no state
// between calls, so they may run concurrently.
class CorrelativeMatcher {
 public:
  // Builds the likelihood grid and its max-pooled levels from the reference cloud's points (all
  // finite points, with or without normals). Throws std::invalid_argument on bad options. A
  // reference spanning more than ~4 million fine cells gets coarser cells (see resolution_m()).
  CorrelativeMatcher(const Cloud& reference, const CorrelativeMatcherOptions& options);

  // Best pose of `current` in the reference frame within +-linear_window_m (x and y, reference
  // frame) and +-angular_window_rad of `guess` (reference_T_current); nullopt when the best score
  // is below min_score or either cloud is empty. Throws std::invalid_argument on a negative or
  // non-finite window.
  std::optional<CorrelativeMatch> Match(const Cloud& current, const Pose2& guess,
                                        double linear_window_m, double angular_window_rad) const;

  // Mean likelihood (0..1) of the thinned current points at one pose, on the finest grid; 0 for an
  // empty cloud. Match's score of a pose is this.
  double Score(const Cloud& current, const Pose2& reference_T_current) const;

  // The discretisation Match uses for this cloud and window. The angular step makes the current
  // point farthest from its origin (range r) move about one cell per step:
  // acos(1 - resolution^2 / (2 r^2)), shrunk so that a whole number of steps spans the window.
  CorrelativeSearchGrid SearchGrid(const Cloud& current, double linear_window_m,
                                   double angular_window_rad) const;

  // The fine cell width in use (options.resolution_m unless the reference was too large).
  double resolution_m() const { return resolution_m_; }
  const CorrelativeMatcherOptions& options() const { return options_; }

 private:
  // Cell indices of points at one rotation (fine grid, before any translation offset).
  struct Cells {
    std::vector<int> x, y;
  };
  Cells Discretise(const std::vector<Eigen::Vector2d>& points_reference) const;
  // Sum over the points of level `level` at the cells shifted by (dx, dy) fine cells.
  float SumAt(int level, const Cells& cells, int dx, int dy) const;

  CorrelativeMatcherOptions options_;
  double resolution_m_ = 0.05;
  // Fine cell (i, j) covers [origin + i * resolution, origin + (i + 1) * resolution) per axis.
  // Grids are stored with `pad_` extra cells below index 0 on both axes (pooled levels reach
  // there), row-major, width_ x height_ including the padding.
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  int pad_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<std::vector<float>> levels_;  // levels_[k]: max over 2^k x 2^k fine cells
};

}  // namespace longterm_mapper2d
