#pragma once

#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d {

// How raw scans are screened before they reach the mapper.
struct InputOptions {
  // Scans with fewer beams are ignored (too little to register against).
  int min_beams = 100;
  // A waypoint (pose + raw scan, used for rendering and merging) every this much travel.
  double waypoint_spacing_m = 0.1;
  double waypoint_spacing_rad = 0.2;

  template <class V>
  void Visit(V& v) {
    v("min_beams", min_beams);
    v("waypoint_spacing_m", waypoint_spacing_m);
    v("waypoint_spacing_rad", waypoint_spacing_rad);
  }
  void Validate(OptionErrors& e) const {
    e.Require(min_beams >= 1, "min_beams", "must be at least 1");
    e.Require(waypoint_spacing_m > 0.0, "waypoint_spacing_m", "must be positive");
    e.Require(waypoint_spacing_rad > 0.0, "waypoint_spacing_rad", "must be positive");
  }
};

}  // namespace longterm_mapper2d
