#pragma once
// RadialResponse: what the profile solver needs from a model of a layer stack (the multipole
// DiffusionStack, or a more accurate transport model): the total, an analytic singular part known
// in space, and the frequency-domain remainder, which must be smooth and decay fast in k.
namespace skin::transport {
class RadialResponse {
 public:
  virtual ~RadialResponse() = default;
  virtual double total() const = 0;               // R_d = R(k = 0)
  virtual double singular(double r) const = 0;    // analytic part in space [1/mm^2]
  virtual double residual_k(double k) const = 0;  // R(k) - FT{singular}(k)
};
}  // namespace skin::transport
