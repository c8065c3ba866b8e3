#include "skin/transport/stack.hpp"

#include <ostream>

namespace skin::transport {

using skin::physics::LayerStack;

std::ostream& operator<<(std::ostream& os, const Transfer& t) {
  return os << "Transfer{R_down=" << t.R_down << ", T_down=" << t.T_down << ", R_up=" << t.R_up
            << ", T_up=" << t.T_up << '}';
}

Transfer add_layers(const Transfer& a, const Transfer& b) {
  // Light bouncing between a (seen from below) and b (seen from above): geometric series.
  const double denom = 1.0 - a.R_up * b.R_down;
  Transfer t;
  t.R_down = a.R_down + a.T_down * b.R_down * a.T_up / denom;
  t.T_down = a.T_down * b.T_down / denom;
  t.R_up = b.R_up + b.T_up * a.R_up * b.T_down / denom;
  t.T_up = b.T_up * a.T_up / denom;
  return t;
}

DiffusionStack::DiffusionStack(const LayerStack& stack) {
  stack.validate();
  const auto& ls = stack.layers;
  const std::size_t n = ls.size();
  down_.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double n_above = i == 0 ? stack.eta_above : ls[i - 1].eta;
    const double n_below = i + 1 == n ? stack.eta_below : ls[i + 1].eta;
    const double A_top = A_boundary(ls[i].eta / n_above);
    // A semi-infinite layer has no bottom boundary (A = 1 is a placeholder, never used).
    const double A_bottom = ls[i].semi_infinite() ? 1.0 : A_boundary(ls[i].eta / n_below);
    down_.push_back(DiffusionSlab::make(ls[i].sigma_a, ls[i].sigma_s_prime, ls[i].thickness,
                                        A_top, A_bottom));
  }
}

Transfer DiffusionStack::at(double k) const {
  auto layer = [k](const DiffusionSlab& slab) {
    const auto t = slab.transfer_k(k);  // the layer from above and from below (flipped)
    return Transfer{t[0], t[1], t[2], t[3]};
  };
  Transfer acc = layer(down_[0]);
  for (std::size_t i = 1; i < down_.size(); ++i) acc = add_layers(acc, layer(down_[i]));
  return acc;
}

}  // namespace skin::transport
