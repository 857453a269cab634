#pragma once

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"

namespace longterm_mapper2d {

struct OptimizerOptions {
  int max_iterations = 20;
  // Loop closures get a Cauchy loss of this scale (in sqrt(chi2) units), so a wrong closure that
  // slipped through pulls with a bounded force. 0 turns it off.
  double loop_closure_loss_scale = 3.0;
  double function_tolerance = 1e-8;
  int threads = 1;

  template <class V>
  void Visit(V& v) {
    v("max_iterations", max_iterations);
    v("loop_closure_loss_scale", loop_closure_loss_scale);
    v("function_tolerance", function_tolerance);
    v("threads", threads);
  }
  void Validate(OptionErrors& e) const {
    e.Require(max_iterations >= 1, "max_iterations", "must be at least 1");
    e.Require(loop_closure_loss_scale >= 0.0, "loop_closure_loss_scale", "must be non-negative");
    e.Require(function_tolerance > 0.0, "function_tolerance", "must be positive");
    e.Require(threads >= 1, "threads", "must be at least 1");
  }
};

struct OptimizationSummary {
  double initial_chi2 = 0.0;  // sum of e' Omega e over the edges, without robust losses
  double final_chi2 = 0.0;
  int iterations = 0;
  double time_s = 0.0;
  bool usable = false;  // false: the estimate was left unchanged
  std::string message;
};

// The g2o SE(2) edge error for nodes X_i, X_j and measurement Z:
//   e = t2v(Z^-1 (X_i^-1 X_j)) = [R_Z' (R_i' (t_j - t_i) - t_Z) ; wrap(theta_j - theta_i - theta_Z)]
Eigen::Vector3d EdgeError(const Pose2& from, const Pose2& to, const Pose2& measurement);
double EdgeChi2(const PoseGraph& graph, const GraphEdge& edge);
// The residual the optimiser minimises, r = S e with S' S = Omega, and its analytic Jacobians
// (row-major 3x3) with respect to (x, y, theta) of `from` and `to`; exposed for tests.
void EvaluateRelativePoseResidual(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                  const Pose2& measurement, const Eigen::Matrix3d& sqrt_information,
                                  Eigen::Vector3d* residual, Eigen::Matrix3d* jacobian_from,
                                  Eigen::Matrix3d* jacobian_to);
double TotalChi2(const PoseGraph& graph);

// Levenberg-Marquardt on Ceres (SPARSE_NORMAL_CHOLESKY, SuiteSparse), warm-started from the
// current node poses, one 3-vector block per node, the gauge node held constant. If `edges` is
// given, only those edges (indices into graph.edges()) take part and only their nodes move;
// `gauge` overrides the graph's gauge. An unusable solve leaves the poses unchanged.
OptimizationSummary Optimize(PoseGraph& graph, const OptimizerOptions& options,
                             const std::optional<std::vector<std::size_t>>& edges = std::nullopt,
                             std::optional<GraphNodeId> gauge = std::nullopt);

// Which information of each edge a system is built from.
enum class EdgeInformation {
  kOptimiser,  // GraphEdge::information
  kGating,     // GraphEdge::gating_information where an edge has one (the loop closer's gate)
};

// Marginal covariances of `nodes` with `gauge` held fixed, at the current estimate, in the
// additive (x, y, theta) increments of the global frame. Uses the given edges (all by default).
// A rank-deficient system (a node not constrained relative to the gauge) is an error.
StatusOr<std::map<GraphNodeId, Eigen::Matrix3d>> ComputeMarginals(
    const PoseGraph& graph, GraphNodeId gauge, const std::vector<GraphNodeId>& nodes,
    const std::optional<std::vector<std::size_t>>& edges = std::nullopt,
    EdgeInformation information = EdgeInformation::kOptimiser);

}  // namespace longterm_mapper2d
