#include "constant_sets.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "input_error.hpp"
#include "sweep.hpp"
#include "driver.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::frontend {
namespace {

namespace fs = std::filesystem;

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

// One record into `set`. `file` names it in every message; a record is untrusted text, so its
// size and nesting are bounded and the values a message quotes are clipped (text_limits.hpp).
// The bytes of one record: a regular file of at most kMaxJsonBytes (a FIFO, /dev/zero or a
// directory is refused before anything is read).
std::string record_text(const std::string& file) {
  try {
    return read_input_file(file, kMaxJsonBytes, "a fit record");
  } catch (const InputFileError& e) {
    throw runner::InputError(std::string("--constants ") + e.what());
  }
}

// The record files `path` names: itself, or a directory's *.json files in name order. Entries
// that cannot be examined (a symbolic link loop, a name too long) are refused by name.
std::vector<std::string> record_files(const std::string& p) {
  std::error_code ec;
  const auto status = fs::status(p, ec);
  if (fs::is_directory(status)) {
    std::vector<std::string> files;
    fs::directory_iterator it(p, ec), end;
    if (ec)
      throw runner::InputError(
          fmt::format("--constants {}: cannot list the directory ({})", clip_text(p), ec.message()));
    for (; it != end; it.increment(ec)) {
      if (ec)
        throw runner::InputError(
            fmt::format("--constants {}: cannot list the directory ({})", clip_text(p), ec.message()));
      if (it->path().extension() != ".json") continue;
      std::error_code entry_ec;
      const bool regular = it->is_regular_file(entry_ec);
      if (entry_ec)
        throw runner::InputError(fmt::format("--constants {}: {} cannot be examined ({})", clip_text(p),
                                             quote(it->path().filename().string()), entry_ec.message()));
      if (regular) files.push_back(it->path().string());
    }
    if (files.empty())
      throw runner::InputError(fmt::format("--constants {}: the directory holds no fit record (*.json)", clip_text(p)));
    std::sort(files.begin(), files.end());
    return files;
  }
  if (fs::exists(status)) return {p};
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw runner::InputError(fmt::format("--constants {}: cannot be examined ({})", clip_text(p), ec.message()));
  throw runner::InputError(fmt::format(
      "--constants {}: no such file or directory (a fit record, a directory of them, or 'published')", clip_text(p)));
}

void load_record(const std::string& file, ConstantSet& set) {
  const std::string text = record_text(file);
  if (const auto error = json_nesting_error(text))
    throw runner::InputError(fmt::format("--constants {}: {}", file, *error));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw runner::InputError(fmt::format("--constants {}: not valid JSON: {}", file, clip_text(e.what(), 400)));
  }
  if (!j.is_object()) throw runner::InputError(fmt::format("--constants {}: a fit record must be a JSON object", file));
  if (!j.contains("fit") || !j["fit"].is_string())
    throw runner::InputError(
        fmt::format("--constants {}: key 'fit': missing or not a string (the `sglab fit` name)", file));
  const std::string fit_name = j["fit"].get<std::string>();
  const fit::Fitter* f = fit::find_fitter(fit_name);
  if (!f) {
    std::vector<std::string> names;
    for (const auto& g : fit::fitters()) names.push_back(g.name);
    throw runner::InputError(
        fmt::format("--constants {}: key 'fit': unknown fit '{}' (fits: {})", file, clip_text(fit_name), join(names)));
  }
  if (!j.contains("parameters") || !j["parameters"].is_object())
    throw runner::InputError(fmt::format("--constants {}: key 'parameters': missing or not an object", file));
  const auto& params = j["parameters"];
  std::vector<std::string> known = f->parameters;
  known.insert(known.end(), f->derived.begin(), f->derived.end());
  for (const auto& [key, value] : params.items()) {
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw runner::InputError(
          fmt::format("--constants {}: key 'parameters.{}': unknown parameter of fit '{}' (parameters: {})", file,
                      clip_text(key), fit_name, join(known)));
    if (!value.is_number())
      throw runner::InputError(
          fmt::format("--constants {}: key 'parameters.{}': not a number ({})", file, key,
                      clip_text(value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace))));
  }
  for (const auto& name : f->parameters)
    if (!params.contains(name))
      throw runner::InputError(fmt::format("--constants {}: key 'parameters.{}': missing (fit '{}' needs {})", file,
                                           name, fit_name, join(f->parameters)));

  std::string provenance = fmt::format("{}: fit {}", file, fit_name);
  if (j.contains("objective") && j["objective"].is_string())
    provenance += ", objective " + clip_text(j["objective"].get<std::string>(), 300);
  else provenance += ", objective not stated (hand-written)";
  if (j.contains("precision") && j["precision"].is_string())
    provenance += ", precision " + clip_text(j["precision"].get<std::string>());

  const auto uses = fit::registry_parameters(*f);
  for (const auto& name : f->parameters) {
    const double v = params[name].get<double>();
    // The domain of every registry parameter this value feeds (all finite; most positive).
    for (const auto& u : uses) {
      if (u.parameter->name != name) continue;
      if (const auto error = column_value_error(Column{name, u.parameter->kind, ""}, v))
        throw runner::InputError(fmt::format("--constants {}: key 'parameters.{}': {} (it is a constant of {})", file,
                                             name, *error, u.user));
    }
    if (!std::isfinite(v))
      throw runner::InputError(fmt::format("--constants {}: key 'parameters.{}': not a finite number", file, name));
    set.set({fit_name, name, v, provenance});
  }
}

}  // namespace

ConstantSet load_constant_sets(const std::vector<std::string>& paths) {
  ConstantSet set;
  for (const auto& p : paths) {
    if (p == "published") {
      set.values.clear();
      continue;
    }
    // Within one directory no two records may set the same constant: which one wins would
    // depend on file names, not on the user's order of --constants.
    std::map<std::pair<std::string, std::string>, std::string> set_by;  // (fit, name) → record
    for (const auto& f : record_files(p)) {
      ConstantSet record;
      load_record(f, record);
      for (const auto& v : record.values) {
        const auto [it, fresh] = set_by.emplace(std::pair(v.fit, v.name), f);
        if (!fresh)
          throw runner::InputError(fmt::format("--constants {}: {}.{} is set by two records ({} and {}); keep one",
                                               clip_text(p), v.fit, v.name, quote(it->second), quote(f)));
        set.set(v);
      }
    }
  }
  return set;
}

std::string constants_fingerprint(const std::vector<std::string>& paths) {
  std::string text;
  for (const auto& p : paths) {
    text += "constants " + p + "\n";
    if (p == "published") continue;
    for (const auto& f : record_files(p)) text += f + "\n" + record_text(f) + "\n";
  }
  return runner::fnv1a_hex(text);
}

const char* const kConstantsOptionHelp =
    "constant set: a fit record (`sglab fit NAME --json`), a directory of them, or 'published'; "
    "repeatable, later sets override earlier ones";

void add_constants_option(CLI::App& app, std::vector<std::string>& paths, const std::string& what) {
  app.add_option("--constants", paths, what)->take_all()->allow_extra_args(false);
}

Constants read_constants(const std::vector<std::string>& paths) {
  Constants c;
  c.paths = paths;
  c.set = load_constant_sets(paths);
  if (!paths.empty()) c.fingerprint = constants_fingerprint(paths);
  return c;
}

void add_constants_option(CLI::App& app, Constants& constants, const std::string& what) {
  app.add_option_function<std::vector<std::string>>(
         "--constants", [&constants](const std::vector<std::string>& paths) { constants = read_constants(paths); },
         what)
      ->take_all()
      ->allow_extra_args(false);
}

std::vector<std::string> constants_arguments(const std::vector<std::string>& paths) {
  std::vector<std::string> a;
  for (const auto& p : paths) a.insert(a.end(), {"--constants", p});
  return a;
}

double standalone_value(const ConstantSet& set, std::string_view user, std::string_view name) {
  const Parameter* p = find_standalone_constant(user, name);
  if (!p) throw std::logic_error(fmt::format("no standalone constant {} of {}", name, user));
  return set.value(*p);
}

namespace {
std::string provenance_of(const ConstantSet& set, const Parameter& p) {
  const ConstantValue* v = p.fit.empty() ? nullptr : set.find(p.fit, p.name);
  return v ? v->provenance : "published: " + p.source;
}
}  // namespace

nlohmann::json constants_json(const ConstantSet& set, const std::vector<ConstantUse>& uses) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& u : uses)
    a.push_back({{"user", u.user},
                 {"fit", u.parameter->fit},
                 {"name", u.parameter->name},
                 {"value", set.value(*u.parameter)},
                 {"published", u.parameter->published},
                 {"provenance", provenance_of(set, *u.parameter)}});
  return a;
}

std::string constants_text(const ConstantSet& set, const std::vector<ConstantUse>& uses, const std::string& prefix) {
  std::string s;
  for (const auto& u : uses)
    s += fmt::format("{}{} {}.{} = {:.17g} ({})\n", prefix, u.user, u.parameter->fit, u.parameter->name,
                     set.value(*u.parameter), provenance_of(set, *u.parameter));
  return s;
}

std::vector<ConstantUse> method_constant_uses(const std::string& user, const Method& m) {
  std::vector<ConstantUse> out;
  for (const auto& p : m.parameters) out.push_back({user, &p});
  return out;
}

}  // namespace sglab::frontend
