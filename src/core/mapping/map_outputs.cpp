#include "longterm_mapper2d/core/mapping/map_outputs.h"

#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/io/map_image_io.h"
#include "longterm_mapper2d/core/io/trajectory_io.h"
#include "longterm_mapper2d/core/map/grid_renderer.h"

namespace longterm_mapper2d {
Status WriteMapOutputs(const Mapper& mapper, const std::string& directory) {
  if (Status s = MakeDirectories(directory); !s.ok()) return s;
  auto grid = RenderOccupancyGrid(mapper.WaypointScans(), mapper.options().grid);
  if (!grid.ok()) return Status::Error("cannot render the map: " + grid.status().message());
  if (Status s = WriteMapPgmYaml(*grid, directory + "/map.yaml"); !s.ok()) return s;
  if (Status s = WriteGridPng(*grid, directory + "/map.png"); !s.ok()) return s;
  return WriteTrajectory(directory + "/trajectory.txt", mapper.Trajectory());
}

}  // namespace longterm_mapper2d
