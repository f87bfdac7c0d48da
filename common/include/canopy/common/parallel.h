// One way to spread independent work over threads (the tools' --threads N).
#pragma once

#include <cstddef>
#include <functional>

namespace canopy::common {

// Calls work(begin, end) on contiguous chunks covering [0, n): with threads <= 1 (or n <= 1)
// once, on this thread, as work(0, n); else on min(threads, n) threads, chunk k being
// [k c, min(n, (k + 1) c)) with c = ceil(n / threads). The chunks are the same for the same
// n and threads, so work that writes only its own indices gives the same result for any
// thread count. An exception thrown by work is rethrown here (the first by chunk order) after
// every thread has finished.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& work);

}  // namespace canopy::common
