// The parameter sets of a batch run: include/skin/batch/sets.hpp.
#include "skin/batch/sets.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "skin/util/cancel.hpp"
#include "skin/util/charconv.hpp"
#include "skin/util/error.hpp"

namespace skin::batch {

using skin::util::InputError;
using skin::util::Table;

using skin::physics::ParameterNames;
using skin::physics::SkinParameters;
using skin::physics::parameter_info;

namespace {

double parse_number(std::string_view text, const std::string& what) {
  double v = 0;
  const char* end = text.data() + text.size();
  const auto r = skin::util::from_chars(text.data(), end, v);
  if (text.empty() || r.ec != std::errc() || r.ptr != end || !std::isfinite(v))
    throw InputError(what + ": '" + std::string(text) + "' is not a finite number");
  return v;
}

}  // namespace

double Sweep::operator[](std::size_t i) const {
  // (The last value is STOP itself: start + (stop - start) can round to a neighbour of stop, as
  // 0.001 + (0.2 - 0.001) does; the fuzzer found it.)
  if (count == 1) return start;
  if (i + 1 == count) return stop;
  return start + (stop - start) * static_cast<double>(i) / static_cast<double>(count - 1);
}

Sweep parse_sweep(std::string_view spec) {
  const std::string what = "sweep = '" + std::string(spec) + "'";
  const auto eq = spec.find('=');
  const auto c1 = spec.find(':', eq == std::string_view::npos ? 0 : eq);
  const auto c2 = c1 == std::string_view::npos ? c1 : spec.find(':', c1 + 1);
  if (eq == std::string_view::npos || c1 == std::string_view::npos || c2 == std::string_view::npos)
    throw InputError(what + " must look like KEY=START:STOP:COUNT (e.g. melanin=0:0.5:21)");
  Sweep s;
  s.info = &parameter_info(spec.substr(0, eq));
  s.start = parse_number(spec.substr(eq + 1, c1 - eq - 1), what + ", START");
  s.stop = parse_number(spec.substr(c1 + 1, c2 - c1 - 1), what + ", STOP");
  const std::string_view count = spec.substr(c2 + 1);
  const double n = parse_number(count, what + ", COUNT");
  if (n < 1 || n > 1e9 || n != std::floor(n))
    throw InputError(what + ": COUNT = " + std::string(count) +
                     " is out of range: must be a whole number in [1, 1e9]");
  s.count = static_cast<std::size_t>(n);
  // The range is an interval: both ends inside it put every value inside.
  s.info->check(s.start);
  s.info->check(s.stop);
  return s;
}

std::pair<std::size_t, std::size_t> parse_rows(std::string_view spec, std::size_t count) {
  const std::string what = "rows = '" + std::string(spec) + "'";
  const auto colon = spec.find(':');
  auto whole = [&](std::string_view t) {
    const double v = parse_number(t, what);
    if (v < 0 || v != std::floor(v) || v > 1e15)
      throw InputError(what + ": '" + std::string(t) + "' is not a whole number >= 0");
    return static_cast<std::size_t>(v);
  };
  if (colon == std::string_view::npos)
    throw InputError(what + " must look like FIRST:END (sets FIRST to END - 1, from 0)");
  const std::size_t a = whole(spec.substr(0, colon)), b = whole(spec.substr(colon + 1));
  if (b < a) throw InputError(what + ": need FIRST <= END");
  return {std::min(a, count), std::min(b, count)};
}

SkinParameters Sets::at(std::size_t i) const {
  SkinParameters p = base;
  for (std::size_t k = 0; k < keys.size(); ++k)
    if (const double v = value(k, i); !std::isnan(v)) p.*(keys[k]->member) = v;
  return p;
}

void Sets::validate(std::size_t first, std::size_t end) const {
  for (std::size_t i = first; i < end; ++i) {
    if ((i - first) % 4096 == 0) util::cancel::check();  // (a million sets take seconds under ASan)
    try {
      at(i).validate();
    } catch (const InputError& e) {
      throw InputError(source + ": set " + std::to_string(i) + ": " + e.what());
    }
  }
}

Sets sets_from_table(const Table& table, const SkinParameters& base) {
  Sets sets;
  sets.base = base;
  ParameterNames names(table.source + ": column");
  for (const std::string& name : table.columns) sets.keys.push_back(&names.add(name));
  sets.count = table.rows();
  sets.value = [t = &table](std::size_t k, std::size_t i) { return t->data[k][i]; };
  sets.source = table.source;
  return sets;
}

Sets sets_from_sweeps(const std::vector<Sweep>& sweeps, const SkinParameters& base) {
  Sets sets;
  sets.base = base;
  sets.count = 1;
  for (const Sweep& s : sweeps) {
    if (std::find(sets.keys.begin(), sets.keys.end(), s.info) != sets.keys.end())
      throw InputError(std::string(s.info->key) + " is swept twice");
    if (sets.count > std::size_t(1e12) / s.count) throw InputError("the sweeps make more than 1e12 sets");
    sets.count *= s.count;
    sets.keys.push_back(s.info);
  }
  // Row-major over the sweeps: the last varies fastest.
  sets.value = [s = &sweeps](std::size_t k, std::size_t i) {
    for (std::size_t j = s->size(); j-- > k + 1;) i /= (*s)[j].count;
    return (*s)[k][i % (*s)[k].count];
  };
  sets.source = "--sweep";
  return sets;
}

}  // namespace skin::batch
