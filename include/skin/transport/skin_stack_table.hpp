#pragma once
// The frequency-domain profiles of the two-layer skin geometry and of a half-space of skin's
// medium, tabulated (docs/accurate-solver.md, sec. 4): a cache of FrequencyStack for the stacks
// every skin material asks for (and the half-spaces the export to pbrt-v4 fits), so that an RGB
// or spectral profile of skin is read, not solved (the cost of a solve: docs/benchmarks.md).
//
// Geometry: air over a finite layer (the epidermis: index eta, Henyey-Greenstein g, reduced
// scattering s, absorption sigma_a,e, thickness d) over a half-space of the same index and g (the
// dermis: reduced scattering dermis_ratio x s, absorption sigma_a,d). In units of 1 / s the stack
// has three parameters, tau = s d, a_e = sigma_a,e / s and a_d = sigma_a,d / s, and its profile is
// R(r) = s^2 rho(x), x = r s. Each node holds ln rho at the x nodes, computed by FrequencyStack
// (the top layer floored at 1e-13 of its peak: in a dark epidermis its inversion is noise below
// ~1e-8 of rho(0.01), which the table keeps at that level; the light from below at 1e-15 of the
// node's peak).
// Two parts per node, each smooth in the parameters: the top layer alone over an absorber (no
// light back from below), and the light that reached the lower layer, computed on its own (R(k)
// of the stack minus R(k) of the top layer, at the same frequencies with the same azimuthal
// orders, inverted: smooth down to ~1e-15 of the peak, where the difference of the two inverted
// profiles was noise below ~1e-10 in a dark epidermis' far field) (their sum has a knee where
// the second takes over, which moves with tau; interpolating the sum was up to 11 % off the
// solver in african and 5 % in asian skin above 1e-4 of the peak, the parts 3.7 % and 0.43 %).
// Interpolation: 4-point Lagrange in ln tau (the top layer) or tau (the light from below, which
// crosses the top layer twice: ln rho falls linearly in tau), sqrt a_e and sqrt a_d (sqrt: where
// a layer is dark ln rho falls linearly in a, where it is bright the diffusion far field falls
// linearly in sqrt a) and cubic in ln x; below the first x node rho continues as the power of x
// of the first two nodes (single scattering's 1 / x) down to a tenth of it and is flat below;
// beyond the last it falls exponentially in x; below 1e-12 of its peak it is 0. The interpolated
// shape is scaled to integrate to the stack's adding-doubling R_d. Nodes: air over eta 1.4, g
// 0.9, the dermis half as scattering; tau 0.078-22.8 (the offsets to 10.1, held beyond), a_e up
// to 16.06 (every preset at 380-780 nm lies below 6.93, where the offsets' a_e nodes end: beyond
// it they hold their last node's values, and gap() reads them only up to a_e 12).
// The half-space (air over one semi-infinite layer of index eta and g): a = sigma_a / sigma_s'
// from 1e-4 to 25 (alpha' 0.9999-0.038), R(r) = s^2 rho(x) with s its sigma_s', interpolated in
// sqrt a like the top layer.
#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "skin/physics/layer.hpp"
#include "skin/util/progress.hpp"

namespace skin::transport::accurate {

struct SkinStackTable {
  double eta = 1.4, g = 0.9, dermis_ratio = 0.5;  // the geometry (air above)
  std::string provenance;
  std::vector<double> tau, a_e, a_d, x;  // nodes, increasing
  std::vector<double> a_h;               // the half-space's nodes (none: half-spaces not covered)
  // The profile in two parts, each smooth in the parameters (their sum has a knee where the light
  // from below takes over, which moves with tau): the top layer alone over an absorber, and the
  // light that reached the lower layer, ln rho_low (solve_low()).
  std::vector<double> ln_rho_top;        // [(i_tau * a_e.size() + i_e) * x.size() + i_x]
  std::vector<double> ln_rho;            // [((i_tau * a_e.size() + i_e) * a_d.size() + i_d) * x.size() + i_x]
  std::vector<double> ln_rho_half;       // [i_h * x.size() + i_x]
  // Offsets for another g, index or dermis ratio (none: only the table's own geometry is
  // covered). The built-in table has the built-in offsets.
  const struct SkinStackOffsets* offsets = nullptr;

  // The built-in nodes (data/skin_stack_profiles.csv), without values.
  static SkinStackTable default_nodes();
  // Computes every node with FrequencyStack (parallel over nodes; cancellable: throws Cancelled).
  // progress(done, total) is called after each node, from worker threads, one call at a time.
  // With `reuse` (a table of the same geometry, a_d, x and a_h), the nodes it holds (tau and a_e
  // equal to 1e-6) are copied from it instead of solved; the others are solved.
  void compute(const util::ProgressCallback& progress = {}, const SkinStackTable* reuse = nullptr);
  std::string to_csv() const;
  // Throws InputError naming `source` for a malformed table.
  static SkinStackTable parse(std::string_view text, std::string_view source);
  // Continues each light from below beyond the noise its inversion leaves in the far field,
  // linearly in x (docs/accurate-solver.md, sec. 4). After the offsets' settle() (which reads the
  // rows as solved); builtin() is parsed and settled so.
  void settle();
  static const SkinStackTable& builtin();

  // Why a stack is not in the table (empty when it is).
  std::string gap(const physics::LayerStack& stack) const;
  // ln rho at the x nodes of the stack (tau, a_e, a_d), or of the half-space a (inside the node
  // ranges).
  std::vector<double> ln_rho_at(double tau, double a_e, double a_d) const;
  // The two parts (ln rho_top, ln rho_low) at the x nodes, before they are added.
  void ln_parts_at(double tau, double a_e, double a_d, std::vector<double>& top, std::vector<double>& low) const;
  std::vector<double> ln_rho_half_space_at(double a) const;
  // The node's values (tests): ln rho at the x nodes (the two parts added).
  std::vector<double> node(std::size_t i_tau, std::size_t i_e, std::size_t i_d) const;
  // ln rho of one node computed by FrequencyStack, floored as in the table; and of its top layer
  // alone over an absorber.
  std::vector<double> solve_node(double tau, double a_e, double a_d) const;
  std::vector<double> solve_top(double tau, double a_e) const;
  // ln rho of the light from below of one node, computed on its own (R(k) of the stack minus
  // R(k) of the top layer, inverted; the table's low part), floored as in the table.
  std::vector<double> solve_low(double tau, double a_e, double a_d) const;
  std::vector<double> solve_half_space(double a) const;
};

struct SkinStackCross;

// Offsets of the table's two parts for skin of another g, index or dermis ratio
// (docs/accurate-solver.md, sec. 4): per axis (g, eta, dermis_ratio) and per node of it other
// than the table's own value, ln rho_top(value) - ln rho_top(table) and the same for the light
// from below, computed as the table's parts are (FrequencyStack; the light from below on its own
// since 2026-12-05: the nodes computed before hold it as the difference of two profiles) on a
// coarse subset of the table's (tau, a_e, a_d) nodes, tau only up to 10.1 and a_e up to 6.93 (the
// dermis ratio's a_e and a_d twice as fine above 0.4: axis_a_e, axis_a_d) and every other x node;
// beyond their last tau and a_e nodes they hold those nodes' values (the table's reach 22.8 and
// 16.06). They are interpolated like the table (4-point Lagrange in ln tau or
// tau, sqrt a_e, sqrt a_d, ln x) and across each axis' nodes (in ln(1 - g), eta and ln ratio),
// and the axes' offsets are added. Where a part is below a threshold of its node's peak (the top
// layer 1e-9: its inversion's noise, or the floor; the light from below 1e-14, smooth to ~1e-15
// since it is solved on its own) the offset holds its value from the nearest x where it is not. Two or
// three axes off the table's at once take the cross terms of each pair of them too
// (SkinStackCross); without them another dermis ratio is not combined with another g or index.
struct SkinStackOffsets {
  static constexpr int kAxes = 3;  // g, eta, dermis_ratio
  static constexpr const char* kAxisNames[kAxes] = {"g", "eta", "dermis_ratio"};
  std::string provenance;
  std::array<double, kAxes> base{0.9, 1.4, 0.5};     // the table's geometry
  std::array<std::vector<double>, kAxes> nodes;       // per axis, increasing, the base among them
  std::vector<double> tau, a_e, a_d, x;               // coarse nodes (the cross terms' too)
  // Per axis, finer (a_e, a_d) nodes than these, among the table's and holding these (empty: these).
  // The dermis ratio's, 0.25 apart in sqrt a above 0.4, since 2026-12-05: its offset's far field
  // changes its fall with x several-fold between a_e 0.4 and 1.28, and read across them was 10-51 %
  // off a Monte Carlo (docs/accurate-solver.md, sec. 4).
  std::array<std::vector<double>, kAxes> axis_a_e, axis_a_d;
  const std::vector<double>& a_e_of(int axis) const { return axis_a_e[static_cast<std::size_t>(axis)].empty() ? a_e : axis_a_e[static_cast<std::size_t>(axis)]; }
  const std::vector<double>& a_d_of(int axis) const { return axis_a_d[static_cast<std::size_t>(axis)].empty() ? a_d : axis_a_d[static_cast<std::size_t>(axis)]; }
  // The row of the light from below of (tau, a_e, a_d) at these (coarse) nodes' indices in the
  // axis' own nodes (d_low[axis][j] + row * x.size()), and of the top layer (d_top).
  std::size_t low_row(int axis, std::size_t i_tau, std::size_t i_e, std::size_t i_d) const;
  std::size_t top_row(int axis, std::size_t i_tau, std::size_t i_e) const;
  // Per axis and node (empty at the base), on the axis' nodes (a_e_of, a_d_of):
  // [(i_tau * n_e + i_e) * x.size() + i_x] and [((i_tau * n_e + i_e) * n_d + i_d) * x.size() + i_x].
  // The top layer does not depend on the dermis: no top offsets on that axis.
  std::array<std::vector<std::vector<double>>, kAxes> d_top, d_low;
  // Per axis and node: 1 where its light from below was solved on its own (the file's
  // `# AXIS_low_solved` line; compute() sets it), 0 where it is the difference of two solved profiles
  // (the nodes computed before 2026-12-05), which settle() holds near the beam.
  std::array<std::vector<char>, kAxes> low_solved;
  // The cross terms of pairs of axes (none: another dermis ratio is not combined with another g
  // or index). The built-in offsets' are data/skin_stack_cross.csv, settled.
  const SkinStackCross* cross = nullptr;

  // The built-in nodes (data/skin_stack_offsets.csv) for `table`, without values.
  static SkinStackOffsets default_nodes(const SkinStackTable& table);
  // Computes the offsets against `table` (whose nodes must include these). With `reuse`, the rows
  // of each axis node it holds (the same tau and (tau, a_e, a_d) among its nodes for that axis) are
  // copied and only the others solved (all of a node whose light from below it holds as a
  // difference, low_solved 0: such a node is solved again, the present way).
  void compute(const SkinStackTable& table, const util::ProgressCallback& progress = {},
               const SkinStackOffsets* reuse = nullptr);
  std::string to_csv() const;
  static SkinStackOffsets parse(std::string_view text, std::string_view source);
  // Holds the light-from-below offsets of the nodes whose light from below is the difference of
  // two profiles (low_solved 0) where that part is unreliable at a node of `table` (see the
  // .cpp). The built-in table's offsets (SkinStackTable::builtin().offsets) are
  // data/skin_stack_offsets.csv, settled.
  void settle(const SkinStackTable& table);

  // Why (g, eta, dermis_ratio) is not covered (empty when it is).
  std::string gap(double g, double eta, double dermis_ratio) const;
  // Adds the offsets at (tau, a_e, a_d) to `table`'s parts read there (`top`, `low`, at the
  // table's x nodes: this table's x are every k-th of them). With `with_cross`: the cross terms
  // when there are any, and with another dermis ratio the far field's rules (g and index offsets
  // held where the table's rows are near the solver's floor, the ratio's read from its node solves
  // there; docs/accurate-solver.md, sec. 4).
  void add(double t, double ae, double ad, double g, double eta, double dermis_ratio,
           const SkinStackTable& table, std::vector<double>& top, std::vector<double>& low,
           bool with_cross = true) const;
};

// Cross terms of the offsets, for two axes off the table's geometry at once (docs/accurate-
// solver.md, sec. 4). Per pair of axes ((g, eta), (g, dermis_ratio), (eta, dermis_ratio)) and per
// corner (the lower or upper end of each of the two axes): the parts solved there minus the
// table's parts with both axes' offsets added, on the offsets' (tau, a_e, a_d) nodes, at the
// offsets' x (held like the offsets where a part is below its threshold, and on reading where the
// corner's solve nears its floor: settle()). For
// values between the base and the ends each corner's term is scaled by the product of the two
// axes' positions from the base towards it (in ln(1 - g), eta and ln ratio: the term is 0 where
// either axis is at the base), and interpolated in (tau, a_e, a_d) like the offsets. On a side of
// an axis without corners (g above 0.9: not solved) the other side's corners are continued
// linearly through the base (a negative position), no farther than they are from it. The top
// layer does not depend on the dermis: top terms on (g, eta) only. The three axes' joint term is
// not tabulated (measured below 1.1 % of the profile where the pairs' are exact, sec. 4). Unlike
// the offsets they are not held where the light from below is small against the top layer's: both
// sides of the difference are computed on their own there (measured: holding them doubled the
// table's deviation from the solver at a corner's node, 0.3 to 0.95 %).
struct SkinStackCross {
  static constexpr int kPairs = 3;
  static constexpr std::array<std::array<int, 2>, kPairs> kPairAxes{{{0, 1}, {0, 2}, {1, 2}}};
  std::string provenance;
  std::array<double, SkinStackOffsets::kAxes> base{0.9, 1.4, 0.5};  // the table's geometry
  std::array<std::array<double, 2>, SkinStackOffsets::kAxes> ends{};  // per axis, lower and upper end
  std::vector<double> tau, a_e, a_d, x;  // coarse nodes (among the offsets'), the offsets' x
  // Per pair and corner (2 x (first axis at its upper end) + (second axis at its upper end)), laid
  // out as SkinStackOffsets::d_top and d_low; no top terms on pairs with the dermis ratio.
  std::array<std::array<std::vector<double>, 4>, kPairs> c_top, c_low;

  // The default nodes for `offsets` (their axes' ends and their coarse (tau, a_e, a_d) nodes, so
  // that at a node the offsets' values and the terms add up to the corner's solve exactly; between
  // nodes the terms are interpolated with the coarse nodes' weights, also where an axis' offsets
  // have finer nodes of their own), without values.
  static SkinStackCross default_nodes(const SkinStackOffsets& offsets);
  // Computes the terms against `table` and its offsets (table.offsets, whose own cross terms are
  // not used). progress(done, total) as SkinStackTable::compute; cancellable. With `reuse` (the
  // same base and nodes), the corners it holds with the same two values are copied (to solve a
  // corner again, leave it out of `reuse`). With `solve_pairs`, only the marked pairs' other
  // corners are solved; the other pairs' are 0, but for a corner on a side of an axis where
  // `reuse` had none (it continued the other side's through the base): that other side's corner
  // times the new end's position on it, so that the pair reads as before. Corners with the same top
  // layer (the dermis ratio's two ends) share its solve.
  void compute(const SkinStackTable& table, const util::ProgressCallback& progress = {},
               const SkinStackCross* reuse = nullptr, const std::array<bool, kPairs>* solve_pairs = nullptr);
  std::string to_csv() const;
  static SkinStackCross parse(std::string_view text, std::string_view source);
  // Holds each node's terms outside the x where its corner's part and the table's are both above
  // 1e-8 of the node's peak (the corners' solves near their floor: see the .cpp), 0 at a node
  // where they never are. `offsets` are the table's, settled, on these nodes (else logic_error).
  // The built-in terms are settled this way.
  void settle(const SkinStackTable& table, const SkinStackOffsets& offsets);
  // Makes terms computed against the offsets `from` those of the offsets `to` without solving the
  // corners again: a term is the corner's solve minus the table with both axes' offsets, so each
  // row changes by the two offsets' change at its corner and node. Before settle(); `from` and
  // `to` on these nodes and ends, settled as they were when the terms were computed (else
  // logic_error).
  void rebase(const SkinStackOffsets& from, const SkinStackOffsets& to);
  // The farthest value of `axis` a combined read reaches on `side` (0 below the base, 1 above):
  // the corners' end, or where a side has no corners (g above the table's 0.9 today), the other
  // side's end mirrored through the base in the axis' variable (ln(1 - g), the index, ln ratio),
  // whose terms add() continues linearly through the base there (docs/accurate-solver.md, sec. 4).
  double reach(int axis, std::size_t side) const;
  // The position of v from the base towards the end on `side` (1 at the end; negative on the
  // other side).
  double position(int axis, std::size_t side, double v) const;
  // Adds the pairs' terms at (tau, a_e, a_d) and the axes' values v to the offsets dt, dl (at x).
  void add(double t, double ae, double ad, const std::array<double, SkinStackOffsets::kAxes>& v,
           std::vector<double>& dt, std::vector<double>& dl) const;
};

// The profile of a stack in the table (gap() empty), as R(r) [1/mm^2] scaled to integrate to R_d.
// With an axis off the table's geometry (offsets added) the light from below is held within 0.3 tau
// of the beam at its value there (the solver does not resolve it nearer, and its split into the
// two parts rings there: docs/accurate-solver.md, sec. 4).
class SkinStackProfile {
 public:
  SkinStackProfile(const SkinStackTable& table, const physics::LayerStack& stack, double R_d);
  // A profile read from another table of the same kind (HalfSpaceTable): ln rho at the x nodes
  // `x` (odd in number, evenly spaced in ln x; kept by reference: the table's), in units of s
  // [1/mm], scaled to integrate to R_d.
  SkinStackProfile(const std::vector<double>& x, std::vector<double> ln_rho, double s, double R_d);
  double operator()(double r) const;

 private:
  void scale_to(double R_d);
  const std::vector<double>* x_;
  double s_ = 1, scale_ = 1;  // s [1/mm]; R(r) = scale_ exp(ln_rho(r s))
  double h_ = 1, cutoff_ = 0, power_ = -1, decay_ = 0;
  std::vector<double> ln_x_, ln_rho_;
};

}  // namespace skin::transport::accurate
