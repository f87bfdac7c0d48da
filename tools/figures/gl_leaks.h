// VTK's offscreen render window loads Mesa's GL driver, which keeps a few per-process
// allocations it never frees (112 bytes in 2 blocks here) and is unloaded before
// LeakSanitizer reports, so the report names no library a suppression could match
// (scripts/sanitize.sh, docs/decisions/hardening.md "Sanitizer run"). Under AddressSanitizer,
// the allocations this thread makes while a GlLeakScope lives are not reported as leaks (every
// other check stays on); in an ordinary build it does nothing.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

namespace canopy::figures {

struct GlLeakScope {
#if defined(__SANITIZE_ADDRESS__)
  GlLeakScope() { __lsan_disable(); }
  ~GlLeakScope() { __lsan_enable(); }
#else
  GlLeakScope() {}   // NOLINT(modernize-use-equals-default): user-provided, so an unused scope
  ~GlLeakScope() {}  // NOLINT(modernize-use-equals-default)  is no -Wunused-variable
#endif
  GlLeakScope(const GlLeakScope&) = delete;
  GlLeakScope& operator=(const GlLeakScope&) = delete;
};

}  // namespace canopy::figures
