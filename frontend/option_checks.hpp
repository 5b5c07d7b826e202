// The checks of a command's options, shared by every `sglab` command (cli/, an experiment's own
// command) and the options the Python module passes through: CLI11 validators for integers,
// numbers, shards and names from a registry, and the --out/--tables-dir pair; with the runner's
// input error (bad input: the message names the value, exit status 2).
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "input_error.hpp"
#include "names.hpp"
#include "run_context.hpp"
#include "sglab/registry.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::frontend {

// A CLI11 check for an unsigned integer option: decimal digits only (no sign, so "-1" is not
// wrapped to 2^64 − 1), no overflow (2^64 is not saturated), at most `max`.
inline CLI::Validator unsigned_at_most(std::uint64_t max) {
  return CLI::Validator(
      [max](std::string& text) -> std::string {
        std::uint64_t v = 0;
        const char* end = text.data() + text.size();
        const auto r = std::from_chars(text.data(), end, v);
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || r.ec != std::errc() ||
            r.ptr != end || v > max)
          return fmt::format("{} is not an integer in [0, {}]", clip_text(text), max);
        return {};
      },
      fmt::format("INT in [0, {}]", max));
}

// A CLI11 check for an option that takes a name: the value is one of `names` (with `comma_list`
// each item of a comma-separated list; with `before_colon` the part before ':', as in fis:64).
// The help lists the names; an unknown one is refused (exit status 2) with the closest valid name.
inline CLI::Validator one_of(std::vector<std::string> names, std::string what, bool comma_list = false,
                             bool before_colon = false) {
  const std::string description = "{" + runner::join_names(names, "|") + "}";
  return CLI::Validator(
      [names = std::move(names), what = std::move(what), comma_list, before_colon](std::string& text) -> std::string {
        std::vector<std::string> items;
        for (std::size_t start = 0;;) {
          const std::size_t end = comma_list ? text.find(',', start) : std::string::npos;
          items.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
          if (end == std::string::npos) break;
          start = end + 1;
        }
        for (std::string item : items) {
          if (before_colon) item = item.substr(0, item.find(':'));
          bool known = false;
          for (const auto& n : names) known = known || n == item;
          if (!known) return runner::unknown_name_message(what, item, names);
        }
        return {};
      },
      description);
}

// The registry's quantities, and a quantity's methods, by name (help texts and messages).
inline std::vector<std::string> quantity_names() {
  std::vector<std::string> names;
  for (const auto& q : quantities()) names.push_back(q.name);
  return names;
}
inline std::vector<std::string> method_names(const Quantity& q) {
  std::vector<std::string> names;
  for (const auto& m : q.methods) names.push_back(m.name);
  return names;
}
// "QUANTITY: METHOD, …" per quantity, one line each (the help of a --method option).
inline std::string methods_per_quantity() {
  std::string text;
  for (const auto& q : quantities()) text += "\n  " + q.name + ": " + runner::join_names(method_names(q));
  return text;
}

// A CLI11 check for an integer option in [lo, hi]: an optional minus sign and decimal digits, no
// overflow. The message quotes the clipped text (a 100 KB value gives an 80-character quote).
inline CLI::Validator integer_in(std::int64_t lo, std::int64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        std::int64_t v = 0;
        const char* end = text.data() + text.size();
        const auto r = std::from_chars(text.data(), end, v);
        if (text.empty() || r.ec != std::errc() || r.ptr != end || v < lo || v > hi)
          return fmt::format("{} is not an integer in [{}, {}]", quote(text), lo, hi);
        return {};
      },
      fmt::format("INT in [{}, {}]", lo, hi));
}

// A CLI11 check for a real option: a finite decimal number (no "nan", "inf", hexadecimal or
// trailing text) in [lo, hi].
inline CLI::Validator finite_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0;
        const char* end = text.data() + text.size();
        const auto r = std::from_chars(text.data(), end, v, std::chars_format::general);
        if (text.empty() || r.ec != std::errc() || r.ptr != end || !std::isfinite(v) || v < lo || v > hi)
          return fmt::format("{} is not a finite number in [{:g}, {:g}]", quote(text), lo, hi);
        return {};
      },
      fmt::format("NUMBER in [{:g}, {:g}]", lo, hi));
}

// A CLI11 check for `--shard i/N` given explicitly: an empty text is refused (it would otherwise
// read as "not given" and run the whole grid); parse_shard (sweep.hpp) checks the rest.
inline CLI::Validator shard_given() {
  return CLI::Validator(
      [](std::string& text) -> std::string { return text.empty() ? "an empty shard (expected i/N, 0 ≤ i < N)" : ""; },
      "i/N");
}

// The two places an experiment's command writes to, declared alike by every command that has
// both: `--out DIR` for its per-run outputs (CSVs, images), by default the run's OUT/DIR_NAME, and
// TABLES_OPTION DIR for its tables ("--tables-dir"; "--tables" in the older commands), by default
// the run's tables directory (empty: beside --out; runner/run_context.hpp Places), each described
// by what it holds, with its default shown.
inline void add_places_options(CLI::App& app, const runner::Places& places, std::string_view dir_name, std::string& out,
                               std::string& tables_dir, const std::string& out_holds, const std::string& tables_holds,
                               const char* tables_option = "--tables-dir") {
  out = places.dir(dir_name);
  tables_dir = places.tables;
  app.add_option("--out", out, out_holds)->capture_default_str();
  app.add_option(tables_option, tables_dir, tables_holds)->capture_default_str();
}

// `--tables-dir DIR` of a command that writes only tables: by default the run's tables directory,
// else OUT/DIR_NAME (Places::tables_or_dir).
inline void add_tables_option(CLI::App& app, const runner::Places& places, std::string_view dir_name,
                              std::string& tables_dir, const std::string& holds) {
  tables_dir = places.tables_or_dir(dir_name);
  app.add_option("--tables-dir", tables_dir, holds)->capture_default_str();
}

}  // namespace sglab::frontend
