#include "skin/util/work_estimate.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <thread>

#include "skin/util/error.hpp"

namespace skin::util {

namespace {
std::string duration_text(double seconds) {
  char buf[64];
  if (seconds < 90) std::snprintf(buf, sizeof buf, "%.0f s", seconds);
  else if (seconds < 2 * 3600.0) std::snprintf(buf, sizeof buf, "%.0f minutes", seconds / 60);
  else if (seconds < 2 * 86400.0) std::snprintf(buf, sizeof buf, "%.1f hours", seconds / 3600);
  else if (seconds < 2 * 365 * 86400.0) std::snprintf(buf, sizeof buf, "%.0f days", seconds / 86400);
  else std::snprintf(buf, sizeof buf, "%.2g years", seconds / (365 * 86400.0));
  return buf;
}
std::string bytes_text(double bytes) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
  return buf;
}
}  // namespace

void check_memory(const std::string& what, double bytes) {
  const double memory = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
  if (memory > 0 && bytes > memory)
    throw InputError(what + " needs about " + bytes_text(bytes) + " of memory, more than this machine's " +
                     bytes_text(memory) + "; make it smaller");
}

WorkEstimate estimate_work(const std::string& what, double units, double units_per_second_per_thread,
                           int threads, double bytes) {
  check_memory(what, bytes);
  WorkEstimate e;
  e.threads = threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  e.seconds = units / (units_per_second_per_thread * e.threads);
  e.text = what + " would take about " + duration_text(e.seconds) + " on " + std::to_string(e.threads) +
           " thread" + (e.threads > 1 ? "s" : "") + " (estimate from the measured speed)";
  if (e.seconds > kRefusedSeconds) throw InputError(e.text + ": refused, make it smaller");
  return e;
}

}  // namespace skin::util
