// How one `sglab` command line runs, decided where it starts (main: a plain run, or the places
// `sglab --results DIR --tables DIR COMMAND` names; `sglab reproduce`: its mode and places; `sglab
// merge`: a summary of a finished sweep) and passed explicitly from there to every command
// (cli/app.cpp run_sglab, each command's registration) and on to what depends on it: the table
// writer's mode (table.hpp Provenance), the sweep runner (sweep.hpp) and every command's default
// output directories (Places).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace sglab::runner {

// The committed tables: written by a full `sglab reproduce` only, read by the write-ups (own-method
// --from, recommend --from) of a run that keeps its tables beside its outputs.
inline constexpr std::string_view kPaperTables = "paper_tables";

// Where a run writes. Each command's own output directory is OUT/ITS_DIR (`--out` defaults to it;
// ITS_DIR is defined once, in the command's file: error-vs-time's is "error_vs_time"), and its
// tables go to TABLES, or beside its outputs when TABLES is empty (a command's --tables-dir, or
// --tables, defaults to it). A plain `sglab COMMAND` runs in Places{}: results/ITS_DIR, tables
// beside; `sglab reproduce` in {results, paper_tables} (--quick: {results/quick,
// results/quick/tables}). A table's header names its directories as options against Places{}'s
// defaults, so that the header's command, run alone, writes the table where it is.
struct Places {
  std::string out = "results";
  std::string tables;  // empty: each command's tables beside its other outputs

  // OUT/NAME: the output directory of the command whose directory is NAME.
  std::string dir(std::string_view name) const { return out + "/" + std::string(name); }
  // The tables of a command that writes only tables (near-wall): TABLES, else OUT/NAME.
  std::string tables_or_dir(std::string_view name) const { return tables.empty() ? dir(name) : tables; }
  // Where a write-up reads the tables of the run (own-method, recommend): TABLES, else paper_tables/.
  std::string tables_read() const { return tables.empty() ? std::string(kPaperTables) : tables; }
  // The figures README.md shows: TABLES/figures.
  std::string key_figures() const { return tables + "/figures"; }

  bool operator==(const Places&) const = default;
};

// The app-level options that name a run's places, given before the command: `sglab --results DIR
// --tables DIR COMMAND …` runs COMMAND in Places{DIR, DIR}.
inline constexpr std::string_view kResultsOption = "--results", kTablesOption = "--tables";

// Those options for `p`, each only where it differs from Places{}, so that a printed command line
// (`sglab reproduce --list`, a step's marker) runs alone where it ran.
inline std::vector<std::string> places_arguments(const Places& p) {
  std::vector<std::string> args;
  if (p.out != Places{}.out) args.insert(args.end(), {std::string(kResultsOption), p.out});
  if (p.tables != Places{}.tables) args.insert(args.end(), {std::string(kTablesOption), p.tables});
  return args;
}

// `s` as one word of a POSIX shell line: as it is where that is safe, else in single quotes.
inline std::string shell_word(const std::string& s) {
  if (!s.empty() && s.find_first_of(" \t'\"\\$`[]*?") == std::string::npos) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The `sglab` line that runs `args` (a command and its arguments) in the places `p`: the places'
// options (places_arguments), then the command. `sglab reproduce --list` prints it for each step,
// and every table the run writes names it as the command that wrote it: run alone from the
// repository root, it rewrites that table where it is.
inline std::string command_line(const Places& p, const std::vector<std::string>& args) {
  std::string line = "sglab";
  for (const auto& a : places_arguments(p)) line += " " + shell_word(a);
  for (const auto& a : args) line += " " + shell_word(a);
  return line;
}

struct RunContext {
  // A coarse run: every table the command writes is marked "quick run", whatever its own options
  // (`sglab reproduce --quick` runs its steps so: a step's quick options may be a smaller image
  // rather than --quick).
  bool quick = false;
  // Every sweep starts afresh, as with its own --fresh: its finished output and checkpoint are
  // deleted first (`sglab reproduce --force`, so that a forced rerun recomputes its sweeps instead
  // of resuming checkpoints that an earlier build of the same version wrote: their fingerprint
  // does not cover the code).
  bool fresh = false;
  // The sweeps compute nothing (`sglab merge` running a sweep's own command to derive its
  // summary): if the output in the directory is not the finished output of the sweep the command
  // defines, the sweep throws InputError instead of recomputing it.
  bool summary_only = false;
  // Where the command writes unless its options say otherwise.
  Places places = {};
  // The line this run runs (command_line of its places and the command's arguments; set by the
  // CLI's run_sglab), which the tables it writes name (table.hpp run_provenance). Empty in a
  // library call: its tables name the line the command composes from its options.
  std::string command = {};
};

}  // namespace sglab::runner
