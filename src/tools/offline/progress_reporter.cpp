#include "longterm_mapper2d/tools/progress_reporter.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace longterm_mapper2d {

ProgressReporter::ProgressReporter(std::uint64_t total)
    : total_(total),
      interactive_(::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

double ProgressReporter::elapsed_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressReporter::Update(std::uint64_t done) {
  if (!interactive_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(200) && done < total_) return;
  last_draw_ = now;
  const double fraction = total_ > 0 ? std::min(1.0, static_cast<double>(done) / total_) : 1.0;
  const double elapsed = elapsed_s();
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  const double eta = rate > 0 ? (total_ - std::min(done, total_)) / rate : 0.0;
  constexpr int kWidth = 30;
  char bar[kWidth + 1];
  const int filled = static_cast<int>(fraction * kWidth);
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  std::fprintf(stderr, "\r[%s] %5.1f%%  %7.0f scans/s  ETA %5.0f s ", bar, 100.0 * fraction, rate,
               eta);
  std::fflush(stderr);
}

void ProgressReporter::Finish() {
  if (!interactive_) return;
  Update(total_);
  std::fprintf(stderr, "\n");
}

}  // namespace longterm_mapper2d
