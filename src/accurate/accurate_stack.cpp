// AccurateStack: multipole shapes with adding-doubling totals (docs/accurate-solver.md, sec. 3).
#include <algorithm>
#include <cmath>
#include <ostream>

#include "skin/accurate/accurate.hpp"

namespace skin::accurate {

namespace {
// The top layer alone, with the boundaries it has in the stack (the index below it is that of
// the next layer, or of the medium below).
LayerStack top_layer(const LayerStack& stack) {
  stack.validate();
  LayerStack top;
  top.layers = {stack.layers.front()};
  top.eta_above = stack.eta_above;
  top.eta_below = stack.layers.size() > 1 ? stack.layers[1].eta : stack.eta_below;
  return top;
}
}  // namespace

AccurateStack::AccurateStack(const LayerStack& stack, const Options& options)
    : totals_(adding_doubling(stack, options)), stack_(stack) {
  const double R_mp = stack_.R_d();
  const double R_top_mp = stack_.slabs().front().R_d();
  if (stack.layers.size() == 1) {
    c_top_ = c_deep_ = totals_.R_d / R_mp;
    return;
  }
  const double R_top_ad = adding_doubling(top_layer(stack), options).R_d;
  const double deep_mp = R_mp - R_top_mp;
  c_top_ = R_top_ad / R_top_mp;
  // The light that came back from below the top layer: its adding-doubling share is the rest of
  // the total. If diffusion sees (almost) none, the whole correction goes to the top layer.
  const double deep_ad = totals_.R_d - R_top_ad;
  if (deep_mp > 1e-9 * R_mp && deep_ad >= 0) {
    c_deep_ = deep_ad / deep_mp;
  } else {
    c_deep_ = 1;
    c_top_ = (totals_.R_d - deep_mp) / R_top_mp;
  }
}

double AccurateStack::singular(double r) const { return c_top_ * stack_.dipole(r); }

double AccurateStack::residual_k(double k) const {
  const double R_top = stack_.slabs().front().R_k(k);
  return c_top_ * (R_top - stack_.dipole_k(k)) + c_deep_ * (stack_.R_k(k) - R_top);
}

std::ostream& operator<<(std::ostream& os, const AccurateStack& s) {
  return os << "AccurateStack{" << s.totals() << ", c_top=" << s.c_top()
            << ", c_deep=" << s.c_deep() << '}';
}

}  // namespace skin::accurate
