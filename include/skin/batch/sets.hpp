#pragma once
// The parameter sets of a batch run (`skin batch`): a table with one column per parameter key
// (a CSV file), or the grid of one or more sweeps "KEY=START:STOP:COUNT", over a base set whose
// other values are fixed. Reading them is checked input: anything wrong is an InputError naming
// the file or the option and what is allowed.
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "skin/physics/skin_parameters.hpp"
#include "skin/util/table.hpp"

namespace skin::batch {

// "KEY=START:STOP:COUNT": COUNT values from START to STOP inclusive, evenly spaced. Both ends
// lie in the parameter's range (so every value does).
struct Sweep {
  const physics::ParameterInfo* info = nullptr;
  double start = 0, stop = 0;
  std::size_t count = 1;
  // Value i: exact at both ends, and the decimal a user types for the usual sweeps (0:0.5:21
  // gives 0.175, not 0.17500000000000002).
  double operator[](std::size_t i) const;
};
Sweep parse_sweep(std::string_view spec);

// [first, end) from "FIRST:END" (whole numbers, FIRST <= END), clamped to `count` sets.
std::pair<std::size_t, std::size_t> parse_rows(std::string_view spec, std::size_t count);

// Set i is `base` with the varying parameters `keys` replaced by value(k, i) (NaN: the base's).
struct Sets {
  physics::SkinParameters base;
  std::vector<const physics::ParameterInfo*> keys;
  std::size_t count = 0;
  std::function<double(std::size_t k, std::size_t i)> value;
  std::string source;  // for messages: the file, or "--sweep"

  physics::SkinParameters at(std::size_t i) const;
  // Validates sets [first, end): InputError "<source>: set i: ..." for the first bad one
  // (Cancelled when cancellation is requested: skin/util/cancel.hpp).
  void validate(std::size_t first, std::size_t end) const;
};

// One column per parameter key or symbol (a repeated parameter is an InputError). The sets refer
// to `table`, which must outlive them.
Sets sets_from_table(const util::Table& table, const physics::SkinParameters& base);
// The grid of the sweeps, row-major (the last varies fastest); at most 1e12 sets; a parameter
// swept twice is an InputError. The sets refer to `sweeps`, which must outlive them.
Sets sets_from_sweeps(const std::vector<Sweep>& sweeps, const physics::SkinParameters& base);

}  // namespace skin::batch
