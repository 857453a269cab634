#pragma once

#include <optional>
#include <vector>

#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

// The written trajectory (Mapper::Trajectory): each scan's pose is taken from its own local map
// (node) through the tracker's chain, and averaged with the poses its neighbours' local maps give
// it through the same chain, over the scans within half_window_s of it. Why: every node carries
// its own error in the graph, and at a node boundary the trajectory jumps by the difference (intel
// 0.59 m and 4.7 deg between two scans 1.4 s apart; aces, scan 0.09 m: 1.1 m in 0.5 s), while the
// tracker's chain over a few seconds is good to millimetres. Over the five robustness runs of each
// log, 8 s took intel 0.040 -> 0.036 m and aces 0.039 -> 0.037 m (README, "Accuracy"). 0: off, the
// pose of each scan's own node only.
struct TrajectorySmoothingOptions {
  double half_window_s = 8.0;

  template <class V>
  void Visit(V& v) {
    v("half_window_s", half_window_s);
  }
  void Validate(OptionErrors& e) const {
    e.Require(half_window_s >= 0.0 && half_window_s <= 600.0, "half_window_s",
              "must be in [0, 600] s (0: off)");
  }
};

// Smooths one stretch of a trajectory whose scans all hang off local maps: `map_T_base[i]` as scan
// i's node puts it, `tracker_T_base[i]` the tracker's pose of it (one continuous chain), stamps
// non-decreasing. Each node's correction C_j = map_T_base[j] * tracker_T_base[j]^-1 is applied to
// scan i for every j within the window; the result's position is the mean of the C_j *
// tracker_T_base[i] positions and its heading the circular mean of their headings. Where all
// corrections agree (one node, or nodes the graph keeps consistent) nothing changes. O(n).
std::vector<Pose2> SmoothAcrossLocalMaps(const std::vector<double>& stamps_s,
                                         const std::vector<Pose2>& map_T_base,
                                         const std::vector<Pose2>& tracker_T_base,
                                         double half_window_s);

// For each i, the mean of C_j * poses[i] over the j within half_window_s of i that have a
// correction C_j (position: the mean; heading: the circular mean), or poses[i] unchanged where no
// j in its window has one. Stamps non-decreasing. O(n).
std::vector<Pose2> AverageCorrections(const std::vector<double>& stamps_s,
                                      const std::vector<std::optional<Pose2>>& corrections,
                                      const std::vector<Pose2>& poses, double half_window_s);

// SmoothAcrossLocalMaps on each stretch of consecutive poses that have `in_stretch` set and
// non-decreasing stamps, in place (`chain`: the tracker's poses, or any locally consistent
// trajectory of the same scans); poses outside every stretch are left as they are.
void SmoothStretches(const std::vector<double>& stamps_s, const std::vector<bool>& in_stretch,
                     const std::vector<Pose2>& chain, double half_window_s,
                     std::vector<Pose2>& map_T_base);

// AverageCorrections on each stretch (as SmoothStretches) of map_T_base, in place: the map-frame
// corrections of some scans (e.g. the trajectory refinement's) spread to the scans around them.
void CorrectStretches(const std::vector<double>& stamps_s, const std::vector<bool>& in_stretch,
                      const std::vector<std::optional<Pose2>>& corrections, double half_window_s,
                      std::vector<Pose2>& map_T_base);

}  // namespace longterm_mapper2d
