// An output file that appears whole or not at all. Data goes to a temporary file in the target's
// directory (same file system, so the final rename is atomic); commit() flushes it to disk and
// renames it over the target. Until then the target is untouched: a command that fails halfway,
// or throws, leaves neither a partial file nor a clobbered old one (the destructor removes the
// temporary). A process killed by a signal can leave the hidden temporary behind, never a
// partial target.
#pragma once

#include <filesystem>
#include <string_view>

namespace sglab::cli {

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

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  int fd_ = -1;
  bool committed_ = false;
};

// The whole of `bytes` as `target`, atomically (an AtomicFile written and committed at once),
// creating the target's parent directories first.
void write_file_atomically(const std::filesystem::path& target, std::string_view bytes);

}  // namespace sglab::cli
