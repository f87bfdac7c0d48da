#include "canopy/common/parallel.h"

#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

namespace canopy::common {

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& work) {
  const std::size_t t = std::min<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), n);
  if (t <= 1) {
    work(0, n);
    return;
  }
  const std::size_t chunk = (n + t - 1) / t;
  std::vector<std::exception_ptr> errors(t);
  std::vector<std::thread> pool;
  for (std::size_t k = 0; k < t; ++k) {
    const std::size_t first = k * chunk, last = std::min(n, first + chunk);
    if (first >= last) break;
    pool.emplace_back([&work, &errors, k, first, last] {
      try {
        work(first, last);
      } catch (...) { errors[k] = std::current_exception(); }
    });
  }
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace canopy::common
