#pragma once

#include <vector>

#include "longterm_mapper2d/core/cloud/cloud_merger.h"
#include "longterm_mapper2d/core/cloud/range_projector.h"
#include "longterm_mapper2d/core/mapping/local_map.h"
#include "longterm_mapper2d/core/mapping/maintenance_options.h"
#include "longterm_mapper2d/core/registration/nicp.h"

namespace longterm_mapper2d {

struct LocalMapMergeStats {
  int virtual_scans = 0;       // viewpoints (the new map's waypoints) that produced a scan
  int aligned = 0;             // ... whose alignment to the merged cloud validated
  int old_waypoints_kept = 0;  // waypoints of the old map not covered by a new one
  MergeStats merge;            // summed over the virtual scans
};

// Merges an old local map into a new one that a loop closure found in the same place
// (ALGORITHMS.md §9.2): the old cloud is moved into the new node's frame; from each of the new
// node's waypoints a virtual scan of the new cloud (what the robot sees of the new map from
// there) is aligned to the merged cloud and merged into it with the free-space rules, so new
// observations overwrite old ones and objects that are gone get erased. The waypoints are united.
// The merged cloud and waypoints replace the new node's.
class LocalMapMerger {
 public:
  LocalMapMerger(const MaintenanceOptions& maintenance, const MergerOptions& merger,
                 const RegistrationOptions& registration, double max_range_m);

  // new_T_old: the old node's pose in the new node's frame (from the optimised graph).
  LocalMapMergeStats Merge(const LocalMapNode& old_node, const Pose2& new_T_old,
                           LocalMapNode* new_node);

 private:
  MaintenanceOptions options_;
  double max_range_m_;
  CloudMerger merger_;
  Nicp nicp_;
  RangeImage image_;
};

}  // namespace longterm_mapper2d
