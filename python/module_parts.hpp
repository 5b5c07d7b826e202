// The parts of the native module that live in files of their own (sglab_module.cpp defines the
// module and the registry, fit and render functions; eval_binding.cpp the evaluation).
#pragma once

#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "sglab/registry.hpp"

namespace sglab::python {

namespace py = pybind11;

// The named quantity, or its method; py::value_error naming the valid ones (sglab_module.cpp).
const Quantity& quantity_named(const std::string& name);
const Method& method_named(const Quantity& q, const std::string& name);

// float32 or float64 arrays of one broadcast shape (the Python side broadcasts and casts) →
// a new C-contiguous array of that shape and dtype; `vectorized`: every method through its batch
// evaluator (eval_binding.cpp, where the details are).
template <class T>
py::array_t<T> eval_numeric(const std::string& quantity, const std::string& method,
                            const std::vector<py::array>& columns, const std::vector<std::string>& constants,
                            bool vectorized);
extern template py::array_t<float> eval_numeric<float>(const std::string&, const std::string&,
                                                       const std::vector<py::array>&, const std::vector<std::string>&,
                                                       bool);
extern template py::array_t<double> eval_numeric<double>(const std::string&, const std::string&,
                                                         const std::vector<py::array>&, const std::vector<std::string>&,
                                                         bool);
// mp50: each column a flat list of decimal strings or Python floats; the values as 50-digit strings.
std::vector<std::string> eval_mp50(const std::string& quantity, const std::string& method,
                                   const std::vector<std::vector<py::object>>& columns,
                                   const std::vector<py::ssize_t>& shape, const std::vector<std::string>& constants);

}  // namespace sglab::python
