#pragma once
// The check of a request before long or large work starts, shared by the command line and the
// Python module: a request whose memory exceeds the machine's physical memory, or whose time
// estimate exceeds a week (a typo, surely), is refused with one line; one estimated over an hour
// is announced (the caller says how: a line on stderr, a Python warning).
#include <string>

namespace skin::util {

inline constexpr double kWarnedSeconds = 3600, kRefusedSeconds = 7 * 86400;

struct WorkEstimate {
  double seconds = 0;  // estimated wall time
  int threads = 1;     // the worker threads it assumes
  // "<what> would take about <duration> on <threads> threads (estimate from the measured speed)"
  std::string text;
  bool long_run() const { return seconds > kWarnedSeconds; }
};

// `what` names the work ("a Monte Carlo run of 1000000 photons"); `units` of work at
// `units_per_second_per_thread` on `threads` workers (0 = all cores) and `bytes` of memory.
// Throws InputError when refused ("<text>: refused, make it smaller", or "<what> needs about
// 12 GB of memory, more than this machine's 8 GB; make it smaller").
WorkEstimate estimate_work(const std::string& what, double units, double units_per_second_per_thread,
                           int threads, double bytes);
// The memory part alone.
void check_memory(const std::string& what, double bytes);

}  // namespace skin::util
