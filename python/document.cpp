// The schema's documents as Python objects (document.hpp).
#include "document.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace skin::python {

namespace {

using namespace pybind11::literals;
using schema::json;

// The shape of j's first elements, nested (empty: not an array, or an empty one).
Shape first_shape(const json& j) {
  Shape shape;
  for (const json* x = &j; x->is_array() && !x->empty(); x = &(*x)[0])
    shape.push_back(static_cast<py::ssize_t>(x->size()));
  return shape;
}

// Whether j is an array of numbers of `shape` (a number when depth == shape.size()); `integers`
// becomes false where a number is not an integer.
bool numeric_array_of_shape(const json& j, const Shape& shape, std::size_t depth, bool& integers) {
  if (depth == shape.size()) {
    if (!j.is_number()) return false;  // (is_number is false for bool)
    integers = integers && !j.is_number_float();
    return true;
  }
  if (!j.is_array() || static_cast<py::ssize_t>(j.size()) != shape[depth]) return false;
  for (const json& x : j)
    if (!numeric_array_of_shape(x, shape, depth + 1, integers)) return false;
  return true;
}

template <class T>
void flatten(const json& j, T*& out) {
  if (j.is_array()) {
    for (const json& x : j) flatten(x, out);
  } else {
    *out++ = j.get<T>();
  }
}

std::size_t elements(const Shape& shape) {
  std::size_t n = 1;
  for (auto d : shape) n *= static_cast<std::size_t>(d);
  return n;
}

Shape concat(Shape a, const Shape& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// A value of the stacked documents: the first set's (shared), an object of them, the numbers of
// every set in one array, or any other value of every set.
struct Node {
  enum class Kind { shared, object, numbers, values } kind = Kind::values;
  py::object value;                                   // shared
  std::vector<std::pair<std::string, Node>> children;  // object, in the documents' key order
  Shape leaf;                                         // numbers: the shape of each set's block
  bool integers = false;
  py::array array;                                    // numbers: shape (sets..., leaf...)
  std::vector<py::object> values;                     // values: one per set
};

[[noreturn]] void differs(const std::string& path, std::size_t set, const std::string& what) {
  throw std::logic_error("stack_to_python: set " + std::to_string(set) + "'s " + path + " " + what +
                         " (the sets' documents must have one form)");
}

Node plan(const json& j, const std::string& path, const Shape& shape,
          const std::function<bool(std::string_view)>& shared) {
  Node n;
  if (!path.empty() && shared(path)) {
    n.kind = Node::Kind::shared;
    n.value = to_python(j);
    return n;
  }
  if (j.is_object()) {
    n.kind = Node::Kind::object;
    for (auto it = j.begin(); it != j.end(); ++it)
      n.children.emplace_back(it.key(), plan(*it, path.empty() ? it.key() : path + "." + it.key(), shape, shared));
    return n;
  }
  const Shape leaf = first_shape(j);
  bool integers = true;
  if ((j.is_number() || !leaf.empty()) && numeric_array_of_shape(j, leaf, 0, integers)) {
    n.kind = Node::Kind::numbers;
    n.leaf = leaf;
    n.integers = integers;
    if (integers)
      n.array = py::array_t<std::int64_t>(concat(shape, leaf));
    else
      n.array = py::array_t<double>(concat(shape, leaf));
    return n;
  }
  n.kind = Node::Kind::values;
  n.values.resize(elements(shape));
  return n;
}

void fill(Node& n, const json& j, std::size_t set, const std::string& path) {
  switch (n.kind) {
    case Node::Kind::shared: return;
    case Node::Kind::object: {
      if (!j.is_object() || j.size() != n.children.size()) differs(path, set, "has other keys");
      for (auto& [key, child] : n.children) {
        const auto it = j.find(key);
        if (it == j.end()) differs(path, set, "lacks " + key);
        fill(child, *it, set, path.empty() ? key : path + "." + key);
      }
      return;
    }
    case Node::Kind::numbers: {
      bool integers = true;
      if (!numeric_array_of_shape(j, n.leaf, 0, integers) || (n.integers && !integers))
        differs(path, set, "is not an array of numbers of the first set's shape");
      const std::size_t block = elements(n.leaf);
      if (n.integers) {
        std::int64_t* out = static_cast<std::int64_t*>(n.array.mutable_data()) + set * block;
        flatten(j, out);
      } else {
        double* out = static_cast<double*>(n.array.mutable_data()) + set * block;
        flatten(j, out);
      }
      return;
    }
    case Node::Kind::values: n.values[set] = to_python(j); return;
  }
}

py::object finish(Node& n, const Shape& shape) {
  switch (n.kind) {
    case Node::Kind::shared: return std::move(n.value);
    case Node::Kind::object: {
      py::dict d;
      for (auto& [key, child] : n.children) d[py::str(key)] = finish(child, shape);
      return std::move(d);
    }
    case Node::Kind::numbers: return std::move(n.array);
    case Node::Kind::values: break;
  }
  py::module_ np = py::module_::import("numpy");
  bool strings = true, bools = true;
  for (const py::object& v : n.values) {
    strings = strings && py::isinstance<py::str>(v);
    bools = bools && py::isinstance<py::bool_>(v);
  }
  py::list list;
  for (const py::object& v : n.values) list.append(v);
  if (strings) return np.attr("array")(list, "dtype"_a = "str").attr("reshape")(py::cast(shape));
  if (bools) return np.attr("array")(list, "dtype"_a = "bool").attr("reshape")(py::cast(shape));
  py::array objects = np.attr("empty")(n.values.size(), "dtype"_a = "object");
  for (std::size_t i = 0; i < n.values.size(); ++i) objects[py::int_(i)] = n.values[i];
  return objects.attr("reshape")(py::cast(shape));
}

}  // namespace

py::object to_python(const json& j, Arrays arrays) {
  switch (j.type()) {
    case json::value_t::null: return py::none();
    case json::value_t::boolean: return py::bool_(j.get<bool>());
    case json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case json::value_t::number_float: return py::float_(j.get<double>());
    case json::value_t::string: return py::str(j.get_ref<const std::string&>());
    case json::value_t::object: {
      py::dict d;
      for (auto it = j.begin(); it != j.end(); ++it) d[py::str(it.key())] = to_python(*it, arrays);
      return std::move(d);
    }
    case json::value_t::array: {
      const Shape shape = first_shape(j);  // along the first elements; every element must match it
      bool integers = true;
      if (arrays == Arrays::numpy && !shape.empty() && numeric_array_of_shape(j, shape, 0, integers)) {
        if (integers) {
          py::array_t<std::int64_t> a(shape);
          std::int64_t* out = a.mutable_data();
          flatten(j, out);
          return std::move(a);
        }
        py::array_t<double> a(shape);
        double* out = a.mutable_data();
        flatten(j, out);
        return std::move(a);
      }
      py::list l;
      for (const json& x : j) l.append(to_python(x, arrays));
      return std::move(l);
    }
    default: throw std::logic_error("to_python: a JSON value of no JSON type");  // binary, discarded
  }
}

py::object stack_to_python(const Shape& shape, const std::function<json(std::size_t)>& document,
                           const std::function<bool(std::string_view path)>& shared) {
  const std::size_t count = elements(shape);
  if (shape.empty()) return to_python(document(0));
  Node root;
  for (std::size_t i = 0; i < count; ++i) {
    // Ctrl-C while a million documents are converted (seconds with the GIL held)
    if (i % 4096 == 0 && PyErr_CheckSignals() != 0) throw py::error_already_set();
    const json j = document(i);
    if (i == 0) root = plan(j, "", shape, shared);
    fill(root, j, i, "");
  }
  return finish(root, shape);
}

}  // namespace skin::python
