#include "atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/core.h>

namespace sglab::cli {
namespace {

[[noreturn]] void throw_errno(const std::string& what, const std::filesystem::path& path) {
  throw std::system_error(errno, std::generic_category(), what + " '" + path.string() + "'");
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  const std::filesystem::path dir = target_.has_parent_path() ? target_.parent_path() : ".";
  const std::string pattern =
      fmt::format("{}/.{}.tmp-XXXXXX", dir.string(), target_.filename().string());
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  fd_ = ::mkstemp(name.data());
  if (fd_ < 0) throw_errno("cannot create a temporary file for", target_);
  temp_ = name.data();
  // mkstemp creates the file 0600; give the result the permissions an ordinary open() would
  // (0666 less the umask). umask can only be read by setting it, so set it back at once.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  if (::fchmod(fd_, 0666 & ~mask) != 0) {
    const int saved = errno;
    ::close(fd_);
    ::unlink(temp_.c_str());
    errno = saved;
    throw_errno("cannot set the permissions of", temp_);
  }
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  if (fd_ >= 0) ::close(fd_);
  ::unlink(temp_.c_str());
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
  // fsync before rename: otherwise a crash right after the rename can publish an empty file.
  if (::fsync(fd_) != 0) throw_errno("cannot flush", temp_);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw_errno("cannot close", temp_);
  if (::rename(temp_.c_str(), target_.c_str()) != 0)
    throw_errno("cannot rename the output to", target_);
  committed_ = true;
  // Make the rename itself durable. The file is already published, so a failure here (some file
  // systems refuse to fsync a directory) is not reported as a failed write.
  const std::filesystem::path dir = target_.has_parent_path() ? target_.parent_path() : ".";
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

void write_file_atomically(const std::filesystem::path& target, std::string_view bytes) {
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
  AtomicFile f(target);
  f.write(bytes);
  f.commit();
}

}  // namespace sglab::cli
