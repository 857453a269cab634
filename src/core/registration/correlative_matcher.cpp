#include "longterm_mapper2d/core/registration/correlative_matcher.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace longterm_mapper2d {
namespace {

constexpr double kMaxCells = 4.0e6;  // per grid level (16 MB of floats)
constexpr double kKernelRadiusSigmas = 3.0;
// Grids are padded by 2^(levels-1) - 1 cells (see pad_), so coarse levels cost memory fast; a
// block of 2^9 cells (25.6 m at 5 cm) is already coarser than any useful window.
constexpr int kMaxLevels = 10;
constexpr double kMaxLinearSteps = 1.0e6;
// Cell indices beyond this are replaced by it before the conversion to int (such a point is far
// outside any grid and scores 0); with kMaxLinearSteps, index + offset cannot overflow an int.
constexpr int kFarCell = 1 << 28;

void ValidateOptions(const CorrelativeMatcherOptions& o) {
  if (!(o.resolution_m > 0.0) || !std::isfinite(o.resolution_m))
    throw std::invalid_argument("CorrelativeMatcher: resolution_m must be positive and finite");
  if (!(o.kernel_sigma_m > 0.0) || !std::isfinite(o.kernel_sigma_m))
    throw std::invalid_argument("CorrelativeMatcher: kernel_sigma_m must be positive and finite");
  if (o.levels < 1 || o.levels > kMaxLevels)
    throw std::invalid_argument("CorrelativeMatcher: levels must be in [1, 10]");
  if (o.max_points < 1) throw std::invalid_argument("CorrelativeMatcher: max_points must be >= 1");
  if (!(o.min_score >= 0.0 && o.min_score <= 1.0))
    throw std::invalid_argument("CorrelativeMatcher: min_score must be in [0, 1]");
}

// The finite points of `cloud`, thinned by a voxel grid to at most max_points. The voxel starts
// at extent / max_points (a line across the cloud would already need that many) and grows by 25 %
// until few enough voxels are occupied; each voxel keeps its first point, in cloud order.
std::vector<Eigen::Vector2d> Thin(const Cloud& cloud, int max_points) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(cloud.size());
  for (const RichPoint& p : cloud)
    if (p.point_m.allFinite()) points.push_back(p.point_m);
  if (static_cast<int>(points.size()) <= max_points) return points;

  Eigen::Vector2d min = points[0], max = points[0];
  for (const Eigen::Vector2d& p : points) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  const double extent = (max - min).maxCoeff();
  double voxel_m = std::max(extent / max_points, 1e-9);
  std::vector<std::pair<std::int64_t, int>> keyed(points.size());  // (voxel, point index)
  for (;;) {
    // extent / voxel_m <= max_points, so the keys cannot overflow.
    const std::int64_t stride = static_cast<std::int64_t>(extent / voxel_m) + 2;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d v = (points[i] - min) / voxel_m;
      keyed[i] = {static_cast<std::int64_t>(v.x()) * stride + static_cast<std::int64_t>(v.y()),
                  static_cast<int>(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    int occupied = 0;
    for (std::size_t i = 0; i < keyed.size(); ++i)
      occupied += i == 0 || keyed[i].first != keyed[i - 1].first;
    if (occupied <= max_points) break;
    voxel_m *= 1.25;
  }
  std::vector<int> kept;
  for (std::size_t i = 0; i < keyed.size(); ++i)
    if (i == 0 || keyed[i].first != keyed[i - 1].first) kept.push_back(keyed[i].second);
  std::sort(kept.begin(), kept.end());
  std::vector<Eigen::Vector2d> thinned;
  thinned.reserve(kept.size());
  for (int i : kept) thinned.push_back(points[i]);
  return thinned;
}

// A translation block of the search: offsets [dx, dx + 2^level) x [dy, dy + 2^level) (fine cells)
// at one rotation, with the sum of its level's grid, an upper bound of the sum of each offset.
struct Candidate {
  float sum;
  int rotation, dx, dy;
};

// The search order: higher sum first; ties by rotation, then offset.
bool Before(const Candidate& a, const Candidate& b) {
  if (a.sum != b.sum) return a.sum > b.sum;
  return std::tie(a.rotation, a.dx, a.dy) < std::tie(b.rotation, b.dx, b.dy);
}

}  // namespace

CorrelativeMatcher::CorrelativeMatcher(const Cloud& reference,
                                       const CorrelativeMatcherOptions& options)
    : options_(options), resolution_m_(options.resolution_m) {
  ValidateOptions(options);
  std::vector<Eigen::Vector2d> points;
  for (const RichPoint& p : reference)
    if (p.point_m.allFinite()) points.push_back(p.point_m);
  if (points.empty()) return;

  const double sigma = options.kernel_sigma_m;
  const double reach_m = kKernelRadiusSigmas * sigma;
  Eigen::Vector2d min = points[0], max = points[0];
  for (const Eigen::Vector2d& p : points) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  min.array() -= reach_m;
  max.array() += reach_m;
  const Eigen::Vector2d span = max - min;
  const double area_cells = (span.x() / resolution_m_ + 1.0) * (span.y() / resolution_m_ + 1.0);
  if (area_cells > kMaxCells) resolution_m_ *= std::sqrt(area_cells / kMaxCells);
  origin_m_ = min;
  // Level k at cell i pools fine cells [i, i + 2^k): it is non-zero down to i = -(2^k - 1).
  pad_ = (1 << (options.levels - 1)) - 1;
  const int fine_width = static_cast<int>(span.x() / resolution_m_) + 1;
  const int fine_height = static_cast<int>(span.y() / resolution_m_) + 1;
  width_ = fine_width + pad_;
  height_ = fine_height + pad_;
  levels_.assign(options.levels, std::vector<float>(std::size_t(width_) * height_, 0.0f));

  // Fine grid: the max over points of the kernel at each cell's centre, cut at 3 sigma. The kernel
  // factors per axis, so a point costs 2 (2r + 1) exponentials for its (2r + 1)^2 cells.
  const int r = static_cast<int>(std::ceil(reach_m / resolution_m_));
  const double inv_two_sigma_sq = 1.0 / (2.0 * sigma * sigma);
  std::vector<double> gx(2 * r + 1), gy(2 * r + 1), dx2(2 * r + 1), dy2(2 * r + 1);
  std::vector<float>& fine = levels_[0];
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d q = (p - origin_m_) / resolution_m_;
    const int cx = static_cast<int>(std::floor(q.x())), cy = static_cast<int>(std::floor(q.y()));
    for (int a = -r; a <= r; ++a) {
      dx2[a + r] = std::pow((cx + a + 0.5 - q.x()) * resolution_m_, 2);
      dy2[a + r] = std::pow((cy + a + 0.5 - q.y()) * resolution_m_, 2);
      gx[a + r] = std::exp(-dx2[a + r] * inv_two_sigma_sq);
      gy[a + r] = std::exp(-dy2[a + r] * inv_two_sigma_sq);
    }
    for (int b = -r; b <= r; ++b) {
      const int y = cy + b;
      if (y < 0 || y >= fine_height) continue;
      float* row = &fine[std::size_t(y + pad_) * width_ + pad_];
      for (int a = -r; a <= r; ++a) {
        const int x = cx + a;
        if (x < 0 || x >= fine_width || dx2[a + r] + dy2[b + r] > reach_m * reach_m) continue;
        row[x] = std::max(row[x], static_cast<float>(gx[a + r] * gy[b + r]));
      }
    }
  }

  // Level k from level k - 1 (h = 2^(k-1)): [i, i + 2^k) = [i, i + h) u [i + h, i + 2h), so
  // L_k(i, j) = max of L_{k-1} at (i, j), (i + h, j), (i, j + h), (i + h, j + h); one row pass and
  // one column pass, O(cells) per level. Why this bounds the search: a block of offsets
  // [dx, dx + 2^k) x [dy, dy + 2^k) sends a point of cell (x, y) into fine cells inside
  // [x + dx, x + dx + 2^k) x [y + dy, y + dy + 2^k), all pooled by L_k(x + dx, y + dy); summed over
  // the points, L_k bounds the score of every offset of the block.
  std::vector<float> rows(levels_[0].size());
  for (int k = 1; k < options.levels; ++k) {
    const int h = 1 << (k - 1);
    const std::vector<float>& prev = levels_[k - 1];
    std::vector<float>& cur = levels_[k];
    for (int y = 0; y < height_; ++y) {
      const std::size_t row = std::size_t(y) * width_;
      for (int x = 0; x < width_; ++x)
        rows[row + x] = x + h < width_ ? std::max(prev[row + x], prev[row + x + h]) : prev[row + x];
    }
    for (int y = 0; y < height_; ++y) {
      const std::size_t row = std::size_t(y) * width_, up = row + std::size_t(h) * width_;
      for (int x = 0; x < width_; ++x)
        cur[row + x] = y + h < height_ ? std::max(rows[row + x], rows[up + x]) : rows[row + x];
    }
  }
}

CorrelativeSearchGrid CorrelativeMatcher::SearchGrid(const Cloud& current, double linear_window_m,
                                                     double angular_window_rad) const {
  if (!(linear_window_m >= 0.0) || !(angular_window_rad >= 0.0) ||
      !std::isfinite(linear_window_m) || !std::isfinite(angular_window_rad))
    throw std::invalid_argument("CorrelativeMatcher: windows must be finite and non-negative");
  if (linear_window_m / resolution_m_ > kMaxLinearSteps)
    throw std::invalid_argument("CorrelativeMatcher: linear window too large for the resolution");
  CorrelativeSearchGrid grid;
  grid.resolution_m = resolution_m_;
  grid.linear_steps = static_cast<int>(std::ceil(linear_window_m / resolution_m_));
  double range_m = 0.0;
  for (const RichPoint& p : current)
    if (p.point_m.allFinite()) range_m = std::max(range_m, p.point_m.norm());
  // A rotation by step moves a point at range r by 2 r sin(step / 2) = r sqrt(2 (1 - cos step)):
  // one cell at the farthest point. Past pi the window repeats itself.
  const double cos_step = 1.0 - resolution_m_ * resolution_m_ / (2.0 * range_m * range_m);
  const double max_step = range_m > 0.0 ? std::acos(std::max(-1.0, cos_step)) : M_PI;
  const double window = std::min(angular_window_rad, M_PI);
  grid.angular_steps = static_cast<int>(std::ceil(window / max_step));
  grid.angular_step_rad = grid.angular_steps > 0 ? window / grid.angular_steps : 0.0;
  return grid;
}

CorrelativeMatcher::Cells CorrelativeMatcher::Discretise(
    const std::vector<Eigen::Vector2d>& points_reference) const {
  Cells cells;
  cells.x.reserve(points_reference.size());
  cells.y.reserve(points_reference.size());
  auto to_cell = [&](double v) {
    const double f = std::floor(v / resolution_m_);
    return f > -kFarCell && f < kFarCell ? static_cast<int>(f) + pad_ : kFarCell;  // NaN: far
  };
  for (const Eigen::Vector2d& p : points_reference) {
    cells.x.push_back(to_cell(p.x() - origin_m_.x()));
    cells.y.push_back(to_cell(p.y() - origin_m_.y()));
  }
  return cells;
}

float CorrelativeMatcher::SumAt(int level, const Cells& cells, int dx, int dy) const {
  const float* grid = levels_[level].data();
  const unsigned width = width_, height = height_;
  float sum = 0.0f;
  for (std::size_t i = 0; i < cells.x.size(); ++i) {
    const unsigned x = static_cast<unsigned>(cells.x[i] + dx);
    const unsigned y = static_cast<unsigned>(cells.y[i] + dy);
    if (x < width && y < height) sum += grid[std::size_t(y) * width + x];  // outside: 0
  }
  return sum;
}

double CorrelativeMatcher::Score(const Cloud& current, const Pose2& reference_T_current) const {
  const std::vector<Eigen::Vector2d> points = Thin(current, options_.max_points);
  if (points.empty() || levels_.empty()) return 0.0;
  std::vector<Eigen::Vector2d> transformed;
  transformed.reserve(points.size());
  for (const Eigen::Vector2d& p : points) transformed.push_back(reference_T_current * p);
  return SumAt(0, Discretise(transformed), 0, 0) / static_cast<double>(points.size());
}

std::optional<CorrelativeMatch> CorrelativeMatcher::Match(const Cloud& current, const Pose2& guess,
                                                          double linear_window_m,
                                                          double angular_window_rad) const {
  const CorrelativeSearchGrid search = SearchGrid(current, linear_window_m, angular_window_rad);
  const std::vector<Eigen::Vector2d> points = Thin(current, options_.max_points);
  if (points.empty() || levels_.empty()) return std::nullopt;
  const double count = static_cast<double>(points.size());
  const int w = search.linear_steps;

  // Each rotation once: guess * R(angle) applied to the points, then discretised; a translation
  // offset is then a shift of cell indices.
  std::vector<Cells> rotated;
  std::vector<Eigen::Vector2d> transformed(points.size());
  for (int a = -search.angular_steps; a <= search.angular_steps; ++a) {
    const Pose2 pose = guess * Pose2(0.0, 0.0, a * search.angular_step_rad);
    for (std::size_t i = 0; i < points.size(); ++i) transformed[i] = pose * points[i];
    rotated.push_back(Discretise(transformed));
  }

  // Roots: blocks of the coarsest level tiling [-w, w]^2 at every rotation.
  const int top = options_.levels - 1;
  std::vector<std::pair<int, Candidate>> stack;  // (level, candidate), best on top
  for (int rot = 0; rot < static_cast<int>(rotated.size()); ++rot)
    for (int dx = -w; dx <= w; dx += 1 << top)
      for (int dy = -w; dy <= w; dy += 1 << top)
        stack.push_back({top, {SumAt(top, rotated[rot], dx, dy), rot, dx, dy}});
  auto later = [](const std::pair<int, Candidate>& a, const std::pair<int, Candidate>& b) {
    return Before(b.second, a.second);
  };
  std::sort(stack.begin(), stack.end(), later);

  // Depth first, best bound first among siblings. A block is pruned when its bound cannot beat
  // the best exact score so far (before the first, when it is below min_score); a level-0 block
  // is a single pose and its sum is exact. Bounds are sums in the same order as the exact sums of
  // terms no smaller, and float rounding is monotone, so the pruning is exact.
  auto passes = [&](float sum) { return sum / count >= options_.min_score; };
  bool found = false;
  Candidate best{0.0f, 0, 0, 0};
  std::vector<std::pair<int, Candidate>> children;
  while (!stack.empty()) {
    const auto [level, c] = stack.back();
    stack.pop_back();
    if (found ? c.sum <= best.sum : !passes(c.sum)) continue;
    if (level == 0) {
      best = c;
      found = true;
      continue;
    }
    const int half = 1 << (level - 1);
    children.clear();
    for (int ox : {0, half})
      for (int oy : {0, half})
        if (c.dx + ox <= w && c.dy + oy <= w)
          children.push_back({level - 1,
                              {SumAt(level - 1, rotated[c.rotation], c.dx + ox, c.dy + oy),
                               c.rotation, c.dx + ox, c.dy + oy}});
    std::sort(children.begin(), children.end(), later);
    stack.insert(stack.end(), children.begin(), children.end());
  }
  if (!found) return std::nullopt;

  const double angle = (best.rotation - search.angular_steps) * search.angular_step_rad;
  CorrelativeMatch match;
  match.reference_T_current =
      Pose2(best.dx * resolution_m_, best.dy * resolution_m_, 0.0) * guess * Pose2(0, 0, angle);
  match.score = best.sum / count;
  return match;
}

}  // namespace longterm_mapper2d
