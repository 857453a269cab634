// The only file of the project that includes Ceres.
#include "longterm_mapper2d/core/graph/optimizer.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <chrono>
#include <cmath>
#include <set>

namespace longterm_mapper2d {
namespace {

// The relative-pose residual r = S e with S' S = Omega (S = L' for Omega = L L'), with analytic
// Jacobians. For e as in EdgeError and d = t_j - t_i:
//   de_t/dt_i = -R_Z' R_i',  de_t/dtheta_i = R_Z' dR_i'/dtheta d,  de_t/dt_j = R_Z' R_i',
//   de_theta/dtheta_i = -1,  de_theta/dtheta_j = 1,
// where dR'/dtheta = [[-s, c], [-c, -s]].
class RelativePoseCost : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  RelativePoseCost(const Pose2& measurement, const Eigen::Matrix3d& sqrt_information)
      : measurement_(measurement), sqrt_information_(sqrt_information) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* a = parameters[0];
    const double* b = parameters[1];
    const double ci = std::cos(a[2]), si = std::sin(a[2]);
    const double cz = std::cos(measurement_.theta()), sz = std::sin(measurement_.theta());
    Eigen::Matrix2d Ri_t, Rz_t, dRi_t;
    Ri_t << ci, si, -si, ci;
    Rz_t << cz, sz, -sz, cz;
    dRi_t << -si, ci, -ci, -si;
    const Eigen::Vector2d d(b[0] - a[0], b[1] - a[1]);
    Eigen::Vector3d e;
    e.head<2>() = Rz_t * (Ri_t * d - measurement_.translation());
    e[2] = NormalizeAngle(b[2] - a[2] - measurement_.theta());
    Eigen::Map<Eigen::Vector3d> r(residuals);
    r = sqrt_information_ * e;
    if (jacobians) {
      if (jacobians[0]) {
        Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
        j.topLeftCorner<2, 2>() = -Rz_t * Ri_t;
        j.block<2, 1>(0, 2) = Rz_t * dRi_t * d;
        j(2, 2) = -1.0;
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> out(jacobians[0]);
        out = sqrt_information_ * j;
      }
      if (jacobians[1]) {
        Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
        j.topLeftCorner<2, 2>() = Rz_t * Ri_t;
        j(2, 2) = 1.0;
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> out(jacobians[1]);
        out = sqrt_information_ * j;
      }
    }
    return true;
  }

 private:
  Pose2 measurement_;
  Eigen::Matrix3d sqrt_information_;
};

// S with S' S = Omega, or nullopt if Omega is not positive definite.
std::optional<Eigen::Matrix3d> SqrtInformation(const Eigen::Matrix3d& information) {
  const Eigen::Matrix3d symmetric = 0.5 * (information + information.transpose());
  const Eigen::LLT<Eigen::Matrix3d> llt(symmetric);
  if (llt.info() != Eigen::Success) return std::nullopt;
  return Eigen::Matrix3d(llt.matrixL().transpose());
}

struct Problem {
  std::map<GraphNodeId, Eigen::Vector3d> parameters;
  std::unique_ptr<ceres::Problem> problem;
  int skipped_edges = 0;
};

// Builds the Ceres problem over the chosen edges; the gauge block is constant.
Problem Build(const PoseGraph& graph, const std::vector<std::size_t>& edge_indices,
              GraphNodeId gauge, double loss_scale,
              EdgeInformation information = EdgeInformation::kOptimiser) {
  Problem p;
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  p.problem = std::make_unique<ceres::Problem>(options);
  for (std::size_t index : edge_indices) {
    const GraphEdge& edge = graph.edges()[index];
    const bool gating = information == EdgeInformation::kGating && edge.gating_information;
    const auto sqrt_information =
        SqrtInformation(gating ? *edge.gating_information : edge.information);
    if (!sqrt_information) {
      ++p.skipped_edges;
      continue;
    }
    for (GraphNodeId id : {edge.from, edge.to}) {
      if (!p.parameters.count(id)) p.parameters[id] = graph.node(id).pose.vector();
    }
    ceres::LossFunction* loss = nullptr;
    if (edge.kind == EdgeKind::kLoopClosure && loss_scale > 0.0) {
      loss = new ceres::CauchyLoss(loss_scale);
    }
    p.problem->AddResidualBlock(new RelativePoseCost(edge.measurement, *sqrt_information), loss,
                                p.parameters[edge.from].data(), p.parameters[edge.to].data());
  }
  if (p.parameters.count(gauge)) p.problem->SetParameterBlockConstant(p.parameters[gauge].data());
  return p;
}

std::vector<std::size_t> AllEdges(const PoseGraph& graph) {
  std::vector<std::size_t> all(graph.edges().size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  return all;
}

}  // namespace

Eigen::Vector3d EdgeError(const Pose2& from, const Pose2& to, const Pose2& measurement) {
  return measurement.Between(from.Between(to)).vector();
}

void EvaluateRelativePoseResidual(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                  const Pose2& measurement, const Eigen::Matrix3d& sqrt_information,
                                  Eigen::Vector3d* residual, Eigen::Matrix3d* jacobian_from,
                                  Eigen::Matrix3d* jacobian_to) {
  const RelativePoseCost cost(measurement, sqrt_information);
  const double* parameters[2] = {from.data(), to.data()};
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> j_from, j_to;
  double* jacobians[2] = {j_from.data(), j_to.data()};
  cost.Evaluate(parameters, residual->data(), jacobians);
  if (jacobian_from) *jacobian_from = j_from;
  if (jacobian_to) *jacobian_to = j_to;
}

double EdgeChi2(const PoseGraph& graph, const GraphEdge& edge) {
  const Eigen::Vector3d e =
      EdgeError(graph.node(edge.from).pose, graph.node(edge.to).pose, edge.measurement);
  return e.dot(edge.information * e);
}

double TotalChi2(const PoseGraph& graph) {
  double chi2 = 0.0;
  for (const GraphEdge& edge : graph.edges()) chi2 += EdgeChi2(graph, edge);
  return chi2;
}

OptimizationSummary Optimize(PoseGraph& graph, const OptimizerOptions& options,
                             const std::optional<std::vector<std::size_t>>& edges,
                             std::optional<GraphNodeId> gauge) {
  OptimizationSummary summary;
  const auto start = std::chrono::steady_clock::now();
  summary.initial_chi2 = TotalChi2(graph);
  const std::optional<GraphNodeId> fixed = gauge ? gauge : graph.gauge();
  if (!fixed || !graph.HasNode(*fixed)) {
    summary.message = "no gauge node";
    summary.final_chi2 = summary.initial_chi2;
    return summary;
  }
  Problem p = Build(graph, edges ? *edges : AllEdges(graph), *fixed,
                    options.loop_closure_loss_scale);
  if (p.parameters.empty()) {
    summary.usable = true;
    summary.final_chi2 = summary.initial_chi2;
    summary.message = "no edges";
    return summary;
  }
  ceres::Solver::Options solver;
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.num_threads = options.threads;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver, p.problem.get(), &ceres_summary);
  summary.iterations = static_cast<int>(ceres_summary.iterations.size()) - 1;
  summary.usable = ceres_summary.IsSolutionUsable();
  summary.message = ceres_summary.BriefReport();
  if (p.skipped_edges > 0) {
    summary.message += "; " + std::to_string(p.skipped_edges) +
                       " edges skipped (information not positive definite)";
  }
  bool finite = true;
  for (const auto& [id, x] : p.parameters) finite &= x.allFinite();
  if (summary.usable && finite) {
    for (const auto& [id, x] : p.parameters) graph.mutable_node(id).pose = Pose2::FromVector(x);
  } else {
    summary.usable = false;
  }
  summary.final_chi2 = TotalChi2(graph);
  summary.time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

StatusOr<std::map<GraphNodeId, Eigen::Matrix3d>> ComputeMarginals(
    const PoseGraph& graph, GraphNodeId gauge, const std::vector<GraphNodeId>& nodes,
    const std::optional<std::vector<std::size_t>>& edges, EdgeInformation information) {
  if (!graph.HasNode(gauge)) return Status::Error("gauge node " + std::to_string(gauge) + " is missing");
  // No robust loss: the covariance is that of the Gaussian model at the estimate.
  Problem p = Build(graph, edges ? *edges : AllEdges(graph), gauge, 0.0, information);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (GraphNodeId id : nodes) {
    if (id == gauge) continue;
    if (!p.parameters.count(id)) {
      return Status::Error("node " + std::to_string(id) + " has no edge in the system");
    }
    blocks.emplace_back(p.parameters[id].data(), p.parameters[id].data());
  }
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::SPARSE_QR;
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  ceres::Covariance covariance(options);
  if (!blocks.empty() && !covariance.Compute(blocks, p.problem.get())) {
    return Status::Error("marginal covariance failed: the system is rank deficient (a node is "
                         "not constrained relative to the gauge)");
  }
  std::map<GraphNodeId, Eigen::Matrix3d> out;
  for (GraphNodeId id : nodes) {
    if (id == gauge) {
      out[id] = Eigen::Matrix3d::Zero();
      continue;
    }
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> block;
    if (!covariance.GetCovarianceBlock(p.parameters[id].data(), p.parameters[id].data(),
                                       block.data())) {
      return Status::Error("marginal covariance of node " + std::to_string(id) + " unavailable");
    }
    if (!block.allFinite()) return Status::Error("marginal covariance is not finite");
    out[id] = block;
  }
  return out;
}

}  // namespace longterm_mapper2d
