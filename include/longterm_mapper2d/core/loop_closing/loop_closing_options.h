#pragma once

#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d {

// Loop-closure search (ALGORITHMS.md §7) and the voting scheme (§8).
struct LoopClosingOptions {
  bool enabled = true;
  // Candidates: nodes farther than this along the graph from the new node...
  double min_graph_distance_m = 5.0;
  // ... and within this Euclidean distance of it ...
  double max_distance_m = 10.0;
  // ... whose marginal position uncertainty allows it (chi2, 2 dof, 95 %), once each axis of the
  // offset is shrunk by the perception range (the local maps overlap within it).
  double mahalanobis_gate = 5.99;
  double perception_range_m = 1.5;
  // An alignment is kept only if where it puts the new node, seen from the candidate, is within
  // this chi2 (2 dof) of where the graph has it, under the gate's marginal plus the closure's own
  // covariance (0: no such test). Why: along a corridor an alignment can slide to a look-alike
  // stretch metres away and still validate, and the vote then finds it consistent with the
  // closures inside the new sub-map, which hold wherever the sub-map is placed.
  double innovation_gate = 5.99;
  // An alignment between nodes at most chain_gate_max_path_m apart along the odometry chain must
  // agree with the chain within chain_gate_m + chain_gate_per_m * path (translation of the new
  // node seen from the old) and chain_gate_rad + chain_gate_rad_per_m * path (0: no such test).
  // The graph's covariance along a corridor is loose (the registrations' is scaled up), so the
  // innovation gate passes a slide of metres to a look-alike stretch a few nodes back (aces:
  // 6-7 m at 2-3 nodes); the tracker does not drift that much. 0.1 per metre, not 0.3: intel's
  // first closure (node 8 -> 6, 5.2 m apart along the chain) slid 1.27 m along the corridor, and
  // that stretch's relations ended 1.28 m off; over the five runs of bench_robustness.sh 0.1
  // left fr079 unchanged and made intel and aces better on average (README, "Robustness").
  double chain_gate_max_path_m = 30.0;
  double chain_gate_m = 0.5;
  double chain_gate_per_m = 0.1;
  double chain_gate_rad = 0.3;
  double chain_gate_rad_per_m = 0.02;
  // Of each connected set of candidates only the nearest is aligned, except that every node of an
  // earlier session nearer than this is aligned too: such nodes at one place are duplicates (left
  // by sessions whose closures there failed), and each needs its own closure to be merged away.
  double duplicate_radius_m = 1.0;
  // Where a set's nearest member does not align, its next nearest ones are tried in turn, up to
  // fallback_members more, each at least fallback_min_spacing_m from the members tried before it
  // (another place, not the same one again) and stamped at least fallback_min_age_s before the
  // new node. After a long loop the graph's drift puts the nearest member of a place the robot
  // returns to metres from where the robot is (aces' return to its start after 840 s: the graph
  // 5.7 m off, and only a node 3 m away tried, which does not overlap); on a short loop the
  // nearest is right and a further member is one more chance for a wrong closure (intel: 0.030
  // -> 0.055 m with one member, no spacing and no age limit; the simulated care home's second
  // session 0.36 m off when an earlier session's members qualified whatever their stamps).
  // 0: the nearest alone.
  int fallback_members = 2;
  double fallback_min_spacing_m = 1.0;
  double fallback_min_age_s = 600.0;
  // Map-to-map alignment: coarse then fine correspondence distance, and validation from the new
  // node on a full-circle projector.
  double coarse_correspondence_m = 1.0;
  double fine_correspondence_m = 0.25;
  int validation_bins = 720;
  double validation_inlier_m = 0.05;
  double min_inlier_ratio = 0.5;
  int min_correspondences = 50;
  // Partial overlap: an alignment below min_inlier_ratio still validates when its inlier ratio
  // is at least partial_min_inlier_ratio and, of the bins where the old map is not hidden behind
  // the new one (inliers, and old surfaces in front of the new map's), at least
  // partial_min_agreement agree. Why: a merged old map holds several visits and reaches places
  // the new node never saw; seen from the new node, those surfaces lie behind its own walls and
  // counted as disagreement (intel: a return to a room the map had merged four visits of
  // validated at 0.33 at its best pose, with 4 % of the bins in front). A wrong alignment puts
  // old walls into the new map's free space. Off: it helps single sessions (intel's five
  // robustness runs 0.0361 -> 0.0337 m, each better, largest 0.60 -> 0.49 m; aces and fr079
  // unchanged) and twenty sessions of intel (0.035 -> 0.031 m on average), but intel in three
  // parts scores 0.034 -> 0.038 m, worse in all four variants tried (README, 2026-12-05).
  bool partial_overlap = false;
  double partial_min_inlier_ratio = 0.3;
  double partial_min_agreement = 0.97;
  // An alignment whose translation information is this much weaker along one axis than along the
  // other is degenerate (a corridor, a single wall): it cannot close a loop. 0.005, not 1e-4: on
  // aces the run's first return to its start produced four alignments, all slid 1.7-4.2 m along
  // a corridor (ratios 3e-4 to 1.9e-3, against 3e-3 to 0.9 for most right ones); over the five
  // runs of bench_robustness.sh 0.003, 0.005 and 0.01 all did better than 1e-4 (README).
  double min_information_ratio = 0.005;
  // Between the two: an alignment weaker along one axis than weak_information_ratio times the
  // other is refused too unless at least weak_min_inlier_ratio of the new map agrees with the
  // old (0: never). A slid corridor match agrees only in part. Intel over eleven node/scan
  // spacings: 0.0356 -> 0.0332 m on average (0.03: 0.0325, but intel in three parts then read
  // 0.044 against one session's 0.030); aces and fr079 unchanged (README, "Accuracy").
  double weak_information_ratio = 0.02;
  double weak_min_inlier_ratio = 0.6;
  // Local maps are aligned by their own points (RichPoint::inherited false: what the node's own
  // scans observed, fused or not with a merged map's) when at least own_points_min of them are
  // left, else by all; the alignment is validated with all the points either way. The inherited
  // points stand where each merge's relative pose put them; a closure measured on them carries
  // those errors into the graph, and they add up over passes. Intel over eleven node/scan
  // spacings 0.0332 -> 0.0308 m, in three parts 0.0322 -> 0.0304; aces and fr079 unchanged
  // within their spread; ten sessions as robust as before (README, "Accuracy").
  bool align_own_points = true;
  int own_points_min = 100;
  // An alignment by the own points that comes out degenerate (see min_information_ratio) is tried
  // again with all the points: a merged map's own scans may have seen only a corridor while the
  // maps it took in saw its ends. Without it, intel's docking corridor (the first node of every
  // session) never closed with the next session's and each session left one more node there.
  bool all_points_if_degenerate = true;
  // After a tracker failure, until a closure ties the new nodes to older ones, an alignment that
  // fails from the graph's guess is tried again with the new node turned by +-k * step,
  // k = 1..steps (0: never). Only then: for every node it would double the alignment time.
  int recovery_heading_steps = 2;
  double recovery_heading_step_rad = 0.35;
  // When no guess aligns an old map the marginal leaves far from where the graph has it, a
  // correlative search (CorrelativeMatcher: branch and bound over a likelihood grid of the new
  // map) finds where it fits best within +-correlative_window_sigmas of the marginal (x and y:
  // its largest axis; heading), capped at correlative_max_window_m / _rad, and the alignment
  // starts again from there. Only windows wider than correlative_min_window_m: within it the
  // alignment's own basin (coarse_correspondence_m) reaches. Best poses scoring below
  // correlative_min_score (mean likelihood of the old map's points, 0..1) are not tried.
  // correlative_resolution_m is the likelihood grid's cell, the translation step and the
  // likelihood kernel's sigma.
  // Why: the graph's guess of a loop after a long stretch is metres off (drift), beyond NICP's
  // basin; the gates and the vote judge what the search finds like any other alignment.
  // Off: on the Freiburg logs the alignments that fail mostly fail validation, not the basin
  // (intel: 354 searches, 104 poses above the score, 2 validated; aces and fr079: none), and the
  // searches took loop closing from 3.1 to 8.6 s on intel (intel 0.0400 -> 0.0419 m, aces and
  // fr079 unchanged, MIT Killian 16.4 -> 16.3 m).
  bool correlative_search = false;
  double correlative_window_sigmas = 3.0;
  double correlative_min_window_m = 0.5;
  double correlative_max_window_m = 5.0;
  double correlative_min_window_rad = 0.1;
  double correlative_max_window_rad = 0.5;
  double correlative_min_score = 0.3;
  double correlative_resolution_m = 0.05;
  // Threads for the closure alignments of a new node (the caller's included; 1: all on the
  // caller). The result does not depend on it.
  int alignment_threads = 2;
  // Information of a closure edge (x, y and theta).
  double closure_information_xy = 1000.0;
  double closure_information_theta = 300.0;
  // Voting: a candidate agrees with a hypothesis if chi2 < vote_inlier_chi2; a hypothesis with at
  // least vote_min_inliers agreeing candidates is accepted. Candidates wait up to vote_window
  // nodes; those farther than vote_outlier_chi2 from the winning hypothesis are dropped.
  double vote_inlier_chi2 = 3.0;
  int vote_min_inliers = 2;
  int vote_window = 10;
  double vote_outlier_chi2 = 500.0;
  // Count a hypothesis' agreeing candidates as distinct nodes (the smaller of distinct new and
  // distinct old nodes among them), so that several candidates against one old local map are
  // one piece of evidence, not several.
  bool vote_distinct_nodes = true;
  // A waiting candidate that disagrees with the graph by more than vote_outlier_chi2 (a loop the
  // graph has drifted away from) predicts where the next nodes sit against its old node: they are
  // aligned there, with the old node and its odometry neighbours, even out of the search's reach.
  // Without it a large loop has one candidate and never the support of two distinct nodes.
  bool vote_predict_from_waiting = true;
  // Vote on the candidates the chain gate checked (old node within chain_gate_max_path_m along
  // this session's chain) apart from the others. Why: the sub-map that moves in the vote is the
  // nodes waiting for votes, not the chain between them and an old node a few nodes back, so
  // such a short loop, however right, disagrees with any hypothesis that moves the sub-map and
  // outvotes a real return to a place seen long ago (aces, node 2.4 m: the return to the start,
  // three distinct nodes, lost to four short loops and the map stayed 11 m apart).
  bool vote_chain_apart = true;
  // When hypotheses are ranked, one the graph already agrees with (its own candidate within
  // vote_inlier_chi2 of the graph) counts one distinct node more: the closures accepted so far
  // are evidence too. Acceptance still needs vote_min_inliers of its own. Why: several new nodes
  // aligned to the one old map the graph already joined them to count as one node, and lost to
  // two candidates 1 m away to a look-alike room (intel, scan every 0.11 m: 6 m off).
  bool vote_graph_supports = true;
  // Drift of the trajectory per metre between two candidates' nodes, added to the closure's
  // covariance when one is scored against the other's hypothesis (0: the rigid test alone).
  double vote_drift_per_m = 0.05;
  double vote_drift_rad_per_m = 0.01;
  // Graph optimisation after each node and after closures.
  int optimizer_iterations = 10;
  // The final sweep (end of a session, and OptimizeNow): every node of this session is searched
  // again, oldest first, against the older nodes the optimised graph now puts near it, and voted
  // on as when it was new. Why: a node is searched only once, when it is made, from where the
  // graph had it then; a return to a place the drifted graph put metres away (aces: back at the
  // start 9 m off, every alignment failed) stays open after later loops pull the map right (the
  // start's relations ended 0.6-0.8 m off). Only pairs not already tied closely by the graph
  // (farther than final_sweep_min_graph_path_m along any of its edges) are tried, an alignment
  // must agree with the optimised graph within final_sweep_max_offset_m / _rad, and in the vote
  // agreeing candidates must agree rigidly (no drift allowance: the graph has no drift left).
  bool final_sweep = true;
  double final_sweep_min_graph_path_m = 20.0;
  double final_sweep_max_offset_m = 1.0;
  double final_sweep_max_offset_rad = 0.3;

  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("min_graph_distance_m", min_graph_distance_m);
    v("max_distance_m", max_distance_m);
    v("mahalanobis_gate", mahalanobis_gate);
    v("perception_range_m", perception_range_m);
    v("innovation_gate", innovation_gate);
    v("chain_gate_max_path_m", chain_gate_max_path_m);
    v("chain_gate_m", chain_gate_m);
    v("chain_gate_per_m", chain_gate_per_m);
    v("chain_gate_rad", chain_gate_rad);
    v("chain_gate_rad_per_m", chain_gate_rad_per_m);
    v("duplicate_radius_m", duplicate_radius_m);
    v("fallback_members", fallback_members);
    v("fallback_min_spacing_m", fallback_min_spacing_m);
    v("fallback_min_age_s", fallback_min_age_s);
    v("coarse_correspondence_m", coarse_correspondence_m);
    v("fine_correspondence_m", fine_correspondence_m);
    v("validation_bins", validation_bins);
    v("validation_inlier_m", validation_inlier_m);
    v("min_inlier_ratio", min_inlier_ratio);
    v("min_correspondences", min_correspondences);
    v("partial_overlap", partial_overlap);
    v("partial_min_inlier_ratio", partial_min_inlier_ratio);
    v("partial_min_agreement", partial_min_agreement);
    v("min_information_ratio", min_information_ratio);
    v("weak_information_ratio", weak_information_ratio);
    v("weak_min_inlier_ratio", weak_min_inlier_ratio);
    v("align_own_points", align_own_points);
    v("own_points_min", own_points_min);
    v("all_points_if_degenerate", all_points_if_degenerate);
    v("recovery_heading_steps", recovery_heading_steps);
    v("recovery_heading_step_rad", recovery_heading_step_rad);
    v("correlative_search", correlative_search);
    v("correlative_window_sigmas", correlative_window_sigmas);
    v("correlative_min_window_m", correlative_min_window_m);
    v("correlative_max_window_m", correlative_max_window_m);
    v("correlative_min_window_rad", correlative_min_window_rad);
    v("correlative_max_window_rad", correlative_max_window_rad);
    v("correlative_min_score", correlative_min_score);
    v("correlative_resolution_m", correlative_resolution_m);
    v("alignment_threads", alignment_threads);
    v("closure_information_xy", closure_information_xy);
    v("closure_information_theta", closure_information_theta);
    v("vote_inlier_chi2", vote_inlier_chi2);
    v("vote_min_inliers", vote_min_inliers);
    v("vote_window", vote_window);
    v("vote_outlier_chi2", vote_outlier_chi2);
    v("vote_distinct_nodes", vote_distinct_nodes);
    v("vote_predict_from_waiting", vote_predict_from_waiting);
    v("vote_chain_apart", vote_chain_apart);
    v("vote_graph_supports", vote_graph_supports);
    v("vote_drift_per_m", vote_drift_per_m);
    v("vote_drift_rad_per_m", vote_drift_rad_per_m);
    v("optimizer_iterations", optimizer_iterations);
    v("final_sweep", final_sweep);
    v("final_sweep_min_graph_path_m", final_sweep_min_graph_path_m);
    v("final_sweep_max_offset_m", final_sweep_max_offset_m);
    v("final_sweep_max_offset_rad", final_sweep_max_offset_rad);
  }
  void Validate(OptionErrors& e) const {
    e.Require(min_graph_distance_m >= 0.0, "min_graph_distance_m", "must be non-negative");
    e.Require(max_distance_m > 0.0, "max_distance_m", "must be positive");
    e.Require(mahalanobis_gate > 0.0, "mahalanobis_gate", "must be positive");
    e.Require(perception_range_m >= 0.0, "perception_range_m", "must be non-negative");
    e.Require(innovation_gate >= 0.0, "innovation_gate", "must be non-negative (0: off)");
    e.Require(chain_gate_max_path_m >= 0.0, "chain_gate_max_path_m",
              "must be non-negative (0: off)");
    e.Require(chain_gate_m >= 0.0 && chain_gate_per_m >= 0.0, "chain_gate_m",
              "the chain gate's translation bounds must be non-negative");
    e.Require(chain_gate_rad >= 0.0 && chain_gate_rad_per_m >= 0.0, "chain_gate_rad",
              "the chain gate's rotation bounds must be non-negative");
    e.Require(duplicate_radius_m >= 0.0, "duplicate_radius_m", "must be non-negative");
    e.Require(fallback_members >= 0, "fallback_members", "must be non-negative");
    e.Require(fallback_min_spacing_m >= 0.0, "fallback_min_spacing_m", "must be non-negative");
    e.Require(fallback_min_age_s >= 0.0, "fallback_min_age_s", "must be non-negative");
    e.Require(coarse_correspondence_m >= fine_correspondence_m && fine_correspondence_m > 0.0,
              "fine_correspondence_m", "must be positive and at most coarse_correspondence_m");
    e.Require(validation_bins >= 36, "validation_bins", "must be at least 36");
    e.Require(validation_inlier_m > 0.0, "validation_inlier_m", "must be positive");
    e.Require(min_inlier_ratio > 0.0 && min_inlier_ratio <= 1.0, "min_inlier_ratio",
              "must be in (0, 1]");
    e.Require(min_correspondences >= 3, "min_correspondences", "must be at least 3");
    e.Require(partial_min_inlier_ratio > 0.0 && partial_min_inlier_ratio <= min_inlier_ratio,
              "partial_min_inlier_ratio", "must be in (0, min_inlier_ratio]");
    e.Require(partial_min_agreement > 0.0 && partial_min_agreement <= 1.0, "partial_min_agreement",
              "must be in (0, 1]");
    e.Require(min_information_ratio >= 0.0 && min_information_ratio < 1.0, "min_information_ratio",
              "must be in [0, 1)");
    e.Require(weak_information_ratio >= min_information_ratio && weak_information_ratio < 1.0,
              "weak_information_ratio", "must be in [min_information_ratio, 1)");
    e.Require(weak_min_inlier_ratio >= 0.0 && weak_min_inlier_ratio <= 1.0, "weak_min_inlier_ratio",
              "must be in [0, 1]");
    e.Require(own_points_min >= 0, "own_points_min", "must be non-negative");
    e.Require(recovery_heading_steps >= 0, "recovery_heading_steps", "must be non-negative");
    e.Require(recovery_heading_step_rad > 0.0 && recovery_heading_step_rad <= 1.6,
              "recovery_heading_step_rad", "must be in (0, 1.6]");
    e.Require(correlative_window_sigmas > 0.0, "correlative_window_sigmas", "must be positive");
    e.Require(correlative_min_window_m >= 0.0 && correlative_max_window_m > 0.0 &&
                  correlative_max_window_m >= correlative_min_window_m &&
                  correlative_max_window_m <= 20.0,
              "correlative_max_window_m",
              "the correlative window must be in [correlative_min_window_m, 20] m, its minimum "
              "non-negative");
    e.Require(correlative_min_window_rad >= 0.0 &&
                  correlative_max_window_rad >= correlative_min_window_rad &&
                  correlative_max_window_rad <= 3.2,
              "correlative_max_window_rad",
              "the correlative heading window must be in [correlative_min_window_rad, 3.2]");
    e.Require(correlative_min_score >= 0.0 && correlative_min_score <= 1.0, "correlative_min_score",
              "must be in [0, 1]");
    e.Require(correlative_resolution_m >= 0.01 && correlative_resolution_m <= 0.5,
              "correlative_resolution_m", "must be in [0.01, 0.5]");
    e.Require(alignment_threads >= 1 && alignment_threads <= 64, "alignment_threads",
              "must be in [1, 64]");
    e.Require(closure_information_xy > 0.0 && closure_information_theta > 0.0,
              "closure_information_xy", "closure information must be positive");
    e.Require(vote_inlier_chi2 > 0.0, "vote_inlier_chi2", "must be positive");
    e.Require(vote_min_inliers >= 1, "vote_min_inliers", "must be at least 1");
    e.Require(vote_window >= 1, "vote_window", "must be at least 1");
    e.Require(vote_drift_per_m >= 0.0, "vote_drift_per_m", "must be non-negative");
    e.Require(vote_drift_rad_per_m >= 0.0, "vote_drift_rad_per_m", "must be non-negative");
    e.Require(vote_outlier_chi2 > vote_inlier_chi2, "vote_outlier_chi2",
              "must exceed vote_inlier_chi2");
    e.Require(optimizer_iterations >= 1, "optimizer_iterations", "must be at least 1");
    e.Require(final_sweep_min_graph_path_m >= 0.0, "final_sweep_min_graph_path_m",
              "must be non-negative");
    e.Require(final_sweep_max_offset_m > 0.0 && final_sweep_max_offset_rad > 0.0,
              "final_sweep_max_offset_m", "the sweep's offset bounds must be positive");
  }
};

}  // namespace longterm_mapper2d
