#include "sweep.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <string_view>
#include <thread>

#include <sched.h>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "atomic_file.hpp"
#include "input_error.hpp"
#include "sweep_detail.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::runner {

namespace fs = std::filesystem;

namespace sweep_detail {

// A non-negative decimal integer, digits only (no sign, no spaces); nullopt otherwise.
std::optional<std::size_t> parse_index(std::string_view s) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string_view::npos) return std::nullopt;
  std::size_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw InputError("cannot read '" + p.string() + "'");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A manifest, parsed within the limits of text_limits.hpp (InputError naming the file).
nlohmann::json read_json(const fs::path& p) {
  std::error_code ec;
  const auto size = fs::file_size(p, ec);
  if (!ec)
    if (const auto error = input_size_error(size, kMaxJsonBytes, "a manifest"))
      throw InputError(fmt::format("{}: {}", p.string(), *error));
  const std::string text = read_text(p);
  if (const auto error = json_nesting_error(text)) throw InputError(fmt::format("{}: {}", p.string(), *error));
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not a sweep manifest ({})", p.string(), clip_text(e.what(), 400)));
  }
}

// A sweep name is a plain file name, never a path: [A-Za-z0-9_.-], not starting with a dot.
// Part of every fingerprint: a checkpoint or manifest of another version of sglab is not reused.
std::string code_version() { return "sglab " SGLAB_VERSION; }

bool valid_sweep_name(const std::string& name) {
  return !name.empty() && name.size() <= 200 && name[0] != '.' &&
         name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") ==
             std::string::npos;
}

}  // namespace sweep_detail

using namespace sweep_detail;

namespace {

using Clock = std::chrono::steady_clock;

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

const std::string kCodeVersion = sweep_detail::code_version();

// A fingerprint of the sweep's identity (with the code version) for the checkpoint's first line;
// a changed grid changes the text, which changes the hash.
std::string fingerprint(const SweepDefinition& d, const Shard& shard) {
  return fnv1a_hex(d.name + '\n' + join(d.args, "\x1f") + '\n' + d.grid + '\n' + join(d.columns, ",") + '\n' +
                   std::to_string(d.point_count) + '\n' + shard.text() + '\n' + kCodeVersion);
}

const std::string kCheckpointMagic = "# sglab sweep checkpoint ";

std::string format_seconds(double s) {
  if (!std::isfinite(s)) return "?";
  if (s < 60) return fmt::format("{:.0f} s", s);
  if (s < 3600) return fmt::format("{:.0f} min {:02.0f} s", std::floor(s / 60), std::fmod(s, 60));
  return fmt::format("{:.0f} h {:02.0f} min", std::floor(s / 3600), std::floor(std::fmod(s, 3600) / 60));
}

nlohmann::json manifest_json(const SweepDefinition& d, const Shard& shard, std::size_t rows, double seconds,
                             const std::string& csv) {
  return {
      {"sweep", d.name},         {"args", d.args},          {"command", "sglab " + join(d.args, " ")}, {"grid", d.grid},
      {"points", d.point_count}, {"shard", shard.text()},   {"columns", with_point(d.columns)},        {"rows", rows},
      {"seconds", seconds},      {"version", kCodeVersion}, {"points_fnv1a", fnv1a_hex(csv)}};
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
    SweepRow row(r.fields.begin() + 1, r.fields.end());
    if (d.check_row) {
      if (const auto problem = d.check_row(*k, row)) {
        out.problem = fmt::format("line {}: point {}: {}", r.line, *k, clip_text(*problem, 400));
        return out;
      }
    }
    out.by_point[*k].push_back(std::move(row));
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
    return InputError("--shard '" + text + "': " + why + " (expected i/N with 0 ≤ i < N, e.g. 0/4)");
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

namespace {

// Whether the outputs of an earlier run of the same sweep and shard are there, whole and unaltered:
// the manifest's identity, and a per-point CSV holding exactly this shard's points.
bool finished_earlier(const SweepDefinition& d, const Shard& shard, SweepRunResult& result, std::size_t points,
                      const std::function<void(const std::string&)>& say, std::string& problem, bool summary_only) {
  if (!fs::exists(result.manifest) || !fs::exists(result.points_csv)) return false;
  bool same = false;
  try {
    const nlohmann::json m = nlohmann::json::parse(read_text(result.manifest));
    same = m.is_object() && m.value("sweep", "") == d.name && m.value("args", std::vector<std::string>{}) == d.args &&
           m.value("grid", "") == d.grid && m.value("points", std::size_t(0)) == d.point_count &&
           m.value("shard", "") == shard.text() &&
           m.value("columns", std::vector<std::string>{}) == with_point(d.columns) &&
           m.value("version", "") == kCodeVersion &&
           // The CSV as the manifest recorded it: a deleted or edited row is not "finished".
           m.value("points_fnv1a", "") == fnv1a_hex(read_text(result.points_csv));
  } catch (const std::exception&) {
    same = false;  // an unreadable or foreign manifest: the output is not known to be finished
  }
  if (!same) return false;
  LoadedRows rows;
  try {
    rows = rows_by_point(read_sweep_points(result.points_csv), d, shard);
  } catch (const InputError& e) {
    rows.problem = e.what();
  }
  if (rows.problem.empty() && rows.by_point.size() == points) {
    say(fmt::format("all {} points finished earlier ({}); nothing to compute", points, result.points_csv.string()));
    result.resumed = points;
    return true;
  }
  problem = rows.problem;
  if (!summary_only)
    say("the earlier output " + result.points_csv.string() + " is incomplete or altered" +
        (rows.problem.empty() ? "" : " (" + rows.problem + ")") + "; recomputing");
  return false;
}

// The rows of the points a checkpoint of the same sweep (fingerprint `print`) holds, into
// rows/done (by position in `mine`); how many. A foreign, altered or unreadable checkpoint is ignored.
std::size_t load_checkpoint(const fs::path& checkpoint, const std::string& print, const SweepDefinition& d,
                            const Shard& shard, const std::vector<std::size_t>& mine,
                            std::vector<std::vector<SweepRow>>& rows, std::vector<char>& done,
                            const std::function<void(const std::string&)>& say) {
  if (!fs::exists(checkpoint)) return 0;
  const std::string text = read_text(checkpoint);
  const std::string first = text.substr(0, text.find('\n'));
  const std::string body = first.size() < text.size() ? text.substr(first.size() + 1) : std::string();
  if (first.rfind(kCheckpointMagic + print + " ", 0) != 0) {
    say("ignoring the checkpoint " + checkpoint.string() + " of a different sweep or grid");
    return 0;
  }
  if (first != kCheckpointMagic + print + " " + fnv1a_hex(body)) {
    say("ignoring the checkpoint " + checkpoint.string() + ": its rows were altered or cut short");
    return 0;
  }
  std::istringstream in(body);
  LoadedRows loaded;
  try {
    loaded = rows_by_point(read_csv(in, checkpoint.string()), d, shard);
  } catch (const InputError& e) {
    loaded.problem = e.what();
  }
  if (!loaded.problem.empty()) {
    say("ignoring the unreadable checkpoint " + checkpoint.string() + ": " + loaded.problem);
    return 0;
  }
  std::size_t resumed = 0;
  for (std::size_t j = 0; j < mine.size(); ++j) {
    auto it = loaded.by_point.find(mine[j]);
    if (it == loaded.by_point.end()) continue;
    rows[j] = std::move(it->second);
    done[j] = 1;
    ++resumed;
  }
  say(fmt::format("resuming: {} of {} points finished earlier (checkpoint {})", resumed, mine.size(),
                  checkpoint.string()));
  return resumed;
}

}  // namespace

// ---- running ------------------------------------------------------------------------------------

namespace {

// One run over this shard's points: the rows of every finished point (from a checkpoint or computed
// here), the checkpoint and the progress lines; `mutex` guards them while points are computed in
// parallel.
struct PointRun {
  const SweepDefinition& d;
  const SweepRunOptions& o;
  const std::vector<std::size_t>& mine;  // this shard's points
  const std::string& label;
  fs::path checkpoint;
  std::string print;  // the sweep's fingerprint, the checkpoint's identity
  std::vector<std::vector<SweepRow>> rows;
  std::vector<char> done;
  std::vector<std::size_t> todo;  // positions in `mine`
  std::size_t resumed = 0, finished = 0;
  std::mutex mutex;
  Clock::time_point last_checkpoint, last_progress, t_compute;

  PointRun(const SweepDefinition& d_, const SweepRunOptions& o_, const std::vector<std::size_t>& mine_,
           const std::string& label_)
      : d(d_), o(o_), mine(mine_), label(label_), rows(mine_.size()), done(mine_.size(), 0) {}

  // The CSV text of every finished point in point order (the checkpoint and the final output).
  std::string csv_text() const {
    std::string text;
    append_csv_record(text, with_point(d.columns));
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
  }

  void write_checkpoint() {  // caller holds the mutex
    const std::string body = csv_text();
    write_file_atomically(checkpoint, kCheckpointMagic + print + " " + fnv1a_hex(body) + "\n" + body);
    last_checkpoint = Clock::now();
  }

  void progress(std::size_t j, bool force) {  // caller holds the mutex
    const auto now = Clock::now();
    if (o.quiet || (!force && std::chrono::duration<double>(now - last_progress).count() < o.progress_seconds)) return;
    last_progress = now;
    const double elapsed = std::chrono::duration<double>(now - t_compute).count();
    const double rate = elapsed > 0 ? double(finished) / elapsed : 0;
    const std::size_t total_done = resumed + finished;
    const double eta = rate > 0 ? double(todo.size() - finished) / rate : NAN;
    std::fprintf(stderr, "%s: %zu/%zu points (%.1f %%), %.3g points/s, ETA %s; finished %s\n", label.c_str(),
                 total_done, mine.size(), 100.0 * double(total_done) / double(std::max<std::size_t>(mine.size(), 1)),
                 rate, format_seconds(eta).c_str(),
                 d.describe ? d.describe(mine[j]).c_str() : fmt::format("point {}", mine[j]).c_str());
  }

  // Computes the point at position j of `mine`, checks its rows and records them.
  void compute_point(std::size_t j) {
    std::vector<SweepRow> point_rows = d.compute(mine[j]);
    if (point_rows.empty())  // a point without rows could not be told from a missing one
      throw std::logic_error(fmt::format("sweep {}: point {} gave no rows", d.name, mine[j]));
    for (const auto& row : point_rows)
      if (row.size() != d.columns.size())
        throw std::logic_error(fmt::format("sweep {}: point {} gave a row of {} fields for {} columns", d.name, mine[j],
                                           row.size(), d.columns.size()));
    std::lock_guard lock(mutex);
    rows[j] = std::move(point_rows);
    done[j] = 1;
    ++finished;
    progress(j, false);
    if (std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= o.checkpoint_seconds &&
        finished < todo.size())
      write_checkpoint();
  }

  // Every point of `todo` on o.threads threads; on an error, what was finished is kept in the
  // checkpoint (the next run resumes from it) and the error goes on.
  template <class Say>
  void compute_todo(const Say& say) {
    last_checkpoint = last_progress = t_compute = Clock::now();
    tbb::task_arena arena(o.threads > 0 ? int(o.threads) : tbb::task_arena::automatic);
    try {
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, todo.size(), 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                            for (std::size_t t = r.begin(); t != r.end(); ++t) {
                              if (tbb::is_current_task_group_canceling()) return;  // another point failed
                              compute_point(todo[t]);
                            }
                          });
      });
    } catch (...) {
      std::lock_guard lock(mutex);
      if (finished > 0) {
        try {
          write_checkpoint();
          say(fmt::format("stopped by an error; {} finished points kept in {}", resumed + finished,
                          checkpoint.string()));
        } catch (const std::exception& e) {
          say(std::string("could not write the checkpoint: ") + e.what());
        }
      }
      throw;
    }
    progress(todo.back(), true);
  }
};

}  // namespace

SweepRunResult run_sweep(const SweepDefinition& d, const SweepRunOptions& o) {
  if (!d.compute) throw std::logic_error("run_sweep: sweep '" + d.name + "' has no compute function");
  const auto t_start = Clock::now();
  fs::create_directories(o.out_dir);
  SweepRunResult result;
  result.points_csv = sweep_points_path(o.out_dir, d.name, o.shard);
  result.manifest = sweep_manifest_path(o.out_dir, d.name, o.shard);
  result.sharded = o.shard.sharded();
  const std::vector<std::size_t> mine = shard_points(d.point_count, o.shard);
  result.points = mine.size();
  const std::string label = "sweep " + d.name + (o.shard.sharded() ? " [shard " + o.shard.text() + "]" : "");
  auto say = [&](const std::string& line) {
    if (!o.quiet) std::fprintf(stderr, "%s: %s\n", label.c_str(), line.c_str());
  };

  // 1. Finished earlier? Same manifest identity and a per-point CSV holding exactly our points.
  std::string problem;
  if (finished_earlier(d, o.shard, result, mine.size(), say, problem, o.summary_only)) {
    result.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
    return result;
  }
  if (o.summary_only && !problem.empty())
    throw InputError(fmt::format("{}: {}: {}; nothing recomputed", label, result.points_csv.string(), problem));
  if (o.summary_only)
    throw InputError(
        fmt::format("{}: {} is not the finished output of the sweep `sglab {}` as defined here (another "
                    "grid, scene, version, or altered rows); nothing recomputed",
                    label, result.points_csv.string(), clip_text(join(d.args, " "), 400)));

  // 2. A checkpoint of the same sweep: its points are done.
  PointRun run(d, o, mine, label);
  run.checkpoint = sweep_checkpoint_path(o.out_dir, d.name, o.shard);
  run.print = fingerprint(d, o.shard);
  result.resumed = run.resumed = load_checkpoint(run.checkpoint, run.print, d, o.shard, mine, run.rows, run.done, say);
  for (std::size_t j = 0; j < mine.size(); ++j)
    if (!run.done[j]) run.todo.push_back(j);

  // 3. The other points.
  if (!run.todo.empty()) {
    say(fmt::format("computing {} of {} points ({} total in the grid{})", run.todo.size(), mine.size(), d.point_count,
                    o.shard.sharded() ? ", shard " + o.shard.text() : ""));
    run.compute_todo(say);
    result.computed = run.finished;
  }

  std::size_t row_count = 0;
  for (const auto& r : run.rows) row_count += r.size();
  const std::string csv = run.csv_text();
  write_file_atomically(result.points_csv, csv);
  result.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  write_file_atomically(result.manifest, manifest_json(d, o.shard, row_count, result.seconds, csv).dump(2) + "\n");
  std::error_code ec;
  fs::remove(run.checkpoint, ec);
  say(fmt::format("{} points ({} computed, {} resumed), {} rows in {:.1f} s -> {}", mine.size(), result.computed,
                  result.resumed, row_count, result.seconds, result.points_csv.string()));
  return result;
}

std::string fnv1a_hex(std::string_view text) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64-bit offset basis
  for (unsigned char ch : text) {
    h ^= ch;
    h *= 1099511628211ull;  // FNV-1a 64-bit prime
  }
  return fmt::format("{:016x}", h);
}

// ---- numbers ------------------------------------------------------------------------------------

std::string csv_number(double x) {
  if (std::isnan(x)) return "";
  if (!std::isfinite(x)) throw std::logic_error("csv_number: an infinite statistic");
  return fmt::format("{}", x);
}

std::size_t given_cpus() {
  if (const char* slurm = std::getenv("SLURM_CPUS_PER_TASK")) {
    std::size_t n = 0;
    const std::string_view text(slurm);
    const auto r = std::from_chars(text.data(), text.data() + text.size(), n);
    if (r.ec == std::errc() && r.ptr == text.data() + text.size() && n > 0) return n;
  }
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof mask, &mask) == 0 && CPU_COUNT(&mask) > 0) return std::size_t(CPU_COUNT(&mask));
  return std::max(1u, std::thread::hardware_concurrency());
}

SweepRunResult run_sweep_command(const SweepDefinition& definition, const std::string& out_dir,
                                 const std::string& shard_text, std::size_t threads, bool fresh,
                                 const RunContext& run) {
  const Shard shard = shard_text.empty() ? Shard{} : parse_shard(shard_text);
  // The whole sweep within the CPUs given: its points and each point's own parallel loops.
  const std::size_t cpus = given_cpus();
  const tbb::global_control cap(tbb::global_control::max_allowed_parallelism, cpus);
  if (threads == 0 || threads > cpus) threads = cpus;
  std::fprintf(stderr, "sweep %s: %zu point(s) at once, within the %zu CPU(s) given\n", definition.name.c_str(),
               threads, cpus);
  if (fresh || run.fresh)
    for (const auto& p :
         {sweep_points_path(out_dir, definition.name, shard), sweep_manifest_path(out_dir, definition.name, shard),
          sweep_checkpoint_path(out_dir, definition.name, shard)})
      std::filesystem::remove(p);
  SweepRunResult r = run_sweep(
      definition, {.out_dir = out_dir, .shard = shard, .threads = threads, .summary_only = run.summary_only});
  if (r.sharded)
    std::fprintf(stderr,
                 "sweep %s: shard %s written to %s; no summary from a part of the grid. When every shard is done:\n"
                 "  sglab merge --out %s <the shard directories>\n",
                 definition.name.c_str(), shard.text().c_str(), r.points_csv.string().c_str(), out_dir.c_str());
  return r;
}

}  // namespace sglab::runner
