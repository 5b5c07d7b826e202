#include "sweep.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A non-negative decimal integer, digits only (no sign, no spaces); nullopt otherwise.
std::optional<std::size_t> parse_index(std::string_view s) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string_view::npos) return std::nullopt;
  std::size_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

std::vector<std::string> with_point(const std::vector<std::string>& columns) {
  std::vector<std::string> h{"point"};
  h.insert(h.end(), columns.begin(), columns.end());
  return h;
}

// Part of every fingerprint: a checkpoint or manifest of another version of sglab is not reused.
const std::string kCodeVersion = "sglab " SGLAB_VERSION;

// A fingerprint of the sweep's identity (with the code version) for the checkpoint's first line;
// a changed grid changes the text, which changes the hash.
std::string fingerprint(const SweepDefinition& d, const Shard& shard) {
  return fnv1a_hex(d.name + '\n' + join(d.args, "\x1f") + '\n' + d.grid + '\n' + join(d.columns, ",") + '\n' +
                   std::to_string(d.point_count) + '\n' + shard.text() + '\n' + kCodeVersion);
}

std::atomic<int> g_summary_only{0};

const std::string kCheckpointMagic = "# sglab sweep checkpoint ";

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw UsageError("cannot read '" + p.string() + "'");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string format_seconds(double s) {
  if (!std::isfinite(s)) return "?";
  if (s < 60) return fmt::format("{:.0f} s", s);
  if (s < 3600) return fmt::format("{:.0f} min {:02.0f} s", std::floor(s / 60), std::fmod(s, 60));
  return fmt::format("{:.0f} h {:02.0f} min", std::floor(s / 3600), std::floor(std::fmod(s, 3600) / 60));
}

nlohmann::json manifest_json(const SweepDefinition& d, const Shard& shard, std::size_t rows, double seconds,
                             const std::string& csv) {
  return {{"sweep", d.name},       {"args", d.args},
          {"command", "sglab " + join(d.args, " ")},
          {"grid", d.grid},        {"points", d.point_count},
          {"shard", shard.text()}, {"columns", with_point(d.columns)},
          {"rows", rows},          {"seconds", seconds},
          {"version", kCodeVersion}, {"points_fnv1a", fnv1a_hex(csv)}};
}

// A manifest, parsed within the limits of text_limits.hpp (UsageError naming the file).
nlohmann::json read_json(const fs::path& p) {
  std::error_code ec;
  const auto size = fs::file_size(p, ec);
  if (!ec)
    if (const auto error = input_size_error(size, kMaxJsonBytes, "a manifest"))
      throw UsageError(fmt::format("{}: {}", p.string(), *error));
  const std::string text = read_text(p);
  if (const auto error = json_nesting_error(text)) throw UsageError(fmt::format("{}: {}", p.string(), *error));
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw UsageError(fmt::format("{}: not a sweep manifest ({})", p.string(), clip_text(e.what(), 400)));
  }
}

// A sweep name is a plain file name, never a path: [A-Za-z0-9_.-], not starting with a dot.
bool valid_sweep_name(const std::string& name) {
  return !name.empty() && name.size() <= 200 && name[0] != '.' &&
         name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") == std::string::npos;
}

// The rows of each point of `points_in_shard` found in `table` (a per-point CSV or checkpoint),
// or a message saying why the table does not belong to this sweep and shard.
struct LoadedRows {
  std::map<std::size_t, std::vector<SweepRow>> by_point;
  std::string problem;  // "" if usable
};

LoadedRows rows_by_point(const CsvTable& table, const SweepDefinition& d, const Shard& shard) {
  LoadedRows out;
  if (table.header != with_point(d.columns)) {
    out.problem = "its header differs from this sweep's columns";
    return out;
  }
  for (const auto& r : table.rows) {
    const auto k = parse_index(r.fields[0]);
    if (!k || *k >= d.point_count || !shard.contains(*k)) {
      out.problem = fmt::format("line {}: point '{}' is not a point of this shard", r.line, r.fields[0]);
      return out;
    }
    out.by_point[*k].emplace_back(r.fields.begin() + 1, r.fields.end());
  }
  return out;
}

}  // namespace

// ---- sharding ---------------------------------------------------------------------------------

std::string Shard::text() const { return fmt::format("{}/{}", index, count); }

std::string Shard::file_suffix() const {
  return sharded() ? fmt::format(".shard-{}-of-{}", index, count) : std::string();
}

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  const auto bad = [&](const std::string& why) {
    return UsageError("--shard '" + text + "': " + why + " (expected i/N with 0 ≤ i < N, e.g. 0/4)");
  };
  if (slash == std::string::npos) throw bad("no '/'");
  const auto i = parse_index(std::string_view(text).substr(0, slash));
  const auto n = parse_index(std::string_view(text).substr(slash + 1));
  if (!i || !n) throw bad("i and N must be non-negative integers");
  if (*n == 0) throw bad("N must be at least 1");
  if (*i >= *n) throw bad(fmt::format("i = {} is not less than N = {}", *i, *n));
  return {*i, *n};
}

std::vector<std::size_t> shard_points(std::size_t point_count, const Shard& shard) {
  std::vector<std::size_t> out;
  for (std::size_t k = shard.index; k < point_count; k += shard.count) out.push_back(k);
  return out;
}

// ---- files --------------------------------------------------------------------------------------

fs::path sweep_points_path(const fs::path& dir, const std::string& name, const Shard& shard) {
  return dir / (name + "_points" + shard.file_suffix() + ".csv");
}
fs::path sweep_manifest_path(const fs::path& dir, const std::string& name, const Shard& shard) {
  return dir / (name + "_sweep" + shard.file_suffix() + ".json");
}
fs::path sweep_checkpoint_path(const fs::path& dir, const std::string& name, const Shard& shard) {
  return dir / ("." + name + "_points" + shard.file_suffix() + ".checkpoint");
}

CsvTable read_sweep_points(const fs::path& path) {
  std::istringstream in(read_text(path));
  return read_csv(in, path.string());
}

// ---- running ------------------------------------------------------------------------------------

SweepRunResult run_sweep(const SweepDefinition& d, const SweepRunOptions& o) {
  if (!d.compute) throw std::logic_error("run_sweep: sweep '" + d.name + "' has no compute function");
  const auto t_start = Clock::now();
  fs::create_directories(o.out_dir);
  SweepRunResult result;
  result.points_csv = sweep_points_path(o.out_dir, d.name, o.shard);
  result.manifest = sweep_manifest_path(o.out_dir, d.name, o.shard);
  result.sharded = o.shard.sharded();
  const fs::path checkpoint = sweep_checkpoint_path(o.out_dir, d.name, o.shard);
  const std::vector<std::size_t> mine = shard_points(d.point_count, o.shard);
  result.points = mine.size();
  const std::string label = "sweep " + d.name + (o.shard.sharded() ? " [shard " + o.shard.text() + "]" : "");
  auto say = [&](const std::string& line) {
    if (!o.quiet) std::fprintf(stderr, "%s: %s\n", label.c_str(), line.c_str());
  };

  // 1. Finished earlier? Same manifest identity and a per-point CSV holding exactly our points.
  if (fs::exists(result.manifest) && fs::exists(result.points_csv)) {
    bool same = false;
    try {
      const nlohmann::json m = nlohmann::json::parse(read_text(result.manifest));
      same = m.is_object() && m.value("sweep", "") == d.name && m.value("args", std::vector<std::string>{}) == d.args &&
             m.value("grid", "") == d.grid && m.value("points", std::size_t(0)) == d.point_count &&
             m.value("shard", "") == o.shard.text() && m.value("columns", std::vector<std::string>{}) == with_point(d.columns) &&
             m.value("version", "") == kCodeVersion &&
             // The CSV as the manifest recorded it: a deleted or edited row is not "finished".
             m.value("points_fnv1a", "") == fnv1a_hex(read_text(result.points_csv));
    } catch (const std::exception&) {
      same = false;  // an unreadable or foreign manifest: the output is not known to be finished
    }
    if (same) {
      LoadedRows rows;
      try {
        rows = rows_by_point(read_sweep_points(result.points_csv), d, o.shard);
      } catch (const UsageError& e) {
        rows.problem = e.what();
      }
      if (rows.problem.empty() && rows.by_point.size() == mine.size()) {
        say(fmt::format("all {} points finished earlier ({}); nothing to compute", mine.size(), result.points_csv.string()));
        result.resumed = mine.size();
        result.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
        return result;
      }
      say("the earlier output " + result.points_csv.string() + " is incomplete or altered; recomputing");
    }
  }
  if (g_summary_only.load() > 0)
    throw UsageError(fmt::format("{}: {} is not the finished output of the sweep `sglab {}` as defined here (another "
                                 "grid, scene, version, or altered rows); nothing recomputed",
                                 label, result.points_csv.string(), clip_text(join(d.args, " "), 400)));

  // 2. A checkpoint of the same sweep: its points are done.
  std::vector<std::vector<SweepRow>> rows(mine.size());
  std::vector<char> done(mine.size(), 0);
  const std::string print = fingerprint(d, o.shard);
  if (fs::exists(checkpoint)) {
    const std::string text = read_text(checkpoint);
    const std::string first = text.substr(0, text.find('\n'));
    const std::string body = first.size() < text.size() ? text.substr(first.size() + 1) : std::string();
    if (first.rfind(kCheckpointMagic + print + " ", 0) != 0) {
      say("ignoring the checkpoint " + checkpoint.string() + " of a different sweep or grid");
    } else if (first != kCheckpointMagic + print + " " + fnv1a_hex(body)) {
      say("ignoring the checkpoint " + checkpoint.string() + ": its rows were altered or cut short");
    } else {
      std::istringstream in(body);
      LoadedRows loaded;
      try {
        loaded = rows_by_point(read_csv(in, checkpoint.string()), d, o.shard);
      } catch (const UsageError& e) {
        loaded.problem = e.what();
      }
      if (!loaded.problem.empty()) {
        say("ignoring the unreadable checkpoint " + checkpoint.string() + ": " + loaded.problem);
      } else {
        for (std::size_t j = 0; j < mine.size(); ++j) {
          auto it = loaded.by_point.find(mine[j]);
          if (it == loaded.by_point.end()) continue;
          rows[j] = std::move(it->second);
          done[j] = 1;
          ++result.resumed;
        }
        say(fmt::format("resuming: {} of {} points finished earlier (checkpoint {})", result.resumed, mine.size(),
                        checkpoint.string()));
      }
    }
  }

  std::vector<std::size_t> todo;  // positions in `mine`
  for (std::size_t j = 0; j < mine.size(); ++j)
    if (!done[j]) todo.push_back(j);

  const std::vector<std::string> header = with_point(d.columns);
  // The CSV text of every finished point in point order (the checkpoint and the final output).
  auto csv_text = [&] {
    std::string text;
    append_csv_record(text, header);
    std::vector<std::string> fields;
    for (std::size_t j = 0; j < mine.size(); ++j) {
      if (!done[j]) continue;
      for (const auto& r : rows[j]) {
        fields.assign(1, std::to_string(mine[j]));
        fields.insert(fields.end(), r.begin(), r.end());
        append_csv_record(text, fields);
      }
    }
    return text;
  };

  std::mutex mutex;  // guards rows/done (after compute), counters, checkpoint and progress
  std::size_t finished = 0;
  auto last_checkpoint = Clock::now(), last_progress = Clock::now();
  const auto t_compute = Clock::now();
  auto write_checkpoint = [&] {  // caller holds the mutex
    const std::string body = csv_text();
    write_file_atomically(checkpoint, kCheckpointMagic + print + " " + fnv1a_hex(body) + "\n" + body);
    last_checkpoint = Clock::now();
  };
  auto progress = [&](std::size_t j, bool force) {  // caller holds the mutex
    const auto now = Clock::now();
    if (o.quiet || (!force && std::chrono::duration<double>(now - last_progress).count() < o.progress_seconds)) return;
    last_progress = now;
    const double elapsed = std::chrono::duration<double>(now - t_compute).count();
    const double rate = elapsed > 0 ? double(finished) / elapsed : 0;
    const std::size_t total_done = result.resumed + finished;
    const double eta = rate > 0 ? double(todo.size() - finished) / rate : NAN;
    std::fprintf(stderr, "%s: %zu/%zu points (%.1f %%), %.3g points/s, ETA %s; finished %s\n", label.c_str(),
                 total_done, mine.size(), 100.0 * double(total_done) / double(std::max<std::size_t>(mine.size(), 1)), rate,
                 format_seconds(eta).c_str(),
                 d.describe ? d.describe(mine[j]).c_str() : fmt::format("point {}", mine[j]).c_str());
  };

  if (!todo.empty()) {
    say(fmt::format("computing {} of {} points ({} total in the grid{})", todo.size(), mine.size(), d.point_count,
                    o.shard.sharded() ? ", shard " + o.shard.text() : ""));
    tbb::task_arena arena(o.threads > 0 ? int(o.threads) : tbb::task_arena::automatic);
    try {
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, todo.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t t = r.begin(); t != r.end(); ++t) {
            if (tbb::is_current_task_group_canceling()) return;  // another point failed
            const std::size_t j = todo[t];
            std::vector<SweepRow> point_rows = d.compute(mine[j]);
            if (point_rows.empty())  // a point without rows could not be told from a missing one
              throw std::logic_error(fmt::format("sweep {}: point {} gave no rows", d.name, mine[j]));
            for (const auto& row : point_rows)
              if (row.size() != d.columns.size())
                throw std::logic_error(fmt::format("sweep {}: point {} gave a row of {} fields for {} columns", d.name,
                                                   mine[j], row.size(), d.columns.size()));
            std::lock_guard lock(mutex);
            rows[j] = std::move(point_rows);
            done[j] = 1;
            ++finished;
            progress(j, false);
            if (std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= o.checkpoint_seconds &&
                finished < todo.size())
              write_checkpoint();
          }
        });
      });
    } catch (...) {
      // Keep what was finished: the next run resumes from it.
      std::lock_guard lock(mutex);
      if (finished > 0) {
        try {
          write_checkpoint();
          say(fmt::format("stopped by an error; {} finished points kept in {}", result.resumed + finished,
                          checkpoint.string()));
        } catch (const std::exception& e) {
          say(std::string("could not write the checkpoint: ") + e.what());
        }
      }
      throw;
    }
    result.computed = finished;
    progress(todo.back(), true);
  }

  std::size_t row_count = 0;
  for (const auto& r : rows) row_count += r.size();
  const std::string csv = csv_text();
  write_file_atomically(result.points_csv, csv);
  result.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  write_file_atomically(result.manifest, manifest_json(d, o.shard, row_count, result.seconds, csv).dump(2) + "\n");
  std::error_code ec;
  fs::remove(checkpoint, ec);
  say(fmt::format("{} points ({} computed, {} resumed), {} rows in {:.1f} s -> {}", mine.size(), result.computed,
                  result.resumed, row_count, result.seconds, result.points_csv.string()));
  return result;
}

// ---- merging ------------------------------------------------------------------------------------

namespace {

struct ShardFile {
  fs::path manifest, points;
  nlohmann::json json;
  Shard shard;
};

// Every shard manifest named by `inputs` (directories are searched, files taken as given).
std::vector<ShardFile> find_shards(
    const std::vector<fs::path>& inputs,
    const std::function<void(const std::vector<std::string>&, const std::filesystem::path&)>& check_args) {
  static const std::regex shard_manifest(R"((.+)_sweep\.shard-(\d+)-of-(\d+)\.json)");
  std::vector<fs::path> manifests;
  for (const auto& in : inputs) {
    if (fs::is_directory(in)) {
      std::vector<fs::path> found;
      for (const auto& e : fs::directory_iterator(in))
        if (e.is_regular_file() && std::regex_match(e.path().filename().string(), shard_manifest))
          found.push_back(e.path());
      if (found.empty()) throw UsageError("merge: no shard manifest (NAME_sweep.shard-i-of-N.json) in '" + in.string() + "'");
      std::sort(found.begin(), found.end());
      manifests.insert(manifests.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(in)) {
      manifests.push_back(in);
    } else {
      throw UsageError("merge: '" + in.string() + "' is neither a directory nor a file");
    }
  }
  std::vector<ShardFile> out;
  for (const auto& p : manifests) {
    ShardFile f;
    f.manifest = p;
    f.json = read_json(p);
    if (!f.json.is_object()) throw UsageError(fmt::format("merge: {}: not a sweep manifest (not a JSON object)", p.string()));
    // Every field is checked for its type: a manifest is data from anywhere.
    const auto field = [&](const char* key, bool ok, const char* expected) {
      if (!f.json.contains(key)) throw UsageError(fmt::format("merge: {}: the manifest has no '{}'", p.string(), key));
      if (!ok)
        throw UsageError(fmt::format("merge: {}: '{}' is {}, expected {}", p.string(), key, clip_text(f.json[key].dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)),
                                     expected));
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
      throw UsageError(fmt::format("merge: {}: sweep name '{}' is not a plain file name (letters, digits, _ . -)", p.string(),
                                   clip_text(name)));
    const auto args = f.json["args"].get<std::vector<std::string>>();
    if (check_args) check_args(args, p);
    for (const auto& a : args)
      for (const char* reserved : {"--out", "--tables-dir", "--shard", "--threads", "--fresh"})
        if (a == reserved || a.rfind(std::string(reserved) + "=", 0) == 0)
          throw UsageError(fmt::format("merge: {}: 'args' contains {}, which merge sets itself", p.string(), reserved));
    try {
      f.shard = parse_shard(f.json["shard"].get<std::string>());
    } catch (const std::exception& e) {
      throw UsageError(fmt::format("merge: {}: {}", p.string(), e.what()));
    }
    // The file name is the manifest's own: NAME_sweep.shard-i-of-N.json.
    if (p.filename() != sweep_manifest_path("", name, f.shard).filename())
      throw UsageError(fmt::format("merge: {}: the file name does not match its sweep '{}' and shard {} (expected {})",
                                   p.string(), clip_text(name), f.shard.text(),
                                   sweep_manifest_path("", name, f.shard).filename().string()));
    if (!f.shard.sharded())
      throw UsageError(fmt::format("merge: {} is the output of an unsharded run (shard {}); only shards are merged",
                                   p.string(), f.shard.text()));
    f.points = sweep_points_path(p.parent_path(), f.json["sweep"].get<std::string>(), f.shard);
    // The same manifest named twice (a directory and its file) is one shard, not a duplicate.
    bool seen = false;
    for (const auto& g : out) seen = seen || fs::equivalent(g.manifest, f.manifest);
    if (!seen) out.push_back(std::move(f));
  }
  return out;
}

}  // namespace

std::vector<MergedSweep> merge_sweep_shards(
    const std::vector<fs::path>& inputs, const fs::path& out_dir,
    const std::function<void(const std::vector<std::string>&, const std::filesystem::path&)>& check_args) {
  if (inputs.empty()) throw UsageError("merge: no shard directories given");
  const std::vector<ShardFile> shards = find_shards(inputs, check_args);
  std::map<std::string, std::vector<const ShardFile*>> by_name;
  for (const auto& s : shards) by_name[s.json["sweep"].get<std::string>()].push_back(&s);

  struct Pending {
    MergedSweep merged;
    fs::path manifest_path;
    std::string csv, manifest;
  };
  std::vector<Pending> pending;
  for (const auto& [name, group] : by_name) {
    const ShardFile& first = *group.front();
    for (const ShardFile* s : group)
      for (const char* key : {"args", "grid", "points", "columns"})
        if (s->json[key] != first.json[key])
          throw UsageError(fmt::format("merge: sweep '{}': '{}' differs between {} ({}) and {} ({})", name, key,
                                       first.manifest.string(), clip_text(first.json[key].dump()), s->manifest.string(),
                                       clip_text(s->json[key].dump())));
    const auto n = first.json["points"].get<std::size_t>();
    const auto header = first.json["columns"].get<std::vector<std::string>>();
    // Each shard's CSV as its manifest recorded it (a deleted row changes both), read before the
    // per-point tables are sized: a manifest cannot make merge allocate for points no file holds.
    std::vector<CsvTable> tables;
    std::size_t total_rows = 0;
    for (const ShardFile* s : group) {
      const std::string text = read_text(s->points);
      if (fnv1a_hex(text) != s->json["points_fnv1a"].get<std::string>())
        throw UsageError(fmt::format("merge: {}: its contents differ from what {} recorded (rows deleted or edited)",
                                     s->points.string(), s->manifest.string()));
      std::istringstream in(text);
      tables.push_back(read_csv(in, s->points.string()));
      if (tables.back().rows.size() != s->json["rows"].get<std::size_t>())
        throw UsageError(fmt::format("merge: {}: {} rows, its manifest {} says {}", s->points.string(),
                                     tables.back().rows.size(), s->manifest.string(), s->json["rows"].get<std::size_t>()));
      total_rows += tables.back().rows.size();
    }
    if (n > total_rows)
      throw UsageError(fmt::format("merge: sweep '{}': the manifests say {} points, the shards hold {} rows in all", name, n,
                                   total_rows));
    std::vector<std::vector<std::vector<std::string>>> rows(n);
    std::vector<const ShardFile*> owner(n, nullptr);
    double seconds = 0;
    std::vector<std::string> sources;
    for (std::size_t g = 0; g < group.size(); ++g) {
      const ShardFile* s = group[g];
      const double shard_seconds = s->json.contains("seconds") && s->json["seconds"].is_number() ? s->json["seconds"].get<double>() : 0.0;
      seconds += shard_seconds;
      sources.push_back(s->points.string());
      const CsvTable& t = tables[g];
      if (t.header != header) {
        std::string diff;
        for (std::size_t c = 0; c < std::max(t.header.size(), header.size()); ++c) {
          const std::string a = c < t.header.size() ? t.header[c] : "(none)", b = c < header.size() ? header[c] : "(none)";
          if (a != b) {
            diff = fmt::format("column {} is '{}', expected '{}'", c + 1, a, b);
            break;
          }
        }
        throw UsageError(fmt::format("merge: {}: header mismatch: {}", s->points.string(), diff));
      }
      std::size_t previous = n;  // the point of the previous row (rows of a point are contiguous)
      for (const auto& r : t.rows) {
        const auto k = parse_index(r.fields[0]);
        if (!k || *k >= n)
          throw UsageError(fmt::format("merge: {}: line {}: point '{}' is not an index in [0, {})", s->points.string(),
                                       r.line, r.fields[0], n));
        if (!s->shard.contains(*k))
          throw UsageError(fmt::format("merge: {}: line {}: point {} does not belong to shard {}", s->points.string(),
                                       r.line, *k, s->shard.text()));
        if (owner[*k] && owner[*k] != s)
          throw UsageError(fmt::format("merge: point {} appears twice: in {} and in {}", *k, owner[*k]->points.string(),
                                       s->points.string()));
        if (owner[*k] == s && previous != *k)
          throw UsageError(fmt::format("merge: {}: line {}: point {} appears twice (its rows are not contiguous)",
                                       s->points.string(), r.line, *k));
        owner[*k] = s;
        previous = *k;
        rows[*k].push_back(r.fields);
      }
    }
    std::vector<std::size_t> missing;
    for (std::size_t k = 0; k < n; ++k)
      if (!owner[k]) missing.push_back(k);
    if (!missing.empty()) {
      std::string list, found;
      for (std::size_t i = 0; i < std::min<std::size_t>(missing.size(), 8); ++i) list += (i ? ", " : "") + std::to_string(missing[i]);
      for (const ShardFile* s : group) found += (found.empty() ? "" : ", ") + s->shard.text();
      throw UsageError(fmt::format("merge: sweep '{}': {} of {} points missing (first: {}{}); shards found: {}", name,
                                   missing.size(), n, list, missing.size() > 8 ? ", …" : "", found));
    }
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
    m["seconds"] = seconds;
    m["merged_from"] = sources;
    m["points_fnv1a"] = fnv1a_hex(p.csv);
    p.manifest = m.dump(2) + "\n";
    p.merged = {name, first.json["args"].get<std::vector<std::string>>(), sweep_points_path(out_dir, name, Shard{}), n,
                group.size()};
    p.manifest_path = sweep_manifest_path(out_dir, name, Shard{});
    pending.push_back(std::move(p));
  }
  // Everything checked: write.
  fs::create_directories(out_dir);
  std::vector<MergedSweep> out;
  for (auto& p : pending) {
    write_file_atomically(p.merged.points_csv, p.csv);
    write_file_atomically(p.manifest_path, p.manifest);
    std::error_code ec;
    fs::remove(sweep_checkpoint_path(out_dir, p.merged.name, Shard{}), ec);  // a stale unsharded checkpoint
    out.push_back(p.merged);
  }
  return out;
}

std::string fnv1a_hex(std::string_view text) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64-bit offset basis
  for (unsigned char ch : text) {
    h ^= ch;
    h *= 1099511628211ull;  // FNV-1a 64-bit prime
  }
  return fmt::format("{:016x}", h);
}

SummaryOnlyScope::SummaryOnlyScope() { g_summary_only.fetch_add(1); }
SummaryOnlyScope::~SummaryOnlyScope() { g_summary_only.fetch_sub(1); }

// ---- statistics ---------------------------------------------------------------------------------

void ErrorAccumulator::add(bool has_value, double value, double reference, double scale, std::size_t tag) {
  ++s_.points;
  if (!has_value || !std::isfinite(value)) {
    ++s_.missing;
    return;
  }
  const double error = std::fabs(value - reference);
  if (scale > 0 && std::isfinite(scale)) {
    const double scaled = error / scale;
    if (!(scaled <= s_.max_scaled)) s_.max_scaled = scaled;  // also replaces the initial NaN
    sum_sq_scaled_ += scaled * scaled;
    ++scaled_;
  }
  if (!(scale > 0 && reference > 0 && reference >= near_zero_ * scale)) {
    ++s_.near_zero;
    return;
  }
  const double relative = error / reference;
  ++s_.relative;
  sum_sq_ += relative * relative;
  const double denominator = std::fabs(value) + std::fabs(reference);  // > 0: reference > 0
  sum_smape_ += 2 * error / denominator;
  if (s_.relative == 1 || relative > s_.max_relative) {
    s_.max_relative = relative;
    s_.worst = tag;
  }
}

ErrorStats ErrorAccumulator::stats() const {
  ErrorStats s = s_;
  if (s.relative > 0) {
    s.rmse_relative = std::sqrt(sum_sq_ / double(s.relative));
    s.smape = sum_smape_ / double(s.relative);
  }
  if (scaled_ > 0) s.rmse_scaled = std::sqrt(sum_sq_scaled_ / double(scaled_));
  return s;
}

std::string csv_number(double x) {
  if (std::isnan(x)) return "";
  if (!std::isfinite(x)) throw std::logic_error("csv_number: an infinite statistic");
  return fmt::format("{}", x);
}

SweepRunResult run_sweep_command(const SweepDefinition& definition, const std::string& out_dir,
                                 const std::string& shard_text, std::size_t threads, bool fresh) {
  const Shard shard = shard_text.empty() ? Shard{} : parse_shard(shard_text);
  if (fresh)
    for (const auto& p : {sweep_points_path(out_dir, definition.name, shard), sweep_manifest_path(out_dir, definition.name, shard),
                          sweep_checkpoint_path(out_dir, definition.name, shard)})
      std::filesystem::remove(p);
  SweepRunResult r = run_sweep(definition, {.out_dir = out_dir, .shard = shard, .threads = threads});
  if (r.sharded)
    std::fprintf(stderr,
                 "sweep %s: shard %s written to %s; no summary from a part of the grid. When every shard is done:\n"
                 "  sglab merge --out %s <the shard directories>\n",
                 definition.name.c_str(), shard.text().c_str(), r.points_csv.string().c_str(), out_dir.c_str());
  return r;
}

}  // namespace sglab::cli
