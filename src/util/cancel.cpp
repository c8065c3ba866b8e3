#include "skin/util/cancel.hpp"

#include <atomic>

namespace skin::util::cancel {

namespace {
// Lock-free, hence usable from a signal handler.
std::atomic<bool> flag{false};
static_assert(std::atomic<bool>::is_always_lock_free);
}  // namespace

void request() noexcept { flag.store(true, std::memory_order_relaxed); }
bool requested() noexcept { return flag.load(std::memory_order_relaxed); }
void reset() noexcept { flag.store(false, std::memory_order_relaxed); }

}  // namespace skin::util::cancel
