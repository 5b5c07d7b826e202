// An output file that appears whole or not at all. Data goes to a temporary file in the target's
// directory (same file system, so the final rename is atomic); commit() flushes it to disk and
// renames it over the target. Until then the target is untouched: a command that fails halfway,
// or throws, leaves neither a partial file nor a clobbered old one (the destructor removes the
// temporary). SIGINT and SIGTERM remove every live temporary before the process dies (the handler
// of fatal_signal.hpp, installed with the first AtomicFile unless the signal's disposition was
// changed already); SIGKILL can leave a hidden temporary behind, never a partial target.
//
// A command with several outputs writes them as one OutputSet: every path is checked before
// anything is computed (check_output_paths), every file goes to its temporary, and the renames
// happen only once all were written, with SIGINT/SIGTERM held off until the set is published.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "input_error.hpp"

namespace sglab::runner {

class AtomicFile {
 public:
  // Creates the temporary file ".NAME.tmp-XXXXXX" next to `target`. Throws std::system_error.
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // Without a successful commit(): closes and removes the temporary file.
  ~AtomicFile();

  // Appends to the temporary file. Throws std::system_error.
  void write(std::string_view data);
  // fsync, close, rename over the target. Throws std::system_error (the target is then
  // untouched). Call once.
  void commit();
  // The two halves of commit(): fsync and close the temporary; then rename it over the target.
  void flush();
  void publish();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  int fd_ = -1;
  int slot_ = -1;  // in the table of temporaries removed on SIGINT/SIGTERM
  bool committed_ = false;
};

// A path given to a command, and the option that named it ("--out", "--stats", "scene").
struct NamedPath {
  std::string option;
  std::filesystem::path path;
};

// Refuses (InputError, exit status 2) an output that would destroy data or not be a plain file:
// an output equal to one of `inputs` or to another output (also through a hard link or a
// symbolic link), or an existing path that is not a regular file (a directory, a device such as
// /dev/full, a FIFO, a socket, or a symbolic link, which the rename would replace). Empty output
// paths (options not given) are skipped.
void check_output_paths(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);

// Several outputs committed as a whole: add() records each (nothing is written yet); commit()
// creates the parent directories, writes every temporary, and renames them over their targets
// only when all were written. If any write fails nothing is replaced.
class OutputSet {
 public:
  void add(std::filesystem::path target, std::string bytes);
  void commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::string>> files_;
};

// The whole of `bytes` as `target`, atomically (an AtomicFile written and committed at once),
// creating the target's parent directories first.
void write_file_atomically(const std::filesystem::path& target, std::string_view bytes);

}  // namespace sglab::runner
