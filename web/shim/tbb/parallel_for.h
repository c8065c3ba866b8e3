#pragma once
// The web build has no threads and no TBB: tbb::parallel_for(first, last, f) of the transport's
// (the frequency-domain nodes) and the fit's sources runs serially, in order (the results do not
// depend on the order: every index writes its own slot). Only this overload is used by the
// sources compiled into the module.
namespace tbb {
template <typename Index, typename Function>
void parallel_for(Index first, Index last, const Function& f) {
  for (Index i = first; i < last; ++i) f(i);
}
}  // namespace tbb
