// What SIGINT and SIGTERM do before an sglab command dies of them: remove every live temporary
// output (AtomicFile's, atomic_file.hpp) and end every registered child process group (the plot
// interpreters of `sglab reproduce`). One handler for both signals, installed by the first
// registration unless the signal's disposition was changed already (ignored, or handled by an
// embedding program); fixed tables, so that the handler touches only async-signal-safe state.
#pragma once

#include <string>

#include <sys/types.h>

namespace sglab::runner {

// A temporary file removed by the handler; returns its slot (-1: the table is full or the path too
// long, and this temporary is not removed by a signal, still never a partial target).
int register_temporary(const std::string& path);
void unregister_temporary(int slot);

// While an output set is renamed into place (between begin and end), the handler waits: a signal
// that arrives meanwhile takes effect at the last publish_end.
void publish_begin();
void publish_end();

// A child that leads a process group of its own: the handler sends the group SIGTERM, then SIGCONT
// (a stopped process acts on the SIGTERM once continued). Returns the slot (-1: table full).
// Forget the group before reaping its leader, so that the handler never signals a group ID that may
// have been reused.
int register_child_group(pid_t group);
void unregister_child_group(int slot);

}  // namespace sglab::runner
