#pragma once

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"
#include "longterm_mapper2d/core/loop_closing/loop_closing_options.h"
#include "longterm_mapper2d/core/mapping/mapper_stats.h"
#include "longterm_mapper2d/core/registration/nicp.h"

namespace longterm_mapper2d {

// A loop-closure hypothesis from aligning two local maps: the pose of `old` in the frame of
// `local` (the node that found it, which stays in the buffer while votes are pending).
struct ClosureCandidate {
  GraphNodeId local = 0;
  GraphNodeId old = 0;
  Pose2 local_T_old;
  // The old node is within LoopClosingOptions::chain_gate_max_path_m along the local node's
  // chain (the chain gate checked the alignment): voted apart from the others.
  bool on_chain = false;
  // Found by the final sweep (LoopCloser::SweepFrom): agreeing candidates must agree rigidly.
  bool from_sweep = false;
};

// Shortest path lengths from `source` along odometry edges (Euclidean lengths between the nodes'
// poses), for the nodes within `limit_m`. Nodes that a closure or a merge (condensed edges) joined
// are not near on this measure. `tracker_chain_only`: only through the source's own session (the
// edge tying a session's first node to a loaded map is a prior, not a tracker measurement).
std::map<GraphNodeId, double> OdometryPathLengths(const PoseGraph& graph, GraphNodeId source,
                                                  double limit_m, bool tracker_chain_only = false);
// The same along every edge (odometry, closures, condensed): how closely the graph already ties
// other nodes to `source`.
std::map<GraphNodeId, double> GraphPathLengths(const PoseGraph& graph, GraphNodeId source,
                                               double limit_m);

// Finds loop closures for new nodes (candidates within a Mahalanobis gate, grouped into
// connected sets, the nearest of each set aligned map-to-map and validated) and accepts them by
// the hypothesise-and-verify vote over a rigid sub-map (ALGORITHMS.md §7-8).
class LoopCloser {
 public:
  using CloudOf = std::function<const Cloud&(GraphNodeId)>;
  LoopCloser(const LoopClosingOptions& options, const RegistrationOptions& registration);

  // Looks for closures of `node` and buffers the validated ones. `heading_in_doubt` (the node
  // follows a tracker failure that no closure has settled yet) also tries the headings of
  // LoopClosingOptions::recovery_heading_steps when the graph's guess does not align.
  void SearchFrom(const PoseGraph& graph, GraphNodeId node, const CloudOf& cloud_of,
                  MapperStats& stats, bool heading_in_doubt = false);
  // The final sweep's search from `node` (LoopClosingOptions::final_sweep): like SearchFrom, but
  // only against older nodes that the graph does not already tie closely to it, and only
  // alignments that agree with the (optimised) graph within the sweep's offset bounds.
  void SweepFrom(const PoseGraph& graph, GraphNodeId node, const CloudOf& cloud_of,
                 MapperStats& stats);
  // Runs the vote when due (or now, if `force`); returns the accepted closures as edges, never
  // one already accepted for the same pair. Ages the buffer.
  std::vector<GraphEdge> Vote(const PoseGraph& graph, bool force, MapperStats& stats);

  // Aligns two local maps (exposed for tests): the pose of `current` in the frame of
  // `reference`, if one of the guesses validates.
  std::optional<Pose2> AlignLocalMaps(const Cloud& reference, const Cloud& current,
                                      const std::vector<Pose2>& guesses);

  // Adds a validated candidate to the vote (SearchFrom does this for the ones it finds).
  void AddCandidate(const ClosureCandidate& candidate);
  const std::vector<ClosureCandidate>& buffer() const { return buffer_; }

 private:
  // One alignment from one guess: the validated pose, or nothing (`degenerate`: refused because
  // the geometry pins only one direction). `all_points`: by all the points, not the own ones
  // (ClosurePoints). Const and self-contained: runs on several threads.
  struct Attempt {
    std::optional<Pose2> pose;
    bool degenerate = false;
  };
  Attempt AlignFrom(const Cloud& reference, const Cloud& current, const Pose2& guess,
                    bool all_points = false) const;
  // The points of a local map that alignments use (LoopClosingOptions::align_own_points): its
  // own points, copied into `own`, or the whole cloud.
  const Cloud& ClosurePoints(const Cloud& cloud, Cloud* own) const;
  // Whether a fine alignment's validation (from the new node) passes, partial overlap included
  // (LoopClosingOptions::partial_overlap).
  bool Validates(const RegistrationValidation& validation) const;
  // What the Mahalanobis gate knew of a candidate: the covariance of the new node's position
  // seen from it (in its frame) and the variance of their relative heading.
  struct Marginal {
    Eigen::Matrix2d offset_covariance = Eigen::Matrix2d::Identity();
    double heading_variance = 0.0;
  };
  // What the guesses tried for one old map gave.
  struct Outcome {
    std::optional<Pose2> pose;
    bool degenerate = false;  // some guess tried was refused as degenerate
  };
  // One old map for the correlative search: the graph's new_T_old and the search window.
  struct CorrelativeRequest {
    const Cloud* current = nullptr;
    Pose2 guess;
    double window_m = 0.0;
    double window_rad = 0.0;
  };
  // The search window for a candidate with this marginal, or nullopt when it is too narrow to
  // need a search (LoopClosingOptions::correlative_*).
  std::optional<CorrelativeRequest> CorrelativeWindow(const Marginal& marginal,
                                                      const Pose2& guess) const;
  // Correlative search then alignment for each request against `reference` (the new node's
  // cloud), side by side on the alignment threads: the validated poses, in request order.
  std::vector<Attempt> AlignCorrelative(const Cloud& reference,
                                        const std::vector<CorrelativeRequest>& requests,
                                        MapperStats& stats) const;
  // The correlative search for the old maps (`olds`, with the graph's new_T_old guesses) whose
  // outcome has no pose yet: writes the validated poses into `outcomes`; true where it did.
  std::vector<bool> SearchCorrelative(const Cloud& reference, const std::vector<GraphNodeId>& olds,
                                      const std::vector<Pose2>& graph_guesses,
                                      const std::map<GraphNodeId, Marginal>& marginals,
                                      const CloudOf& cloud_of, std::vector<Outcome>& outcomes,
                                      MapperStats& stats) const;
  // The members of a candidate set (distance from the new node, id; nearest first) to try after
  // the nearest, each mapped to the member whose failed alignment it waits for.
  void ChooseFallbacks(const PoseGraph& graph, GraphNodeId node,
                       const std::vector<std::pair<double, GraphNodeId>>& members,
                       std::map<GraphNodeId, GraphNodeId>* fallback_of) const;
  // SearchFrom (`sweep` false) and SweepFrom (true).
  void Search(const PoseGraph& graph, GraphNodeId node, const CloudOf& cloud_of, MapperStats& stats,
              bool heading_in_doubt, bool sweep);
  // The gated candidates, and for each the marginal the gate used. `sweep`: older nodes not tied
  // closely by the graph only.
  std::vector<GraphNodeId> Candidates(const PoseGraph& graph, GraphNodeId node, bool sweep,
                                      MapperStats& stats,
                                      std::map<GraphNodeId, Marginal>* gated_marginals) const;
  Eigen::Matrix3d ClosureInformation() const;
  // One vote among the buffered candidates with this `on_chain` (nullopt: all of them).
  void VoteWithin(const PoseGraph& graph, std::optional<bool> on_chain,
                  std::vector<GraphEdge>& accepted, MapperStats& stats);
  // Where the waiting candidates that disagree with the graph put `node` against their old
  // nodes and those nodes' odometry neighbours: node_T_old guesses per old node (at most two).
  std::map<GraphNodeId, std::vector<Pose2>> PredictFromWaiting(const PoseGraph& graph,
                                                               GraphNodeId node) const;

  LoopClosingOptions options_;
  RegistrationOptions coarse_;
  RegistrationOptions fine_;
  std::vector<ClosureCandidate> buffer_;
  std::map<GraphNodeId, int> ages_;
  std::set<std::pair<GraphNodeId, GraphNodeId>> accepted_pairs_;
  bool degenerate_ = false;  // the last AlignLocalMaps refused a degenerate alignment
};

}  // namespace longterm_mapper2d
