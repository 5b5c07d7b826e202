// The sweep runner every `sglab sweep …` shares: a sweep is
//
//   N parameter points (a fixed, deterministic order)  ──►  per-point CSV  ──►  summary
//
// The runner does the first arrow, generically; each sweep kind supplies the points and a
// function that computes the CSV rows of point k, then derives its summary (tables, figures)
// from the per-point CSV alone — never from in-memory state — so that a run interrupted and
// resumed, a run split into shards and joined by `sglab merge`, and a plain run all give the
// same summary from the same bytes.
//
// What the runner provides:
//  • Parallelism: points are computed concurrently with TBB (all cores, or SweepRunOptions::
//    threads). `compute` must therefore be thread-safe (pure functions of the point are).
//  • Progress on stderr: points done / total, rate, ETA and the point being finished.
//  • Sharding (`--shard i/N`): shard i of N owns the points k with k % N == i (round-robin, so
//    that every shard gets a similar mix of cheap and expensive points when cost varies along
//    the grid). The shards of one sweep may write into one directory: their files carry the
//    shard in their names (below).
//  • Resume: the rows of finished points are checkpointed atomically (a whole-file rewrite of
//    a hidden checkpoint file at most every `checkpoint_seconds`, and when a run fails). A run
//    that finds a checkpoint of the same sweep (same name, arguments, grid, columns and shard)
//    computes only the points that are not in it; a run that finds the finished output of the
//    same sweep computes nothing. A checkpoint of a different sweep is ignored (and replaced).
//  • Output: the per-point CSV, written atomically (AtomicFile) once every point of the shard is
//    done, sorted by point index, each row beginning with its point index; then a JSON manifest
//    (what was run: name, arguments, grid, point count, shard, columns, rows, seconds).
//
// Files in the output directory, for a sweep called NAME (e.g. "specular"):
//    unsharded:  NAME_points.csv                 NAME_sweep.json
//    shard i/N:  NAME_points.shard-i-of-N.csv    NAME_sweep.shard-i-of-N.json   (N > 1)
//    checkpoint: .NAME_points[.shard-i-of-N].checkpoint (removed when the run completes)
// A shard writes no summary (it would describe a part of the grid); `sglab merge` joins the
// shards into NAME_points.csv + NAME_sweep.json, exactly the files an unsharded run writes, and
// the sweep's own command then finds its output finished and derives the summary from it.
//
// Usage (see sweep_specular.cpp):
//   SweepDefinition d{.name = "specular", .args = {"sweep", "specular", "--quick"}, .grid = "...",
//                     .point_count = n, .columns = {...}, .compute = ..., .describe = ...};
//   const SweepRunResult r = run_sweep(d, {.out_dir = dir, .shard = shard});
//   if (!r.sharded) { read r.points_csv; write the summary }
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "csv.hpp"
#include "input_error.hpp"
#include "run_context.hpp"

namespace sglab::runner {

// ---- sharding ---------------------------------------------------------------------------------

struct Shard {
  std::size_t index = 0;  // i, in [0, count)
  std::size_t count = 1;  // N ≥ 1

  bool contains(std::size_t point) const { return point % count == index; }
  bool sharded() const { return count > 1; }
  std::string text() const;  // "i/N"
  // "" unsharded, else ".shard-i-of-N": inserted before a file's extension.
  std::string file_suffix() const;
};

// Parses "i/N" (decimal, 0 ≤ i < N). Throws InputError naming the text for anything else
// ("0/0", "3/2", "x", "1/", "-1/2", "1/2/3").
Shard parse_shard(const std::string& text);

// The points of `shard` among 0 … point_count − 1, ascending.
std::vector<std::size_t> shard_points(std::size_t point_count, const Shard& shard);

// ---- running a sweep --------------------------------------------------------------------------

// One row of the per-point CSV, without the point index (the runner prepends it).
using SweepRow = std::vector<std::string>;

struct SweepDefinition {
  std::string name;               // file names and messages: "specular"
  std::vector<std::string> args;  // the sglab arguments that define the sweep, without --out,
                                  // --shard, --threads or --tables-dir: {"sweep", "specular", "--quick"};
                                  // the summary's header names this command
  std::string grid;               // a complete description of the grid and of the methods; part of
                                  // the identity checked on resume and merge
  std::size_t point_count = 0;
  std::vector<std::string> columns;  // per-point CSV columns after the leading "point"
  // The rows of point k (at least one — a point without rows could not be told from a missing
  // one — each with columns.size() fields). Called concurrently from several threads.
  std::function<std::vector<SweepRow>(std::size_t point)> compute;
  // Optional: what point k is, for progress lines ("α=0.01 λ=1e4 view_cos=0.1").
  std::function<std::string(std::size_t point)> describe;
  // Optional: what is wrong with a row read back from disk as point k's (a checkpoint, a finished
  // output, a merged shard): coordinates that are not point k's grid point, a method or
  // configuration the sweep does not run; nullopt if nothing. A fingerprint updated after the
  // edit cannot hide such a row: a checkpoint holding one is ignored, a finished output holding
  // one recomputed, and a merge's summary (SweepRunOptions::summary_only) refused naming the line and value.
  std::function<std::optional<std::string>(std::size_t point, const SweepRow& row)> check_row;
};

struct SweepRunOptions {
  std::filesystem::path out_dir;
  Shard shard;
  std::size_t threads = 0;         // 0: every CPU given (given_cpus())
  double checkpoint_seconds = 10;  // at most this long between checkpoints (0: after every point)
  double progress_seconds = 2;     // at most this often a progress line on stderr
  bool quiet = false;              // no progress lines (tests)
  // Compute nothing (RunContext::summary_only): if the output in the directory is not the
  // finished output of this definition, throw InputError instead of recomputing it.
  bool summary_only = false;
};

struct SweepRunResult {
  std::filesystem::path points_csv;  // the per-point CSV of this run (shard)
  std::filesystem::path manifest;    // its JSON manifest
  bool sharded = false;              // a shard of N > 1: no summary should be derived from it
  std::size_t points = 0;            // points of this shard
  std::size_t resumed = 0;           // of which taken from a checkpoint or a finished earlier run
  std::size_t computed = 0;          // of which computed by this run
  double seconds = 0;                // wall time of this run
};

// Runs (or resumes, or finds finished) the sweep; see the top of this file. Exceptions thrown by
// `compute` propagate after a checkpoint of every point finished so far has been written.
SweepRunResult run_sweep(const SweepDefinition& definition, const SweepRunOptions& options);

// The CPUs this process was given: SLURM_CPUS_PER_TASK when Slurm sets it (a job step may see every
// core of the node), else the CPUs of the affinity mask (taskset, cgroups' cpusets, Slurm's task
// affinity), else the machine's cores.
std::size_t given_cpus();

// What every `sglab sweep KIND` command does with its common options: parse `shard_text` ("" =
// the whole grid), with `fresh` (the command's --fresh, or run.fresh) delete this shard's finished
// output and checkpoint first, run the sweep (computing nothing with run.summary_only), and for a
// shard print how to merge (the caller then writes no summary: r.sharded). Everything the sweep
// runs, the points' own parallel loops included (a render's), stays within given_cpus() threads.
SweepRunResult run_sweep_command(const SweepDefinition& definition, const std::string& out_dir,
                                 const std::string& shard_text, std::size_t threads, bool fresh, const RunContext& run);

// The file names of the runner's outputs (for callers and tests).
std::filesystem::path sweep_points_path(const std::filesystem::path& dir, const std::string& name, const Shard& shard);
std::filesystem::path sweep_manifest_path(const std::filesystem::path& dir, const std::string& name,
                                          const Shard& shard);
std::filesystem::path sweep_checkpoint_path(const std::filesystem::path& dir, const std::string& name,
                                            const Shard& shard);

// Reads a per-point CSV (InputError naming the file if it is missing or malformed).
CsvTable read_sweep_points(const std::filesystem::path& path);

// ---- merging shards ---------------------------------------------------------------------------

struct MergedSweep {
  std::string name;
  std::vector<std::string> args;  // the sweep's defining arguments (SweepDefinition::args)
  std::filesystem::path points_csv, manifest;
  std::size_t points = 0, shards = 0;
  // The files the merge replaced, moved aside (target, hidden backup) until the caller keeps or
  // undoes the merge (keep_merge, undo_merge).
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> replaced;
};

// After merge_sweep_shards, once the merged output was used (its summary derived): the files it
// replaced are deleted. undo_merge instead removes the merged per-point CSV and manifest and puts
// back what they replaced, so that a merge whose summary is refused leaves the directory as it was.
void keep_merge(const std::vector<MergedSweep>& merged);
void undo_merge(const std::vector<MergedSweep>& merged);

// Joins the shard outputs found in `inputs` (directories, searched for NAME_sweep.shard-*.json,
// or manifest files) into `out_dir`/NAME_points.csv and NAME_sweep.json, one pair per sweep name
// found, exactly as an unsharded run would have written them. Throws InputError, naming the file
// and the value, when the shards disagree (name, arguments, grid, point count, columns), when a
// per-point CSV's header differs from its manifest, when a point appears twice (in two shards or
// twice in one), when a point is missing, when a point index is not an integer in range, or when
// no shard is found. Writes nothing unless everything checks. Manifests are data: a sweep name
// that is not a plain file name, a field of the wrong type, or a per-point CSV whose row count or
// fingerprint differs from its manifest's is refused.
// `check_args`, if given, is called with each manifest's "args" and path before anything is
// written, and throws InputError for a command line its caller will not run.
std::vector<MergedSweep> merge_sweep_shards(
    const std::vector<std::filesystem::path>& inputs, const std::filesystem::path& out_dir,
    const std::function<void(const std::vector<std::string>&, const std::filesystem::path&)>& check_args = {});

// ---- fingerprints, summary-only runs, numbers --------------------------------------------------
// (The summaries' error statistics, ErrorStats and ErrorAccumulator, are the metrics module's:
// core/include/sglab/error_metrics.hpp.)

// FNV-1a, 64 bit (Fowler, Noll, Vo), as 16 hex digits: the fingerprint of a text in checkpoints,
// manifests and reproduce markers (a changed or truncated file changes it). Not security.
std::string fnv1a_hex(std::string_view text);

// Formats a double for a CSV field: the shortest text that reads back to the same double; ""
// for NaN (a statistic over no points).
std::string csv_number(double x);

}  // namespace sglab::runner
