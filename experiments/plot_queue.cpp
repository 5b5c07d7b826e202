#include "plot_queue.hpp"

#include <algorithm>
#include <csignal>
#include <utility>

#include <fcntl.h>
#include <nlohmann/json.hpp>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

#include "fatal_signal.hpp"

namespace sglab::experiments {

PlotServer::Outcome PlotServer::run(const std::vector<std::string>& args) {
  if (!started() && !start(std::filesystem::path(args.at(0)).parent_path() / "_serve.py")) return {127, 0, 0, {}};
  const double paused0 = paused_seconds();
  const std::string request = nlohmann::json(args).dump() + "\n";
  for (std::size_t sent = 0; sent < request.size();) {
    const ssize_t n = send(socket_, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return died();
    sent += std::size_t(n);
  }
  std::string answer;
  for (char c = 0; c != '\n';) {
    const ssize_t n = recv(socket_, &c, 1, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return died();
    answer += c;
  }
  const nlohmann::json a = nlohmann::json::parse(answer, nullptr, false);
  if (!a.is_object() || !a.contains("status") || !a["status"].is_number_integer()) return died();
  Outcome out{a["status"].get<int>(), a.value("cpu", 0.0), paused_seconds() - paused0, {}};
  for (const auto& path : a.value("wrote", nlohmann::json::array()))
    if (path.is_string()) out.wrote.insert(path.get<std::string>());
  return out;
}

void PlotServer::pause() {
  const std::lock_guard guard(state_);
  if (paused_) return;
  paused_ = true;
  paused_since_ = std::chrono::steady_clock::now();
  if (pid_ > 0) signal_all(SIGSTOP);
}

void PlotServer::resume() {
  const std::lock_guard guard(state_);
  if (!paused_) return;
  paused_ = false;
  paused_total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - paused_since_).count();
  if (pid_ > 0) signal_all(SIGCONT);
}

void PlotServer::stop() {
  resume();
  const std::lock_guard guard(state_);
  if (pid_ <= 0) return;
  close(socket_);
  runner::unregister_child_group(group_slot_);  // before the group's ID can be reused
  group_slot_ = -1;
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = 0;
}

bool PlotServer::started() {
  const std::lock_guard guard(state_);
  return pid_ > 0;
}

double PlotServer::paused_seconds() {
  const std::lock_guard guard(state_);
  return paused_total_;
}

void PlotServer::signal_all(int signal) { kill(-pid_, signal); }

bool PlotServer::start(const std::filesystem::path& server) {
  const std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  int ends[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0) return false;
  std::vector<std::string> words = {python, server.string()};
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, ends[1], 3);  // dup2 clears close-on-exec on fd 3
  // Outside the terminal's foreground group a read of the terminal would stop the plot (SIGTTIN):
  // a plot reads no input. A write would with `stty tostop` (SIGTTOU), unless that signal is blocked.
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  posix_spawnattr_setpgroup(&attributes, 0);  // a process group of its own, led by the interpreter
  sigset_t mask;
  sigemptyset(&mask);
  sigaddset(&mask, SIGTTOU);
  posix_spawnattr_setsigmask(&attributes, &mask);
  // What ends the group (plot_queue.hpp) must end it also where sglab runs with these ignored (under
  // nohup, SIGHUP): the kernel's SIGHUP to an orphaned group, the handler's SIGTERM.
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGHUP);
  sigaddset(&defaults, SIGTERM);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  const std::lock_guard guard(state_);
  const int spawned = posix_spawnp(&pid_, python.c_str(), &actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  close(ends[1]);
  if (spawned != 0) {
    close(ends[0]);
    pid_ = 0;
    return false;
  }
  socket_ = ends[0];
  group_slot_ = runner::register_child_group(pid_);
  if (paused_) signal_all(SIGSTOP);  // paused before it started: it starts stopped
  return true;
}

PlotServer::Outcome PlotServer::died() {
  stop();
  return {128, 0, 0, {}};
}

PlotQueue::~PlotQueue() {
  {
    const std::lock_guard guard(mutex_);
    stop_ = true;  // the plots running finish; the queued ones are dropped
  }
  for (auto& s : servers_) s.resume();
  changed_.notify_all();
  for (auto& w : workers_) w.join();
}

void PlotQueue::release(std::vector<Job>& jobs) {
  {
    const std::lock_guard guard(mutex_);
    for (auto& job : jobs) queued_.push_back(std::move(job));
    held_ = false;
    for (auto& s : servers_) s.resume();
    while (workers_.size() < std::min(servers_.size(), queued_.size() + std::size_t(running_)))
      workers_.emplace_back(&PlotQueue::loop, this, std::ref(servers_[workers_.size()]));
  }
  jobs.clear();
  changed_.notify_all();
}

void PlotQueue::hold() {
  const std::lock_guard guard(mutex_);
  held_ = true;
  for (auto& s : servers_) s.pause();
  rethrow();
}

void PlotQueue::drain(std::vector<Job>& jobs) {
  release(jobs);
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return running_ == 0 && (queued_.empty() || failure_); });
  rethrow();
  for (auto& s : servers_) s.stop();
}

void PlotQueue::loop(PlotServer& server) {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return stop_ || (!held_ && !failure_ && !queued_.empty()); });
    if (stop_) return;
    Job job = std::move(queued_.front());
    queued_.pop_front();
    ++running_;
    lock.unlock();
    std::exception_ptr failure;
    try {
      job(server);
    } catch (...) {
      failure = std::current_exception();
    }
    lock.lock();
    --running_;
    if (failure && !failure_) failure_ = failure;
    changed_.notify_all();
  }
}

void PlotQueue::rethrow() {
  if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
}

}  // namespace sglab::experiments
