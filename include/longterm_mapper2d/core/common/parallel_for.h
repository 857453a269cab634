#pragma once

#include <cstddef>
#include <functional>

namespace longterm_mapper2d {

// Calls fn(i) once for every i in [0, count), on up to `threads` threads (the calling thread is
// one of them; threads <= 1 or count <= 1 runs everything here, in order). Which thread runs which
// i is not fixed, so fn must write only to slots of its own i: callers gather the results in
// index order afterwards, which keeps them deterministic. The first exception thrown by fn is
// rethrown here once every thread has stopped.
void ParallelFor(std::size_t count, int threads, const std::function<void(std::size_t)>& fn);

}  // namespace longterm_mapper2d
