#include "longterm_mapper2d/core/mapping/map_outputs.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include "longterm_mapper2d/core/io/map_image_io.h"
#include "longterm_mapper2d/core/io/trajectory_io.h"
#include "longterm_mapper2d/core/map/grid_renderer.h"

namespace longterm_mapper2d {
namespace {

Status MakeDirectories(const std::string& directory) {
  std::string partial;
  for (std::size_t i = 0; i <= directory.size(); ++i) {
    if (i == directory.size() || directory[i] == '/') {
      if (!partial.empty() && ::mkdir(partial.c_str(), 0755) != 0 && errno != EEXIST) {
        return Status::Error("cannot create folder '" + partial + "': " + std::strerror(errno));
      }
    }
    if (i < directory.size()) partial += directory[i];
  }
  return Status::Ok();
}

}  // namespace

Status WriteMapOutputs(const Mapper& mapper, const std::string& directory) {
  if (Status s = MakeDirectories(directory); !s.ok()) return s;
  auto grid = RenderOccupancyGrid(mapper.WaypointScans(), mapper.options().grid);
  if (!grid.ok()) return Status::Error("cannot render the map: " + grid.status().message());
  if (Status s = WriteMapPgmYaml(*grid, directory + "/map.yaml"); !s.ok()) return s;
  if (Status s = WriteGridPng(*grid, directory + "/map.png"); !s.ok()) return s;
  return WriteTrajectory(directory + "/trajectory.txt", mapper.Trajectory());
}

}  // namespace longterm_mapper2d
