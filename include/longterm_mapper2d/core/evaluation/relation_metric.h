#pragma once

#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/io/relations_reader.h"

namespace longterm_mapper2d {

// How trajectory poses are looked up at the relation stamps.
struct RelationMetricOptions {
  // A trajectory stamp this close to the relation stamp is used as is.
  double exact_match_s = 1e-6;
  // Otherwise the pose is interpolated between the two bracketing trajectory poses, provided
  // both lie within this distance of the relation stamp; else the relation is unmatched.
  double max_dt_s = 0.1;

  template <class V>
  void Visit(V& v) {
    v("exact_match_s", exact_match_s);
    v("max_dt_s", max_dt_s);
  }
  void Validate(OptionErrors& e) const {
    e.Require(exact_match_s >= 0.0, "exact_match_s", "must be non-negative");
    e.Require(max_dt_s >= exact_match_s, "max_dt_s", "must be at least exact_match_s");
  }
};

// Mean and (population) standard deviation of a sample; both 0 for an empty sample.
struct MeanStd {
  double mean = 0.0;
  double std = 0.0;
};
MeanStd ComputeMeanStd(const std::vector<double>& values);

// The error of one relation; the errors are only meaningful when `matched`.
struct RelationError {
  double t1_s = 0.0;
  double t2_s = 0.0;
  bool matched = false;
  double trans_m = 0.0;
  double rot_deg = 0.0;
};

// The Kümmerle et al. (2009) metric of a trajectory, translational and rotational parts reported
// separately, over the matched relations only.
struct RelationMetricResult {
  int matched = 0;
  int total = 0;
  std::vector<RelationError> errors;  // one per input relation, in input order
  MeanStd trans_abs_m;
  MeanStd trans_sq_m2;
  double trans_max_m = 0.0;
  MeanStd rot_abs_deg;
  MeanStd rot_sq_deg2;
  double rot_max_deg = 0.0;
};

// The base pose at `stamp_s` from a trajectory sorted by stamp: an exact stamp match, else the
// interpolation of the bracketing poses if both are within options.max_dt_s; else an error.
StatusOr<Pose2> PoseAtStamp(const std::vector<StampedPose2>& sorted_trajectory, double stamp_s,
                            const RelationMetricOptions& options);

// Evaluates `trajectory` (map_T_base per stamp, any order) against `relations`.
//   estimated relation  delta    = pose(t1)^-1 * pose(t2)
//   error               epsilon  = relation.t1_T_t2^-1 * delta
//   translational error = ||trans(epsilon)|| [m], rotational = |wrap(theta(epsilon))| [deg].
// Errors only on invalid options or a non-finite trajectory pose or stamp.
StatusOr<RelationMetricResult> EvaluateRelations(const std::vector<StampedPose2>& trajectory,
                                                 const std::vector<Relation>& relations,
                                                 const RelationMetricOptions& options = {});

}  // namespace longterm_mapper2d
