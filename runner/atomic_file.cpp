#include "atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/core.h>

#include "fatal_signal.hpp"
#include "input_error.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::runner {
namespace {

[[noreturn]] void throw_errno(const std::string& what, const std::filesystem::path& path) {
  throw std::system_error(errno, std::generic_category(), what + " '" + path.string() + "'");
}

const char* file_kind(const struct stat& st) {
  if (S_ISDIR(st.st_mode)) return "a directory";
  if (S_ISLNK(st.st_mode)) return "a symbolic link";
  if (S_ISFIFO(st.st_mode)) return "a FIFO";
  if (S_ISCHR(st.st_mode)) return "a character device";
  if (S_ISBLK(st.st_mode)) return "a block device";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  const std::filesystem::path dir = target_.has_parent_path() ? target_.parent_path() : ".";
  const std::string pattern = fmt::format("{}/.{}.tmp-XXXXXX", dir.string(), target_.filename().string());
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  fd_ = ::mkstemp(name.data());
  if (fd_ < 0) throw_errno("cannot create a temporary file for", target_);
  temp_ = name.data();
  slot_ = register_temporary(temp_.string());
  // mkstemp creates the file 0600; give the result the permissions an ordinary open() would
  // (0666 less the umask). umask can only be read by setting it, so set it back at once.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  if (::fchmod(fd_, 0666 & ~mask) != 0) {
    const int saved = errno;
    ::close(fd_);
    ::unlink(temp_.c_str());
    unregister_temporary(slot_);
    errno = saved;
    throw_errno("cannot set the permissions of", temp_);
  }
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  if (fd_ >= 0) ::close(fd_);
  ::unlink(temp_.c_str());
  unregister_temporary(slot_);
}

void AtomicFile::write(std::string_view data) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd_, data.data(), data.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      throw_errno("cannot write", temp_);
    }
    data.remove_prefix(static_cast<std::size_t>(n));
  }
}

void AtomicFile::commit() {
  flush();
  publish_begin();
  try {
    publish();
  } catch (...) {
    publish_end();
    throw;
  }
  publish_end();
}

void AtomicFile::flush() {
  // fsync before rename: otherwise a crash right after the rename can publish an empty file.
  if (::fsync(fd_) != 0) throw_errno("cannot flush", temp_);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw_errno("cannot close", temp_);
}

void AtomicFile::publish() {
  // The target may have become a special file since the command's checks: never replace one.
  struct stat st {};
  if (::lstat(target_.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw InputError(
        fmt::format("'{}' is {}; refusing to replace it with an output file", target_.string(), file_kind(st)));
  if (::rename(temp_.c_str(), target_.c_str()) != 0) throw_errno("cannot rename the output to", target_);
  committed_ = true;
  unregister_temporary(slot_);
  // Make the rename itself durable. The file is already published, so a failure here (some file
  // systems refuse to fsync a directory) is not reported as a failed write.
  const std::filesystem::path dir = target_.has_parent_path() ? target_.parent_path() : ".";
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

void check_output_paths(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs) {
  namespace fs = std::filesystem;
  std::error_code ec;
  auto same = [&](const fs::path& a, const fs::path& b) {
    if (fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec) && !ec) return true;
    ec.clear();
    const bool eq = fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);  // hard links
    ec.clear();
    return eq;
  };
  // Commands record their paths in JSON (stats, manifests, markers), which holds only UTF-8.
  for (const auto* list : {&outputs, &inputs})
    for (const NamedPath& p : *list)
      if (!valid_utf8(p.path.string()))
        throw InputError(fmt::format("{} '{}' is not valid UTF-8; rename it", p.option, clip_text(p.path.string())));
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& o = outputs[i];
    if (o.path.empty()) continue;
    struct stat st {};
    if (::lstat(o.path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
      throw InputError(fmt::format("{} '{}' is {}; an output must be a regular file (or not exist yet)", o.option,
                                   o.path.string(), file_kind(st)));
    for (const NamedPath& in : inputs)
      if (!in.path.empty() && same(o.path, in.path))
        throw InputError(fmt::format("{} '{}' is the input {}; refusing to overwrite an input", o.option,
                                     o.path.string(), in.option));
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].path.empty() && same(o.path, outputs[j].path))
        throw InputError(fmt::format("{} '{}' is also the output of {}; each output needs its own file", o.option,
                                     o.path.string(), outputs[j].option));
  }
}

void OutputSet::add(std::filesystem::path target, std::string bytes) {
  files_.emplace_back(std::move(target), std::move(bytes));
}

void OutputSet::commit() {
  std::vector<std::unique_ptr<AtomicFile>> temps;
  for (auto& [target, bytes] : files_) {
    if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
    temps.push_back(std::make_unique<AtomicFile>(target));
    temps.back()->write(bytes);
    temps.back()->flush();
  }
  // Every file is written: publish them together, a signal meanwhile waits for the last rename.
  publish_begin();
  try {
    for (auto& t : temps) t->publish();
  } catch (...) {
    publish_end();
    throw;
  }
  publish_end();
  files_.clear();
}

void write_file_atomically(const std::filesystem::path& target, std::string_view bytes) {
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
  AtomicFile f(target);
  f.write(bytes);
  f.commit();
}

}  // namespace sglab::runner
