// Joining the shards of a sharded sweep (`sglab merge`): the shard manifests are found and checked
// (every field for its type: a manifest is data from anywhere), and the per-point CSV is written
// exactly as an unsharded run would have written it.
#include <algorithm>
#include <map>
#include <string_view>
#include <system_error>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "atomic_file.hpp"
#include "input_error.hpp"
#include "sglab/text_limits.hpp"
#include "sweep.hpp"
#include "sweep_detail.hpp"

namespace sglab::runner {

namespace fs = std::filesystem;
using namespace sweep_detail;

// ---- merging ------------------------------------------------------------------------------------

namespace {

// NAME_sweep.shard-i-of-N.json, NAME not empty, i and N decimal digits: a shard's manifest, as
// sweep.hpp names it. By hand, not std::regex: <regex> costs this unit 3.5 CPU s to compile.
bool is_shard_manifest_name(std::string_view name) {
  constexpr std::string_view stem = "_sweep.shard-", extension = ".json";
  if (!name.ends_with(extension)) return false;
  name.remove_suffix(extension.size());
  const auto at = name.rfind(stem);  // the digits after the last stem hold no stem
  if (at == std::string_view::npos || at == 0) return false;
  const auto digits = [](std::string_view d) {
    return !d.empty() && std::all_of(d.begin(), d.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  const auto rest = name.substr(at + stem.size());
  const auto of = rest.find("-of-");
  return of != std::string_view::npos && digits(rest.substr(0, of)) && digits(rest.substr(of + 4));
}

struct ShardFile {
  fs::path manifest, points;
  nlohmann::json json;
  Shard shard;
};

// Every shard manifest named by `inputs` (directories are searched, files taken as given).
std::vector<ShardFile> find_shards(
    const std::vector<fs::path>& inputs,
    const std::function<void(const std::vector<std::string>&, const std::filesystem::path&)>& check_args) {
  std::vector<fs::path> manifests;
  for (const auto& in : inputs) {
    if (fs::is_directory(in)) {
      std::vector<fs::path> found;
      for (const auto& e : fs::directory_iterator(in))
        if (e.is_regular_file() && is_shard_manifest_name(e.path().filename().string())) found.push_back(e.path());
      if (found.empty())
        throw InputError("merge: no shard manifest (NAME_sweep.shard-i-of-N.json) in '" + in.string() + "'");
      std::sort(found.begin(), found.end());
      manifests.insert(manifests.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(in)) {
      manifests.push_back(in);
    } else {
      throw InputError("merge: '" + in.string() + "' is neither a directory nor a file");
    }
  }
  std::vector<ShardFile> out;
  for (const auto& p : manifests) {
    ShardFile f;
    f.manifest = p;
    f.json = read_json(p);
    if (!f.json.is_object())
      throw InputError(fmt::format("merge: {}: not a sweep manifest (not a JSON object)", p.string()));
    // Every field is checked for its type: a manifest is data from anywhere.
    const auto field = [&](const char* key, bool ok, const char* expected) {
      if (!f.json.contains(key)) throw InputError(fmt::format("merge: {}: the manifest has no '{}'", p.string(), key));
      if (!ok)
        throw InputError(fmt::format(
            "merge: {}: '{}' is {}, expected {}", p.string(), key,
            clip_text(f.json[key].dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)), expected));
    };
    const auto strings = [&](const char* key) {
      if (!f.json.contains(key) || !f.json[key].is_array()) return false;
      for (const auto& x : f.json[key])
        if (!x.is_string()) return false;
      return true;
    };
    field("sweep", f.json.contains("sweep") && f.json["sweep"].is_string(), "a string");
    field("args", strings("args"), "an array of strings");
    field("grid", f.json.contains("grid") && f.json["grid"].is_string(), "a string");
    field("points", f.json.contains("points") && f.json["points"].is_number_unsigned(), "a non-negative integer");
    field("shard", f.json.contains("shard") && f.json["shard"].is_string(), "a string");
    field("columns", strings("columns"), "an array of strings");
    field("rows", f.json.contains("rows") && f.json["rows"].is_number_unsigned(), "a non-negative integer");
    field("points_fnv1a", f.json.contains("points_fnv1a") && f.json["points_fnv1a"].is_string(), "a string");
    const std::string name = f.json["sweep"].get<std::string>();
    if (!valid_sweep_name(name))
      throw InputError(fmt::format("merge: {}: sweep name '{}' is not a plain file name (letters, digits, _ . -)",
                                   p.string(), clip_text(name)));
    const auto args = f.json["args"].get<std::vector<std::string>>();
    if (check_args) check_args(args, p);
    for (const auto& a : args)
      for (const char* reserved : {"--out", "--tables-dir", "--shard", "--threads", "--fresh"})
        if (a == reserved || a.rfind(std::string(reserved) + "=", 0) == 0)
          throw InputError(fmt::format("merge: {}: 'args' contains {}, which merge sets itself", p.string(), reserved));
    try {
      f.shard = parse_shard(f.json["shard"].get<std::string>());
    } catch (const std::exception& e) {
      throw InputError(fmt::format("merge: {}: {}", p.string(), e.what()));
    }
    // The file name is the manifest's own: NAME_sweep.shard-i-of-N.json.
    if (p.filename() != sweep_manifest_path("", name, f.shard).filename())
      throw InputError(fmt::format("merge: {}: the file name does not match its sweep '{}' and shard {} (expected {})",
                                   p.string(), clip_text(name), f.shard.text(),
                                   sweep_manifest_path("", name, f.shard).filename().string()));
    if (!f.shard.sharded())
      throw InputError(fmt::format("merge: {} is the output of an unsharded run (shard {}); only shards are merged",
                                   p.string(), f.shard.text()));
    f.points = sweep_points_path(p.parent_path(), f.json["sweep"].get<std::string>(), f.shard);
    // The same manifest named twice (a directory and its file) is one shard, not a duplicate.
    bool seen = false;
    for (const auto& g : out) seen = seen || fs::equivalent(g.manifest, f.manifest);
    if (!seen) out.push_back(std::move(f));
  }
  return out;
}

// Every shard of one sweep must define the same sweep.
void check_same_sweep(const std::string& name, const std::vector<const ShardFile*>& group) {
  const ShardFile& first = *group.front();
  for (const ShardFile* s : group)
    for (const char* key : {"args", "grid", "points", "columns"})
      if (s->json[key] != first.json[key])
        throw InputError(fmt::format("merge: sweep '{}': '{}' differs between {} ({}) and {} ({})", name, key,
                                     first.manifest.string(), clip_text(first.json[key].dump()), s->manifest.string(),
                                     clip_text(s->json[key].dump())));
}

// Each shard's CSV as its manifest recorded it (a deleted row changes both), read before the
// per-point tables are sized: a manifest cannot make merge allocate for points no file holds.
std::vector<CsvTable> read_shard_tables(const std::string& name, const std::vector<const ShardFile*>& group,
                                        std::size_t n) {
  std::vector<CsvTable> tables;
  std::size_t total_rows = 0;
  for (const ShardFile* s : group) {
    const std::string text = read_text(s->points);
    if (fnv1a_hex(text) != s->json["points_fnv1a"].get<std::string>())
      throw InputError(fmt::format("merge: {}: its contents differ from what {} recorded (rows deleted or edited)",
                                   s->points.string(), s->manifest.string()));
    std::istringstream in(text);
    tables.push_back(read_csv(in, s->points.string()));
    if (tables.back().rows.size() != s->json["rows"].get<std::size_t>())
      throw InputError(fmt::format("merge: {}: {} rows, its manifest {} says {}", s->points.string(),
                                   tables.back().rows.size(), s->manifest.string(),
                                   s->json["rows"].get<std::size_t>()));
    total_rows += tables.back().rows.size();
  }
  if (n > total_rows)
    throw InputError(fmt::format("merge: sweep '{}': the manifests say {} points, the shards hold {} rows in all", name,
                                 n, total_rows));
  return tables;
}

void check_header(const ShardFile& s, const CsvTable& t, const std::vector<std::string>& header) {
  if (t.header == header) return;
  std::string diff;
  for (std::size_t c = 0; c < std::max(t.header.size(), header.size()); ++c) {
    const std::string a = c < t.header.size() ? t.header[c] : "(none)", b = c < header.size() ? header[c] : "(none)";
    if (a != b) {
      diff = fmt::format("column {} is '{}', expected '{}'", c + 1, a, b);
      break;
    }
  }
  throw InputError(fmt::format("merge: {}: header mismatch: {}", s.points.string(), diff));
}

// The rows of shard `s` into their points; each point belongs to its shard, once, with contiguous rows.
void assign_rows(const ShardFile& s, const CsvTable& t, std::vector<std::vector<std::vector<std::string>>>& rows,
                 std::vector<const ShardFile*>& owner) {
  const std::size_t n = rows.size();
  std::size_t previous = n;  // the point of the previous row (rows of a point are contiguous)
  for (const auto& r : t.rows) {
    const auto k = parse_index(r.fields[0]);
    if (!k || *k >= n)
      throw InputError(fmt::format("merge: {}: line {}: point '{}' is not an index in [0, {})", s.points.string(),
                                   r.line, r.fields[0], n));
    if (!s.shard.contains(*k))
      throw InputError(fmt::format("merge: {}: line {}: point {} does not belong to shard {}", s.points.string(),
                                   r.line, *k, s.shard.text()));
    if (owner[*k] && owner[*k] != &s)
      throw InputError(fmt::format("merge: point {} appears twice: in {} and in {}", *k, owner[*k]->points.string(),
                                   s.points.string()));
    if (owner[*k] == &s && previous != *k)
      throw InputError(fmt::format("merge: {}: line {}: point {} appears twice (its rows are not contiguous)",
                                   s.points.string(), r.line, *k));
    owner[*k] = &s;
    previous = *k;
    rows[*k].push_back(r.fields);
  }
}

void check_no_missing(const std::string& name, const std::vector<const ShardFile*>& group,
                      const std::vector<const ShardFile*>& owner) {
  std::vector<std::size_t> missing;
  for (std::size_t k = 0; k < owner.size(); ++k)
    if (!owner[k]) missing.push_back(k);
  if (missing.empty()) return;
  std::string list, found;
  for (std::size_t i = 0; i < std::min<std::size_t>(missing.size(), 8); ++i)
    list += (i ? ", " : "") + std::to_string(missing[i]);
  for (const ShardFile* s : group) found += (found.empty() ? "" : ", ") + s->shard.text();
  throw InputError(fmt::format("merge: sweep '{}': {} of {} points missing (first: {}{}); shards found: {}", name,
                               missing.size(), owner.size(), list, missing.size() > 8 ? ", …" : "", found));
}

// One sweep's merged per-point CSV and manifest, checked and ready to write.
struct Pending {
  MergedSweep merged;
  fs::path manifest_path;
  std::string csv, manifest;
};

Pending merge_group(const std::string& name, const std::vector<const ShardFile*>& group, const fs::path& out_dir) {
  check_same_sweep(name, group);
  const ShardFile& first = *group.front();
  const auto n = first.json["points"].get<std::size_t>();
  const auto header = first.json["columns"].get<std::vector<std::string>>();
  const std::vector<CsvTable> tables = read_shard_tables(name, group, n);
  // Shards of another version of sglab may compute other values: never mixed into one table.
  for (const ShardFile* sh : group) {
    if (!sh->json.contains("version") || !sh->json["version"].is_string())
      throw InputError(fmt::format("merge: {}: the manifest has no 'version'", sh->manifest.string()));
    if (sh->json["version"].get<std::string>() != code_version())
      throw InputError(fmt::format("merge: {}: written by {}, this is {}; rerun the shard with this version",
                                   sh->manifest.string(), quote(sh->json["version"].get<std::string>()),
                                   code_version()));
  }
  std::vector<std::vector<std::vector<std::string>>> rows(n);
  std::vector<const ShardFile*> owner(n, nullptr);
  double seconds = 0;
  std::vector<std::string> sources;
  for (std::size_t g = 0; g < group.size(); ++g) {
    const ShardFile* s = group[g];
    seconds += s->json.contains("seconds") && s->json["seconds"].is_number() ? s->json["seconds"].get<double>() : 0.0;
    sources.push_back(s->points.string());
    check_header(*s, tables[g], header);
    assign_rows(*s, tables[g], rows, owner);
  }
  check_no_missing(name, group, owner);
  Pending p;
  std::size_t row_count = 0;
  append_csv_record(p.csv, header);
  for (const auto& point_rows : rows)
    for (const auto& r : point_rows) {
      append_csv_record(p.csv, r);
      ++row_count;
    }
  nlohmann::json m = first.json;
  m["shard"] = Shard{}.text();
  m["rows"] = row_count;
  // Not the merged sweep's wall time: the shards ran apart (in parallel, on other machines).
  m["seconds"] = seconds;
  m["seconds_are"] = fmt::format(
      "the sum of the {} shards' own wall seconds (each shard's run; not a wall time of the sweep)", group.size());
  m["merged_from"] = sources;
  m["points_fnv1a"] = fnv1a_hex(p.csv);
  p.manifest = m.dump(2) + "\n";
  p.manifest_path = sweep_manifest_path(out_dir, name, Shard{});
  p.merged = {.name = name,
              .args = first.json["args"].get<std::vector<std::string>>(),
              .points_csv = sweep_points_path(out_dir, name, Shard{}),
              .manifest = p.manifest_path,
              .points = n,
              .shards = group.size(),
              .replaced = {}};
  return p;
}

}  // namespace

std::vector<MergedSweep> merge_sweep_shards(
    const std::vector<fs::path>& inputs, const fs::path& out_dir,
    const std::function<void(const std::vector<std::string>&, const std::filesystem::path&)>& check_args) {
  if (inputs.empty()) throw InputError("merge: no shard directories given");
  const std::vector<ShardFile> shards = find_shards(inputs, check_args);
  std::map<std::string, std::vector<const ShardFile*>> by_name;
  for (const auto& s : shards) by_name[s.json["sweep"].get<std::string>()].push_back(&s);
  std::vector<Pending> pending;
  for (const auto& [name, group] : by_name) pending.push_back(merge_group(name, group, out_dir));
  // Everything checked: write.
  fs::create_directories(out_dir);
  std::vector<MergedSweep> out;
  for (auto& p : pending) {
    for (const fs::path& target : {p.merged.points_csv, p.manifest_path}) {
      std::error_code ec;
      if (!fs::exists(target, ec)) continue;
      const fs::path backup = target.parent_path() / fmt::format(".{}.merge-backup", target.filename().string());
      fs::rename(target, backup);
      p.merged.replaced.emplace_back(target, backup);
    }
    write_file_atomically(p.merged.points_csv, p.csv);
    write_file_atomically(p.manifest_path, p.manifest);
    std::error_code ec;
    fs::remove(sweep_checkpoint_path(out_dir, p.merged.name, Shard{}), ec);  // a stale unsharded checkpoint
    out.push_back(p.merged);
  }
  return out;
}

void keep_merge(const std::vector<MergedSweep>& merged) {
  for (const auto& m : merged)
    for (const auto& [target, backup] : m.replaced) {
      std::error_code ec;
      fs::remove(backup, ec);
    }
}

void undo_merge(const std::vector<MergedSweep>& merged) {
  for (const auto& m : merged) {
    std::error_code ec;
    fs::remove(m.points_csv, ec);
    fs::remove(m.manifest, ec);
    for (const auto& [target, backup] : m.replaced) fs::rename(backup, target, ec);
  }
}

}  // namespace sglab::runner
