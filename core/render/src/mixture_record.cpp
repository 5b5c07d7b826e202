// Reading mixture records (mixture_record.hpp).
#include "sglab/render/mixture_record.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <array>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sglab/text_limits.hpp"

namespace sglab::render {
namespace {

// k and the field index of "lobe<k>.<field>" (k decimal without leading zeros, below the lobe
// limit), or nothing.
bool parse_key(std::string_view key, std::size_t& k, int& field) {
  if (key.substr(0, 4) != "lobe") return false;
  key.remove_prefix(4);
  const std::size_t dot = key.find('.');
  if (dot == std::string_view::npos || dot == 0 || dot > 4 || (dot > 1 && key[0] == '0')) return false;
  const auto [end, ec] = std::from_chars(key.data(), key.data() + dot, k);
  if (ec != std::errc() || end != key.data() + dot || k >= kMaxMixtureLobes) return false;
  const std::string_view f = key.substr(dot + 1);
  for (int i = 0; i < 7; ++i)
    if (f == kMixtureLobeFields[i]) {
      field = i;
      return true;
    }
  return false;
}

}  // namespace

SgMixture parse_mixture(std::string_view text, const std::string& name) {
  const std::string where = "mixture " + quote(name);
  auto fail = [&](const std::string& why) -> EnvironmentError { return EnvironmentError(where + ": " + why); };
  if (const auto error = json_nesting_error(text)) throw fail(*error);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw fail(std::string("is not JSON (") + bounded_message(e.what(), 300) + ")");
  }
  if (!j.is_object()) throw fail("not a JSON object (a fit record of `sglab fit envmap --json`)");
  if (!j.contains("fit") || !j["fit"].is_string() || j["fit"].get<std::string>() != "envmap")
    throw fail("\"fit\" is " +
               (j.contains("fit") ? quote(j["fit"].dump(-1, ' ', false, nlohmann::json::error_handler_t::replace))
                                  : std::string("missing")) +
               "; a mixture record is the output of `sglab fit envmap --json` (\"fit\": \"envmap\")");
  if (!j.contains("parameters") || !j["parameters"].is_object()) throw fail("has no \"parameters\" object");
  const auto& p = j["parameters"];
  // Every key names a lobe field; lobe k's seven values land in values[k].
  std::map<std::size_t, std::array<std::optional<double>, 7>> values;
  for (const auto& [key, value] : p.items()) {
    std::size_t k = 0;
    int field = 0;
    if (!parse_key(key, k, field))
      throw fail(fmt::format("parameter {} is not a lobe field (lobe<k>.axis_x|axis_y|axis_z|sharpness|r|g|b, k < {})",
                             quote(key), kMaxMixtureLobes));
    if (!value.is_number() || !std::isfinite(value.get<double>()))
      throw fail(fmt::format("\"{}\" is {}, not a finite number", key,
                             quote(value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace))));
    values[k][std::size_t(field)] = value.get<double>();
  }
  if (values.empty()) throw fail("has no lobes (parameters lobe0.axis_x …)");
  const std::size_t count = values.rbegin()->first + 1;
  SgMixture m;
  for (std::size_t k = 0; k < count; ++k) {
    const auto it = values.find(k);
    for (int f = 0; f < 7; ++f)
      if (it == values.end() || !it->second[std::size_t(f)])
        throw fail(
            fmt::format("\"lobe{}.{}\" is missing (the record has lobes up to lobe{}; each needs all seven fields)", k,
                        kMixtureLobeFields[f], count - 1));
    double v[7];
    for (int f = 0; f < 7; ++f) v[f] = *it->second[std::size_t(f)];
    // Scaled by the largest component before the norm, so that no square overflows or underflows.
    const double scale = std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
    if (!(scale > 0)) throw fail(fmt::format("lobe{} has the zero axis", k));
    SgLight l;
    l.axis = sglab::Vec3<double>(v[0] / scale, v[1] / scale, v[2] / scale).normalized();
    l.sharpness = v[3];
    l.amplitude = {v[4], v[5], v[6]};
    if (!(v[3] >= 0 && v[3] <= kMaxMixtureSharpness))
      throw fail(fmt::format("lobe{}.sharpness {} is outside [0, {:g}]", k, v[3], kMaxMixtureSharpness));
    for (int c = 0; c < 3; ++c)
      if (!(v[4 + c] >= 0 && v[4 + c] <= kMaxMixtureAmplitude))
        throw fail(fmt::format("lobe{}.{} {} is outside [0, {:g}]", k, kMixtureLobeFields[4 + c], v[4 + c],
                               kMaxMixtureAmplitude));
    m.push_back(l);
  }
  if (j.contains("lobes") && !(j["lobes"].is_number_unsigned() && j["lobes"].get<std::size_t>() == m.size()))
    throw fail(fmt::format("\"lobes\" is {}, but the parameters hold {} lobes",
                           quote(j["lobes"].dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)), m.size()));
  return m;
}

SgMixture load_mixture(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec)))
    throw EnvironmentError("mixture " + quote(path) + ": no such file");
  std::string text;
  try {
    text = read_input_file(path, kMaxJsonBytes, "a mixture record");
  } catch (const InputFileError& e) {
    throw EnvironmentError(std::string("mixture ") + e.what());
  }
  return parse_mixture(text, path);
}

}  // namespace sglab::render
