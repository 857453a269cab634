#include "longterm_mapper2d/core/loop_closing/loop_closer.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <deque>
#include <set>

#include "longterm_mapper2d/core/common/parallel_for.h"
#include "longterm_mapper2d/core/graph/optimizer.h"

namespace longterm_mapper2d {
namespace {

double Shrink(double value, double by) {
  return value > by ? value - by : (value < -by ? value + by : 0.0);
}

}  // namespace

LoopCloser::LoopCloser(const LoopClosingOptions& options, const RegistrationOptions& registration)
    : options_(options), coarse_(registration), fine_(registration) {
  coarse_.max_correspondence_distance_m = options.coarse_correspondence_m;
  coarse_.max_normal_angle_rad = std::max(registration.max_normal_angle_rad, 0.8);
  coarse_.damping = 0.0;
  fine_.max_correspondence_distance_m = options.fine_correspondence_m;
  fine_.damping = 0.0;
  fine_.inlier_distance_m = options.validation_inlier_m;
  fine_.min_inlier_ratio = options.min_inlier_ratio;
  fine_.min_correspondences = options.min_correspondences;
  fine_.min_correspondence_ratio = 0.0;
}

Eigen::Matrix3d LoopCloser::ClosureInformation() const {
  return Eigen::Vector3d(options_.closure_information_xy, options_.closure_information_xy,
                         options_.closure_information_theta)
      .asDiagonal();
}

std::vector<GraphNodeId> LoopCloser::Candidates(
    const PoseGraph& graph, GraphNodeId node, bool sweep, MapperStats& stats,
    std::map<GraphNodeId, Marginal>* gated_marginals) const {
  const Pose2& pose = graph.node(node).pose;
  // Along the node's own session's odometry edges only: nodes that a closure or a merge joined
  // are still candidates, so a revisited place keeps finding its old local maps and merging them;
  // so are the loaded nodes near a session's start, which the edge of the initial pose would put
  // next to the session's first node (and next to every earlier session's first node, all tied
  // to nodes there: none of them ever merged). The sweep looks only for what is still missing:
  // older nodes not already tied closely along any edges.
  const auto near_in_graph =
      sweep ? GraphPathLengths(graph, node, options_.final_sweep_min_graph_path_m)
            : OdometryPathLengths(graph, node, options_.min_graph_distance_m, true);
  std::vector<GraphNodeId> nearby;
  for (const auto& [id, other] : graph.nodes()) {
    if (id == node || near_in_graph.count(id) || (sweep && id > node)) continue;
    if ((other.pose.translation() - pose.translation()).norm() <= options_.max_distance_m) {
      nearby.push_back(id);
    }
  }
  if (nearby.empty()) return nearby;
  // Mahalanobis gate on the marginal of each candidate relative to the new node, from the edges'
  // gating information where they have one (looser than the optimiser's).
  ScopedStageTimer timer(stats.stage_times, "loop_closing_marginals");
  const auto marginals =
      ComputeMarginals(graph, node, nearby, std::nullopt, EdgeInformation::kGating);
  if (!marginals.ok()) {
    ++stats.counters["loop_closing_marginals_failed"];
    return {};
  }
  std::vector<GraphNodeId> gated;
  for (GraphNodeId id : nearby) {
    const Pose2& candidate = graph.node(id).pose;
    // The new node seen from the candidate, shrunk by the perception range on each axis.
    const Eigen::Vector2d h = candidate.Between(pose).translation();
    const Eigen::Vector2d cropped(Shrink(h.x(), options_.perception_range_m),
                                  Shrink(h.y(), options_.perception_range_m));
    // The marginal is in global increments: rotate it into the candidate's frame.
    const Eigen::Matrix2d R = candidate.rotation();
    const Eigen::Matrix2d P = R.transpose() * marginals->at(id).topLeftCorner<2, 2>() * R +
                              1e-6 * Eigen::Matrix2d::Identity();
    if (cropped.dot(P.inverse() * cropped) <= options_.mahalanobis_gate) {
      gated.push_back(id);
      if (gated_marginals) (*gated_marginals)[id] = {P, marginals->at(id)(2, 2)};
    }
  }
  return gated;
}

void LoopCloser::ChooseFallbacks(const PoseGraph& graph, GraphNodeId node,
                                 const std::vector<std::pair<double, GraphNodeId>>& members,
                                 std::map<GraphNodeId, GraphNodeId>* fallback_of) const {
  const GraphNode& current = graph.node(node);
  std::vector<GraphNodeId> chosen = {members.front().second};
  for (std::size_t i = 1; i < members.size(); ++i) {
    if (static_cast<int>(chosen.size()) > options_.fallback_members) return;
    const GraphNode& member = graph.node(members[i].second);
    if (current.stamp_s - member.stamp_s < options_.fallback_min_age_s) continue;
    const bool apart = std::all_of(chosen.begin(), chosen.end(), [&](GraphNodeId id) {
      return (graph.node(id).pose.translation() - member.pose.translation()).norm() >=
             options_.fallback_min_spacing_m;
    });
    if (!apart) continue;
    (*fallback_of)[member.id] = chosen.back();
    chosen.push_back(member.id);
  }
}

void LoopCloser::SearchFrom(const PoseGraph& graph, GraphNodeId node, const CloudOf& cloud_of,
                            MapperStats& stats, bool heading_in_doubt) {
  Search(graph, node, cloud_of, stats, heading_in_doubt, /*sweep=*/false);
}

void LoopCloser::SweepFrom(const PoseGraph& graph, GraphNodeId node, const CloudOf& cloud_of,
                           MapperStats& stats) {
  Search(graph, node, cloud_of, stats, /*heading_in_doubt=*/false, /*sweep=*/true);
}

void LoopCloser::Search(const PoseGraph& graph, GraphNodeId node, const CloudOf& cloud_of,
                        MapperStats& stats, bool heading_in_doubt, bool sweep) {
  if (!options_.enabled || !graph.HasNode(node)) return;
  std::map<GraphNodeId, Marginal> marginals;
  const std::vector<GraphNodeId> candidates = Candidates(graph, node, sweep, stats, &marginals);
  // Waiting loops the graph has drifted away from are tried from this node too, where they put it.
  const std::map<GraphNodeId, std::vector<Pose2>> predicted = PredictFromWaiting(graph, node);
  if (candidates.empty() && predicted.empty()) return;
  ScopedStageTimer timer(stats.stage_times, "loop_closing_alignment");
  // Connected sets of candidates (joined by graph edges among candidates); in each, the nearest.
  std::set<GraphNodeId> remaining(candidates.begin(), candidates.end());
  std::map<GraphNodeId, std::vector<GraphNodeId>> adjacency;
  for (const GraphEdge& e : graph.edges()) {
    if (remaining.count(e.from) && remaining.count(e.to)) {
      adjacency[e.from].push_back(e.to);
      adjacency[e.to].push_back(e.from);
    }
  }
  const Pose2& pose = graph.node(node).pose;
  std::vector<GraphNodeId> olds;  // the local maps to align the new one with, in order
  std::set<GraphNodeId> tried;
  std::map<GraphNodeId, GraphNodeId> fallback_of;  // member -> the one whose failure it awaits
  auto align = [&](GraphNodeId old) {
    if (!tried.insert(old).second) return;
    if (accepted_pairs_.count({std::min(node, old), std::max(node, old)})) return;
    olds.push_back(old);
  };
  while (!remaining.empty()) {
    std::deque<GraphNodeId> queue{*remaining.begin()};
    remaining.erase(remaining.begin());
    std::vector<std::pair<double, GraphNodeId>> members;
    while (!queue.empty()) {
      const GraphNodeId id = queue.front();
      queue.pop_front();
      members.push_back({(graph.node(id).pose.translation() - pose.translation()).norm(), id});
      for (GraphNodeId next : adjacency[id]) {
        if (remaining.erase(next)) queue.push_back(next);
      }
    }
    std::sort(members.begin(), members.end());
    align(members[0].second);
    // The sweep starts from the final graph: its nearest member is where the place is.
    if (!sweep) ChooseFallbacks(graph, node, members, &fallback_of);
  }
  for (GraphNodeId id : candidates) {
    const GraphNode& other = graph.node(id);
    if (other.session_id >= graph.node(node).session_id) continue;
    if ((other.pose.translation() - pose.translation()).norm() < options_.duplicate_radius_m) {
      align(id);
    }
  }
  for (const auto& [target, unused] : predicted) {
    if (tried.insert(target).second) olds.push_back(target);
  }
  if (olds.empty()) return;

  // Each old map is tried from the graph's guess, then from its heading alone; the first guess
  // that validates wins, as when one thread tries them in turn. The old maps still unsettled run
  // side by side on the alignment threads, one guess each per round (no guess is tried that the
  // sequential order would have skipped).
  std::vector<Outcome> outcomes(olds.size());
  auto try_in_rounds = [&](const std::vector<std::vector<Pose2>>& guesses) {
    std::vector<std::size_t> open(olds.size());
    for (std::size_t k = 0; k < olds.size(); ++k) open[k] = k;
    for (std::size_t round = 0; !open.empty(); ++round) {
      std::vector<std::size_t> trying;
      for (std::size_t k : open) {
        if (round < guesses[k].size()) trying.push_back(k);
      }
      if (trying.empty()) break;
      std::vector<Attempt> attempts(trying.size());
      ParallelFor(trying.size(), options_.alignment_threads, [&](std::size_t i) {
        const std::size_t k = trying[i];
        attempts[i] = AlignFrom(cloud_of(node), cloud_of(olds[k]), guesses[k][round]);
      });
      open.clear();
      for (std::size_t i = 0; i < trying.size(); ++i) {
        Outcome& outcome = outcomes[trying[i]];
        outcome.degenerate |= attempts[i].degenerate;
        if (attempts[i].pose) {
          outcome.pose = attempts[i].pose;
        } else {
          open.push_back(trying[i]);
        }
      }
    }
  };
  const std::map<GraphNodeId, double> chain_m =
      options_.chain_gate_max_path_m > 0.0
          ? OdometryPathLengths(graph, node, options_.chain_gate_max_path_m, true)
          : std::map<GraphNodeId, double>{};
  std::vector<Pose2> graph_guesses(olds.size());  // new_T_old as the graph has it
  std::vector<std::vector<Pose2>> guesses(olds.size());
  for (std::size_t k = 0; k < olds.size(); ++k) {
    graph_guesses[k] = pose.Between(graph.node(olds[k]).pose);
    guesses[k] = {graph_guesses[k], Pose2(0.0, 0.0, graph_guesses[k].theta())};
    const auto prediction = predicted.find(olds[k]);
    if (prediction == predicted.end()) continue;
    // An old node only a prediction reaches is tried where the prediction puts it, not where the
    // drifted graph does.
    if (!marginals.count(olds[k])) guesses[k].clear();
    guesses[k].insert(guesses[k].end(), prediction->second.begin(), prediction->second.end());
  }
  try_in_rounds(guesses);
  // A set's next nearest member where the one before it did not align (the graph's guess drifted
  // away from the place): one more round of old maps per failure, with the same two guesses.
  for (bool added = true; added;) {
    added = false;
    for (std::vector<Pose2>& g : guesses) g.clear();
    for (const auto& [member, before] : fallback_of) {
      const auto it = std::find(olds.begin(), olds.end(), before);
      if (it == olds.end() || outcomes[it - olds.begin()].pose) continue;
      if (std::find(olds.begin(), olds.end(), member) != olds.end()) continue;
      if (accepted_pairs_.count({std::min(node, member), std::max(node, member)})) continue;
      ++stats.counters["loop_closure_alignments_fallback"];
      olds.push_back(member);
      graph_guesses.push_back(pose.Between(graph.node(member).pose));
      guesses.push_back({graph_guesses.back(), Pose2(0.0, 0.0, graph_guesses.back().theta())});
      outcomes.emplace_back();
      added = true;
    }
    if (added) try_in_rounds(guesses);
  }

  // Turning in place, a wrong registration can leave the heading tens of degrees off, far
  // beyond what the alignment corrects from the graph's guess: after a tracker failure, the maps
  // that did not align are tried with the new node turned about itself. The vote still has to
  // find the result consistent with others.
  std::vector<bool> turned(olds.size(), false);
  if (heading_in_doubt && options_.recovery_heading_steps > 0) {
    for (std::size_t k = 0; k < olds.size(); ++k) {
      guesses[k].clear();
      if (outcomes[k].pose) continue;
      turned[k] = true;
      outcomes[k].degenerate = false;  // the retry's refusals are the ones reported
      for (int step = 1; step <= options_.recovery_heading_steps; ++step) {
        for (double sign : {1.0, -1.0}) {
          guesses[k].push_back(Pose2(0.0, 0.0, sign * step * options_.recovery_heading_step_rad) *
                               graph_guesses[k]);
        }
      }
    }
    try_in_rounds(guesses);
  }

  // The old maps no guess aligned, from a graph guess too uncertain for the alignment's basin:
  // a correlative search over the marginal's window, then the alignment from its best pose.
  const std::vector<bool> correlative =
      options_.correlative_search && !sweep
          ? SearchCorrelative(cloud_of(node), olds, graph_guesses, marginals, cloud_of, outcomes,
                              stats)
          : std::vector<bool>(olds.size(), false);

  for (std::size_t k = 0; k < olds.size(); ++k) {
    ++stats.counters["loop_closure_alignments"];
    if (turned[k]) ++stats.counters["loop_closure_alignments_turned"];
    if (correlative[k]) ++stats.counters["loop_closure_alignments_correlative"];
    if (!outcomes[k].pose) {
      if (outcomes[k].degenerate) ++stats.counters["loop_closure_alignments_degenerate"];
      continue;
    }
    // The new node seen from the old one: where the alignment puts it against where the graph
    // has it (one innovation for both gates).
    const Eigen::Vector2d innovation =
        outcomes[k].pose->inverse().translation() - graph_guesses[k].inverse().translation();
    const double turn_rad =
        std::abs(NormalizeAngle(outcomes[k].pose->theta() - graph_guesses[k].theta()));
    if (sweep && (innovation.norm() > options_.final_sweep_max_offset_m ||
                  turn_rad > options_.final_sweep_max_offset_rad)) {
      ++stats.counters["loop_closure_sweep_alignments_off_graph"];
      continue;
    }
    const auto path = chain_m.find(olds[k]);
    if (path != chain_m.end() &&
        (innovation.norm() > options_.chain_gate_m + options_.chain_gate_per_m * path->second ||
         turn_rad > options_.chain_gate_rad + options_.chain_gate_rad_per_m * path->second)) {
      ++stats.counters["loop_closure_alignments_against_chain"];
      continue;
    }
    // Nodes only a prediction reached have no marginal here: the vote judges them.
    if (options_.innovation_gate > 0.0 && marginals.count(olds[k])) {
      const Eigen::Matrix2d S = marginals.at(olds[k]).offset_covariance +
                                Eigen::Matrix2d::Identity() / options_.closure_information_xy;
      const double chi2 = innovation.dot(S.inverse() * innovation);
      if (chi2 > options_.innovation_gate) {
        ++stats.counters["loop_closure_alignments_implausible"];
        continue;
      }
    }
    ++stats.counters["loop_closure_candidates"];
    AddCandidate({node, olds[k], *outcomes[k].pose, path != chain_m.end(), sweep});
  }
}

std::map<GraphNodeId, std::vector<Pose2>> LoopCloser::PredictFromWaiting(const PoseGraph& graph,
                                                                         GraphNodeId node) const {
  std::map<GraphNodeId, std::vector<Pose2>> predicted;
  if (!options_.vote_predict_from_waiting) return predicted;
  const Eigen::Matrix3d information = ClosureInformation();
  std::map<GraphNodeId, std::vector<GraphNodeId>> neighbours;
  const Pose2& pose = graph.node(node).pose;
  for (const ClosureCandidate& c : buffer_) {
    if (c.local == node || ages_.count(c.old) || !graph.HasNode(c.local) || !graph.HasNode(c.old)) {
      continue;
    }
    const Eigen::Vector3d e =
        EdgeError(graph.node(c.local).pose, graph.node(c.old).pose, c.local_T_old);
    if (e.dot(information * e) < options_.vote_outlier_chi2) continue;
    if (neighbours.empty()) {
      for (const GraphEdge& edge : graph.edges()) {
        if (edge.kind != EdgeKind::kOdometry) continue;
        neighbours[edge.from].push_back(edge.to);
        neighbours[edge.to].push_back(edge.from);
      }
    }
    // node_T_old if the candidate holds and the sub-map between its node and this one is right.
    const Pose2 node_T_old = pose.Between(graph.node(c.local).pose) * c.local_T_old;
    std::vector<GraphNodeId> targets = {c.old};
    targets.insert(targets.end(), neighbours[c.old].begin(), neighbours[c.old].end());
    for (GraphNodeId target : targets) {
      if (target == node || ages_.count(target) ||
          accepted_pairs_.count({std::min(node, target), std::max(node, target)})) {
        continue;
      }
      const Pose2 guess = node_T_old * graph.node(c.old).pose.Between(graph.node(target).pose);
      if (guess.translation().norm() > options_.max_distance_m) continue;
      std::vector<Pose2>& guesses = predicted[target];
      if (guesses.size() < 2) guesses.push_back(guess);
    }
  }
  return predicted;
}

void LoopCloser::AddCandidate(const ClosureCandidate& candidate) {
  buffer_.push_back(candidate);
  ages_.emplace(candidate.local, 0);
}

}  // namespace longterm_mapper2d
