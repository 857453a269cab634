#include <algorithm>
#include <limits>
#include <optional>
#include <set>
#include <utility>

#include "longterm_mapper2d/core/graph/optimizer.h"
#include "longterm_mapper2d/core/loop_closing/loop_closer.h"

namespace longterm_mapper2d {

// One vote among the buffered candidates of one group (`on_chain`; nullopt: all of them). The
// winning hypothesis' agreeing candidates become edges, its clear outliers are dropped, the rest
// of the group and the other group's candidates wait.
void LoopCloser::VoteWithin(const PoseGraph& graph, std::optional<bool> on_chain,
                            std::vector<GraphEdge>& accepted, MapperStats& stats) {
  auto in_group = [&](const ClosureCandidate& c) { return !on_chain || c.on_chain == *on_chain; };
  const Eigen::Matrix3d information = ClosureInformation();
  // The local sub-map L moves rigidly so that hypothesis h holds exactly; every candidate is
  // scored at the moved poses.
  auto moved = [&](GraphNodeId id, const Pose2& motion) {
    const Pose2& pose = graph.node(id).pose;
    return ages_.count(id) ? motion * pose : pose;
  };
  // Both nodes of the candidate wait: a hypothesis moves it as a whole.
  auto moves_whole_candidate = [&](const ClosureCandidate& c) { return ages_.count(c.old) > 0; };
  constexpr double kNotScored = std::numeric_limits<double>::infinity();
  int best = -1, best_rank = 0, best_support = 0, best_inliers = 0;
  double best_chi2 = 0.0;
  std::vector<double> best_scores, best_plain_scores;
  for (std::size_t h = 0; h < buffer_.size(); ++h) {
    const ClosureCandidate& hyp = buffer_[h];
    if (!in_group(hyp)) continue;
    const Pose2 local_target = graph.node(hyp.old).pose * hyp.local_T_old.inverse();
    const Pose2 motion = local_target * graph.node(hyp.local).pose.inverse();
    int inliers = 0;
    double chi2_sum = 0.0;
    std::vector<double> scores(buffer_.size(), kNotScored), plain_scores(buffer_.size(), 0.0);
    std::set<GraphNodeId> inlier_locals, inlier_olds;
    for (std::size_t i = 0; i < buffer_.size(); ++i) {
      const ClosureCandidate& c = buffer_[i];
      if (!in_group(c)) continue;
      const Eigen::Vector3d e =
          EdgeError(moved(c.local, motion), moved(c.old, motion), c.local_T_old);
      // The sub-map moves rigidly, but its chain has drifted between the two candidates' nodes
      // (and the old map may have between theirs): the closure's covariance grows by the drift
      // over that distance, so agreeing candidates a corridor apart still agree.
      const double d =
          (graph.node(c.local).pose.translation() - graph.node(hyp.local).pose.translation())
              .norm() +
          (graph.node(c.old).pose.translation() - graph.node(hyp.old).pose.translation()).norm();
      // The final sweep votes on the optimised graph: no drift left to allow for.
      const double s_xy = hyp.from_sweep ? 0.0 : options_.vote_drift_per_m * d;
      const double s_th = hyp.from_sweep ? 0.0 : options_.vote_drift_rad_per_m * d;
      const Eigen::Vector3d drift_variance(s_xy * s_xy, s_xy * s_xy, s_th * s_th);
      const Eigen::Vector3d drifted_information =
          (information.diagonal().cwiseInverse() + drift_variance).cwiseInverse();
      scores[i] = e.dot(drifted_information.asDiagonal() * e);
      plain_scores[i] = e.dot(information * e);
      // A candidate whose old node waits too moves with the sub-map on both ends: it agrees
      // with a return that moves the sub-map exactly as well as with the graph, so it is no
      // evidence for one (it is still accepted with it). Counted as support, in a simulated
      // patrol with a 180 deg laser a right closure between two recent nodes (their chain broken
      // by a merge) made the second distinct node behind a wrong return 5 m along a corridor
      // and 90 deg turned, and the map broke (14 m RMSE).
      const bool evidence = moves_whole_candidate(hyp) || !moves_whole_candidate(c);
      if (scores[i] < options_.vote_inlier_chi2 && evidence) {
        ++inliers;
        chi2_sum += scores[i];
        inlier_locals.insert(c.local);
        inlier_olds.insert(c.old);
      }
    }
    // Candidates that share a node are not independent: two new nodes aligned to the same old
    // local map agree with each other even when that map is a look-alike room elsewhere.
    // The support of a hypothesis is the number of distinct nodes on its weaker side.
    const int support = options_.vote_distinct_nodes
                            ? static_cast<int>(std::min(inlier_locals.size(), inlier_olds.size()))
                            : inliers;
    int rank = support;
    if (options_.vote_graph_supports) {
      const Eigen::Vector3d e =
          EdgeError(graph.node(hyp.local).pose, graph.node(hyp.old).pose, hyp.local_T_old);
      if (e.dot(information * e) < options_.vote_inlier_chi2) ++rank;
    }
    if (rank > best_rank ||
        (rank == best_rank &&
         (inliers > best_inliers || (inliers == best_inliers && chi2_sum < best_chi2)))) {
      best = static_cast<int>(h);
      best_rank = rank;
      best_support = support;
      best_inliers = inliers;
      best_chi2 = chi2_sum;
      best_scores = std::move(scores);
      best_plain_scores = std::move(plain_scores);
    }
  }
  if (best < 0 || best_support < options_.vote_min_inliers) return;
  std::vector<ClosureCandidate> kept;
  for (std::size_t i = 0; i < buffer_.size(); ++i) {
    const ClosureCandidate& c = buffer_[i];
    if (!in_group(c)) {
      kept.push_back(c);  // the other group's vote decides it
    } else if (best_scores[i] < options_.vote_inlier_chi2) {
      const auto pair = std::make_pair(std::min(c.local, c.old), std::max(c.local, c.old));
      if (accepted_pairs_.insert(pair).second) {
        GraphEdge edge;
        edge.from = c.local;
        edge.to = c.old;
        edge.measurement = c.local_T_old;
        edge.information = information;
        edge.kind = EdgeKind::kLoopClosure;
        edge.stamp_s = graph.node(c.local).stamp_s;
        edge.session_id = graph.node(c.local).session_id;
        accepted.push_back(edge);
      }
    } else if (best_plain_scores[i] < options_.vote_outlier_chi2) {
      kept.push_back(c);  // undecided: waits for more votes
    } else {
      ++stats.counters["loop_closures_rejected"];
    }
  }
  buffer_ = std::move(kept);
}

// The hypothesise-and-verify vote of LoopCloser (ALGORITHMS.md §8), apart from the search and
// alignment of candidates in loop_closer.cpp.
std::vector<GraphEdge> LoopCloser::Vote(const PoseGraph& graph, bool force, MapperStats& stats) {
  std::vector<GraphEdge> accepted;
  // Drop candidates whose nodes are gone.
  buffer_.erase(std::remove_if(buffer_.begin(), buffer_.end(),
                               [&](const ClosureCandidate& c) {
                                 return !graph.HasNode(c.local) || !graph.HasNode(c.old);
                               }),
                buffer_.end());
  bool due = force;
  for (const auto& [id, age] : ages_) due |= age >= options_.vote_window - 1;
  if (due && !buffer_.empty()) {
    ScopedStageTimer timer(stats.stage_times, "loop_closing_vote");
    if (options_.vote_chain_apart) {
      VoteWithin(graph, /*on_chain=*/false, accepted, stats);
      VoteWithin(graph, /*on_chain=*/true, accepted, stats);
    } else {
      VoteWithin(graph, std::nullopt, accepted, stats);
    }
  }
  // Age the buffer; expired nodes take their candidates with them.
  for (auto& [id, age] : ages_) ++age;
  for (auto it = ages_.begin(); it != ages_.end();) {
    if (it->second >= options_.vote_window || force) {
      const GraphNodeId id = it->first;
      const auto before = buffer_.size();
      buffer_.erase(std::remove_if(buffer_.begin(), buffer_.end(),
                                   [id](const ClosureCandidate& c) { return c.local == id; }),
                    buffer_.end());
      stats.counters["loop_closures_expired"] += before - buffer_.size();
      it = ages_.erase(it);
    } else {
      ++it;
    }
  }
  stats.counters["loop_closures_accepted"] += accepted.size();
  return accepted;
}

}  // namespace longterm_mapper2d
