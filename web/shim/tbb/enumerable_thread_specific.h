#pragma once
// The web build has no threads and no TBB: tbb::enumerable_thread_specific<T>(make) of the
// export's sources holds one T, made by `make` on first use (local()). Only the constructor and
// local() are used by the sources compiled into the module.
#include <functional>
#include <optional>
#include <utility>

namespace tbb {
template <typename T>
class enumerable_thread_specific {
 public:
  template <typename Make>
  explicit enumerable_thread_specific(Make make) : make_(std::move(make)) {}
  T& local() {
    if (!value_) value_.emplace(make_());
    return *value_;
  }

 private:
  std::function<T()> make_;
  std::optional<T> value_;
};
}  // namespace tbb
