#include "plot_queue.hpp"

#include <algorithm>
#include <csignal>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include <nlohmann/json.hpp>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

namespace sglab::experiments {
namespace {

// The processes below `root` (its children, theirs, …), by the parent each names in /proc/PID/stat.
std::vector<pid_t> descendants(pid_t root) {
  std::multimap<pid_t, pid_t> children;  // parent -> child
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc", ec); !ec && it != std::filesystem::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(it->path() / "stat");
    std::string stat;
    std::getline(in, stat);
    const auto close = stat.rfind(')');  // "PID (COMM) STATE PPID …"; COMM may hold ") "
    if (close == std::string::npos) continue;
    std::istringstream rest(stat.substr(close + 1));
    std::string state;
    long parent = 0;
    if (rest >> state >> parent) children.emplace(pid_t(parent), pid_t(std::stol(name)));
  }
  std::vector<pid_t> out, open = {root};
  while (!open.empty() && out.size() < children.size()) {
    const auto [first, last] = children.equal_range(open.back());
    open.pop_back();
    for (auto c = first; c != last; ++c) {
      out.push_back(c->second);
      open.push_back(c->second);
    }
  }
  return out;
}

}  // namespace

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

void PlotServer::signal_all(int signal) {
  kill(pid_, signal);
  for (int pass = 0; pass < 2; ++pass)
    for (const pid_t child : descendants(pid_)) kill(child, signal);
}

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
  const std::lock_guard guard(state_);
  const int spawned = posix_spawnp(&pid_, python.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(ends[1]);
  if (spawned != 0) {
    close(ends[0]);
    pid_ = 0;
    return false;
  }
  socket_ = ends[0];
  if (paused_) kill(pid_, SIGSTOP);  // paused before it started: it starts stopped
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
