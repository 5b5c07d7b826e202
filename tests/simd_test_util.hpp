// Helpers shared by the SIMD tests (simd_test.cpp, simd_specular_test.cpp): the registry's method
// behind a name of simd::vectorized_methods(), its tolerance, and a method's batch evaluator in T.
#pragma once

#include <map>
#include <span>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

#include "sglab/registry.hpp"

namespace sglab::test {

struct QuantityMethod {
  const Quantity* quantity = nullptr;
  const Method* method = nullptr;
};

// The quantity and method named "quantity/method"; a test failure (and nullptrs) if either is missing.
inline QuantityMethod find_quantity_method(const std::string& name) {
  const auto slash = name.find('/');
  QuantityMethod r;
  r.quantity = find_quantity(name.substr(0, slash));
  if (r.quantity) r.method = r.quantity->find(name.substr(slash + 1));
  EXPECT_NE(r.method, nullptr) << "no method " << name << " in the registry";
  return r;
}

// A test's tolerances k (ulps) per "quantity/method" name, each with its reason beside it.
using UlpsTable = std::map<std::string, double>;

// k of the vectorized method `name`; a test failure naming it (and k = 0) where the table has none.
inline double ulps_for(const UlpsTable& table, const std::string& name) {
  const auto it = table.find(name);
  EXPECT_NE(it, table.end()) << "no tolerance for " << name << " (a vectorized method needs one, with its reason)";
  return it == table.end() ? 0 : it->second;
}

// m's batch evaluator for T (float or double) over rows of `arity` arguments.
template <class T>
void batch_as(const Method& m, std::span<const T> args, std::size_t arity, std::span<T> out) {
  if constexpr (std::is_same_v<T, float>) m.batch_float(args, arity, out);
  else m.batch_double(args, arity, out);
}

}  // namespace sglab::test
