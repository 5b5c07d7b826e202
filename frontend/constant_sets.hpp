// Constant sets on the command line: `--constants PATH` (repeatable, later sets override earlier
// ones), where PATH is one fit record (the JSON `sglab fit NAME --json FILE` writes; a hand-written
// {"fit": "lambda-d", "parameters": {"lambda_d": 3.25}} is enough), a directory of them (what
// `sglab fit all --json-dir DIR` writes), or `published` (every constant back to its published
// value). The set replaces the published constants of the registry's methods (sglab::bind), the
// renderer's λ_d and the filter's λ_c; every command that takes it names the set in its output.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "sglab/registry.hpp"

namespace sglab::frontend {

// The sets named by --constants, in order. Bad input (unreadable or malformed file, unknown fit,
// unknown or missing parameter, a value that is not a number or is outside the parameter's
// domain) is an InputError naming the file and the key, raised before anything is written.
ConstantSet load_constant_sets(const std::vector<std::string>& paths);

// The fingerprint (FNV-1a) of the sets' contents: every record file the paths name, with its
// bytes. Part of what checkpoints, sweep manifests and reproduce markers compare, so that an
// edited record is another run, never a stale result. Throws InputError as load_constant_sets.
std::string constants_fingerprint(const std::vector<std::string>& paths);

// A command's constant set, read once where the command line is parsed (add_constants_option) and
// passed down to everything the command runs: nothing below reads a record again.
struct Constants {
  std::vector<std::string> paths;  // --constants, as given, in order (provenance: constants_arguments)
  ConstantSet set;                 // their values (load_constant_sets)
  std::string fingerprint;         // of their contents (constants_fingerprint); "" when no path is given
  bool given() const { return !paths.empty(); }
};
// Reads the sets (InputError as load_constant_sets).
Constants read_constants(const std::vector<std::string>& paths);

// Adds `--constants PATH` (repeatable); `what` is its help line (the default describes a constant
// set; `sglab reproduce` says which of its steps get it). Bound to `paths` the option only keeps
// the paths (reproduce passes them on); bound to `constants` it reads the sets when the command
// line is parsed, so that a bad set is refused (exit status 2) before the command runs.
extern const char* const kConstantsOptionHelp;
void add_constants_option(CLI::App& app, std::vector<std::string>& paths,
                          const std::string& what = kConstantsOptionHelp);
void add_constants_option(CLI::App& app, Constants& constants, const std::string& what = kConstantsOptionHelp);
// The option back as arguments (provenance, reproduce's steps).
std::vector<std::string> constants_arguments(const std::vector<std::string>& paths);
inline std::vector<std::string> constants_arguments(const Constants& c) { return constants_arguments(c.paths); }

// The value of a standalone constant (user "render" or "filter", see sglab::constant_uses) in the
// set, and its provenance.
double standalone_value(const ConstantSet& set, std::string_view user, std::string_view name);

// Each constant of `uses` with its value and provenance ("published: SOURCE" or the set's), as a
// JSON array of {user, fit, name, value, published, provenance}.
nlohmann::json constants_json(const ConstantSet& set, const std::vector<ConstantUse>& uses);
// The same as text lines "USER FIT.NAME = VALUE (PROVENANCE)", one per constant, each prefixed.
std::string constants_text(const ConstantSet& set, const std::vector<ConstantUse>& uses, const std::string& prefix);
// The constants of one method (its registry parameters), as uses.
std::vector<ConstantUse> method_constant_uses(const std::string& user, const Method& m);

}  // namespace sglab::frontend
