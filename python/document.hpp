#pragma once
// The documents of src/schema (the `skin` command's JSON) as Python objects, without JSON text in
// between: the results of the module's functions are these documents, converted.
#include <cstddef>
#include <functional>
#include <string_view>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "schema.hpp"

namespace skin::python {

namespace py = pybind11;
using Shape = std::vector<py::ssize_t>;

// Objects as dicts (keys in order); arrays of numbers (nested, rectangular, not empty; not bool)
// as numpy arrays, float64 or, when every number is an integer, int64 (Arrays::lists: as lists);
// other arrays as lists; numbers, strings, true/false and null as Python's.
enum class Arrays { numpy, lists };
py::object to_python(const schema::json& j, Arrays arrays = Arrays::numpy);

// The documents of several sets, document(i) for i in [0, count) (count = the product of
// `shape`), one at a time, as one dict shaped like one of them: where shared(path) (a key's path,
// "parameters.melanin"), the first set's value; elsewhere a number or an array of numbers becomes
// an array of shape `shape` + its own, strings a numpy array of str, true/false one of bool, and
// other values (lists, null) an object array. Every document has the same keys and array sizes
// (std::logic_error otherwise: the schema gave sets different forms).
py::object stack_to_python(const Shape& shape, const std::function<schema::json(std::size_t)>& document,
                           const std::function<bool(std::string_view path)>& shared);

}  // namespace skin::python
