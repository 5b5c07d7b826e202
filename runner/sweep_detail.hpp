// The sweep runner's file helpers shared by running (sweep.cpp) and merging (sweep_merge.cpp).
// Internal to the runner.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace sglab::runner::sweep_detail {

// A non-negative decimal integer, digits only (no sign, no spaces); nullopt otherwise.
std::optional<std::size_t> parse_index(std::string_view s);
// The whole file (InputError naming it if it cannot be read).
std::string read_text(const std::filesystem::path& p);
// A manifest, parsed within the limits of text_limits.hpp (InputError naming the file).
nlohmann::json read_json(const std::filesystem::path& p);
// The code version every fingerprint includes ("sglab X.Y.Z"): a checkpoint or manifest of another
// version is not reused, and shards of different versions are not merged.
std::string code_version();
// A sweep name is a plain file name, never a path: [A-Za-z0-9_.-], not starting with a dot.
bool valid_sweep_name(const std::string& name);

}  // namespace sglab::runner::sweep_detail
