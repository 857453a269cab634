#pragma once

#include <cstddef>
#include <functional>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"
#include "longterm_mapper2d/tools/offline_mapper_app.h"

namespace longterm_mapper2d {

// Reads a recording on a thread of its own and hands its scans to `visit` on the calling thread,
// in the recording's order, at most `capacity` scans ahead. Decoding (bz2-compressed bags took a
// sixth of the offline mapper's time on the intel log) overlaps with mapping; the result is the
// same as recording.ForEach(visit). Returns the recording's status. If `visit` throws, reading
// stops being handed on, the thread is joined and the exception propagates.
Status ForEachPrefetched(RecordedScans& recording,
                         const std::function<void(const ScanInput&)>& visit,
                         std::size_t capacity = 256);

}  // namespace longterm_mapper2d
