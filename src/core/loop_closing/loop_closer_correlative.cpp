// The loop closer's correlative search: where the graph's guess of an old map is too uncertain
// for the map-to-map alignment's basin, a branch-and-bound search over the marginal's window
// gives the alignment a start near the right answer.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "longterm_mapper2d/core/common/parallel_for.h"
#include "longterm_mapper2d/core/loop_closing/loop_closer.h"
#include "longterm_mapper2d/core/registration/correlative_matcher.h"

namespace longterm_mapper2d {

std::optional<LoopCloser::CorrelativeRequest> LoopCloser::CorrelativeWindow(
    const Marginal& marginal, const Pose2& guess) const {
  // The largest axis of the offset's covariance: the window is square, in the new node's frame.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(marginal.offset_covariance);
  const double sigma_m = std::sqrt(std::max(eigen.eigenvalues().maxCoeff(), 0.0));
  const double sigma_rad = std::sqrt(std::max(marginal.heading_variance, 0.0));
  const double k = options_.correlative_window_sigmas;
  if (!std::isfinite(sigma_m) || !std::isfinite(sigma_rad) ||
      k * sigma_m <= options_.correlative_min_window_m) {
    return std::nullopt;
  }
  CorrelativeRequest request;
  request.guess = guess;
  request.window_m = std::min(k * sigma_m, options_.correlative_max_window_m);
  request.window_rad = std::clamp(k * sigma_rad, options_.correlative_min_window_rad,
                                  options_.correlative_max_window_rad);
  return request;
}

std::vector<LoopCloser::Attempt> LoopCloser::AlignCorrelative(
    const Cloud& reference, const std::vector<CorrelativeRequest>& requests,
    MapperStats& stats) const {
  std::vector<Attempt> attempts(requests.size());
  if (requests.empty()) return attempts;
  ScopedStageTimer timer(stats.stage_times, "loop_closing_correlative");
  CorrelativeMatcherOptions options;
  options.resolution_m = options_.correlative_resolution_m;
  // One cell is also the kernel's sigma: the grid cannot represent a narrower peak, and a wider
  // one blurs the walls the search has to tell apart.
  options.kernel_sigma_m = options_.correlative_resolution_m;
  options.min_score = options_.correlative_min_score;
  // One likelihood grid of the new map serves every old map.
  const CorrelativeMatcher matcher(reference, options);
  std::vector<char> matched(requests.size(), 0);
  ParallelFor(requests.size(), options_.alignment_threads, [&](std::size_t i) {
    const CorrelativeRequest& request = requests[i];
    const auto match =
        matcher.Match(*request.current, request.guess, request.window_m, request.window_rad);
    if (!match) return;
    matched[i] = 1;
    attempts[i] = AlignFrom(reference, *request.current, match->reference_T_current);
  });
  stats.counters["loop_closure_correlative_searches"] += requests.size();
  stats.counters["loop_closure_correlative_matches"] +=
      static_cast<std::uint64_t>(std::count(matched.begin(), matched.end(), 1));
  return attempts;
}

std::vector<bool> LoopCloser::SearchCorrelative(
    const Cloud& reference, const std::vector<GraphNodeId>& olds,
    const std::vector<Pose2>& graph_guesses, const std::map<GraphNodeId, Marginal>& marginals,
    const CloudOf& cloud_of, std::vector<Outcome>& outcomes, MapperStats& stats) const {
  std::vector<bool> correlative(olds.size(), false);
  std::vector<std::size_t> searching;
  std::vector<CorrelativeRequest> requests;
  for (std::size_t k = 0; k < olds.size(); ++k) {
    // Only the maps no guess aligned, for a reason other than degenerate geometry (a search
    // cannot pin a corridor either), and that the Mahalanobis gate gave a window.
    const auto marginal = marginals.find(olds[k]);
    if (outcomes[k].pose || outcomes[k].degenerate || marginal == marginals.end()) continue;
    auto request = CorrelativeWindow(marginal->second, graph_guesses[k]);
    if (!request) continue;
    request->current = &cloud_of(olds[k]);
    searching.push_back(k);
    requests.push_back(*request);
  }
  const std::vector<Attempt> attempts = AlignCorrelative(reference, requests, stats);
  for (std::size_t i = 0; i < searching.size(); ++i) {
    Outcome& outcome = outcomes[searching[i]];
    outcome.degenerate |= attempts[i].degenerate;
    outcome.pose = attempts[i].pose;
    correlative[searching[i]] = attempts[i].pose.has_value();
  }
  return correlative;
}

}  // namespace longterm_mapper2d
