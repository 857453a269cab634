#include "longterm_mapper2d/core/registration/nearest_neighbour_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace longterm_mapper2d {
namespace {
constexpr double kMaxCells = 4.0e6;
}  // namespace

NearestNeighbourGrid::NearestNeighbourGrid(const Cloud& cloud, double max_distance_m,
                                           double target_cell_m)
    : max_distance_m_(max_distance_m) {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  int count = 0;
  for (const RichPoint& p : cloud) {
    if (!p.has_normal() || !p.point_m.allFinite()) continue;
    min_x = std::min(min_x, p.point_m.x());
    min_y = std::min(min_y, p.point_m.y());
    max_x = std::max(max_x, p.point_m.x());
    max_y = std::max(max_y, p.point_m.y());
    ++count;
  }
  if (count == 0) {
    cell_begin_.assign(1, 0);
    return;
  }
  // A whole number of cells per radius, so that the ring bound below is tight.
  const double radius = std::max(max_distance_m, 1e-6);
  cell_m_ = radius / std::max(1.0, std::ceil(radius / std::max(target_cell_m, 1e-6)));
  const double area = (max_x - min_x + cell_m_) * (max_y - min_y + cell_m_);
  if (area / (cell_m_ * cell_m_) > kMaxCells) cell_m_ = std::sqrt(area / kMaxCells);
  min_x_ = min_x;
  min_y_ = min_y;
  width_ = static_cast<long>((max_x - min_x) / cell_m_) + 1;
  height_ = static_cast<long>((max_y - min_y) / cell_m_) + 1;

  // Counting sort of the points by cell (row-major), keeping cloud order within a cell.
  std::vector<long> cell_of(cloud.size(), -1);
  cell_begin_.assign(width_ * height_ + 1, 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const RichPoint& p = cloud[i];
    if (!p.has_normal() || !p.point_m.allFinite()) continue;
    const long cx = std::min(width_ - 1, static_cast<long>((p.point_m.x() - min_x_) / cell_m_));
    const long cy = std::min(height_ - 1, static_cast<long>((p.point_m.y() - min_y_) / cell_m_));
    cell_of[i] = cy * width_ + cx;
    ++cell_begin_[cell_of[i] + 1];
  }
  for (std::size_t c = 1; c < cell_begin_.size(); ++c) cell_begin_[c] += cell_begin_[c - 1];
  entries_.resize(count);
  std::vector<int> fill(cell_begin_.begin(), cell_begin_.end() - 1);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cell_of[i] < 0) continue;
    const RichPoint& p = cloud[i];
    entries_[fill[cell_of[i]]++] = {p.point_m.x(), p.point_m.y(), p.normal.x(), p.normal.y(),
                                    static_cast<int>(i)};
  }
}

int NearestNeighbourGrid::Nearest(const Eigen::Vector2d& query, const Eigen::Vector2d& normal,
                                  double cos_max_angle, double max_distance_sq) const {
  if (entries_.empty() || !query.allFinite()) return -1;
  const double qx = query.x() - min_x_, qy = query.y() - min_y_;
  const double fx = std::floor(qx / cell_m_), fy = std::floor(qy / cell_m_);
  // Far outside the grid (also guards the conversions to long below).
  const double reach = std::sqrt(max_distance_sq) / cell_m_ + 1.0;
  if (fx < -reach || fy < -reach || fx > width_ + reach || fy > height_ + reach) return -1;
  const long cx = static_cast<long>(fx), cy = static_cast<long>(fy);
  // Offsets of the query inside its cell, for the distance from the query to a cell.
  const double ox = qx - fx * cell_m_, oy = qy - fy * cell_m_;
  const double margin = std::min(std::min(ox, cell_m_ - ox), std::min(oy, cell_m_ - oy));
  const long max_ring = static_cast<long>(std::ceil(max_distance_m_ / cell_m_)) + 1;

  int best = -1;
  double best_sq = max_distance_sq;
  auto visit_cell = [&](long x, long y) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    // Distance from the query to the cell's box, per axis.
    const double dx = x < cx ? ox + (cx - x - 1) * cell_m_
                             : (x > cx ? (x - cx - 1) * cell_m_ + cell_m_ - ox : 0.0);
    const double dy = y < cy ? oy + (cy - y - 1) * cell_m_
                             : (y > cy ? (y - cy - 1) * cell_m_ + cell_m_ - oy : 0.0);
    if (dx * dx + dy * dy >= best_sq) return;
    const long cell = y * width_ + x;
    for (int k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k) {
      const Entry& e = entries_[k];
      const double ex = query.x() - e.x, ey = query.y() - e.y;
      const double d2 = ex * ex + ey * ey;
      if (d2 < best_sq && normal.x() * e.nx + normal.y() * e.ny > cos_max_angle) {
        best_sq = d2;
        best = e.index;
      }
    }
  };
  visit_cell(cx, cy);
  for (long ring = 1; ring <= max_ring; ++ring) {
    // Every cell of this ring is at least this far from the query.
    const double bound = (ring - 1) * cell_m_ + margin;
    if (bound * bound >= best_sq) break;
    for (long x = cx - ring; x <= cx + ring; ++x) {
      visit_cell(x, cy - ring);
      visit_cell(x, cy + ring);
    }
    for (long y = cy - ring + 1; y <= cy + ring - 1; ++y) {
      visit_cell(cx - ring, y);
      visit_cell(cx + ring, y);
    }
  }
  return best;
}

}  // namespace longterm_mapper2d
