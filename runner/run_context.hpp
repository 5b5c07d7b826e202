// How one `sglab` command line runs, decided where it starts (main: a plain run; `sglab
// reproduce`: its mode; `sglab merge`: a summary of a finished sweep) and passed explicitly from
// there to every command (cli/app.cpp run_sglab, each command's registration) and on to what
// depends on it: the table writer's mode (table.hpp Provenance) and the sweep runner (sweep.hpp).
#pragma once

namespace sglab::runner {

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
};

}  // namespace sglab::runner
