// The plot steps of `sglab reproduce`: their interpreters (PlotServer) and the queue that runs them
// beside the sglab steps (PlotQueue). Used by reproduce.cpp alone.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <sys/types.h>

namespace sglab::experiments {

// The plot steps' interpreter: one `python3 plots/_serve.py` for the whole run, which runs each
// plot script as `python3 SCRIPT ARGS` would (as __main__, with that sys.argv), so that the
// interpreter's start and `import matplotlib` are paid once, not once per plot. Debian's
// interpreter, which has python3-matplotlib (a python3 earlier on PATH, from pyenv or a venv, may
// not). Requests and answers go through a socket (a write to a server that died is an error,
// not SIGPIPE); see plots/_serve.py. run() is used by one thread at a time (a plot queue's
// worker); pause() and resume() by any.
class PlotServer {
 public:
  PlotServer() = default;
  PlotServer(const PlotServer&) = delete;
  PlotServer& operator=(const PlotServer&) = delete;
  ~PlotServer() { stop(); }

  // What a plot did: its exit status (127: no interpreter; 128: the interpreter died), its CPU
  // seconds, the seconds it was paused, and the files it wrote (absolute paths, as
  // plots/_serve.py reports them).
  struct Outcome {
    int status = 128;
    double cpu = 0.0, paused = 0.0;
    std::set<std::string> wrote;
  };
  // Runs `python3 ARGS` (ARGS[0]: the script, beside which _serve.py lies).
  Outcome run(const std::vector<std::string>& args);

  // Stops the interpreter and its worker processes where they are (SIGSTOP), now or, if it is
  // not running yet, as soon as it starts; resume() continues them (SIGCONT). For the timed
  // steps, which run with nothing beside them: a paused plot uses no CPU and finishes later.
  // The interpreter leads a process group of its own, which its worker processes join, so that
  // none of them outlives sglab stopped: sglab's SIGINT/SIGTERM handler ends the group
  // (runner/fatal_signal.hpp; a Ctrl-C reaches the plots that way, not from the terminal), and
  // however else sglab ends, the group, orphaned then, gets SIGHUP and SIGCONT from the kernel if
  // a process of it is stopped at that moment (a running one ends at the end of its requests).
  // In sglab's own group a stopped interpreter would stay stopped for as long as that group had
  // a process whose parent is outside it, such as the script that called sglab.
  void pause();
  void resume();

  // Ends the interpreter (the end of its requests) and waits for it, so that its CPU counts
  // among this process's finished children.
  void stop();

 private:
  bool started();
  double paused_seconds();
  // `signal` to the interpreter's process group: the interpreter and a script's worker processes.
  void signal_all(int signal);
  bool start(const std::filesystem::path& server);
  Outcome died();

  std::mutex state_;     // pid_ and the pause, shared by the plot thread (run) and the main thread
  pid_t pid_ = 0;        // the interpreter, which leads its process group (ID pid_)
  int group_slot_ = -1;  // its slot in the fatal-signal handler's table of groups
  int socket_ = -1;
  bool paused_ = false;
  std::chrono::steady_clock::time_point paused_since_;
  double paused_total_ = 0.0;  // seconds paused so far
};

// How many plots run at once: each is one Python process (a worker pool of its own in a few).
inline constexpr std::size_t kPlotWorkers = 2;

// The plot steps, on threads of their own (one per PlotServer, each its own interpreter), beside
// the sglab steps of the main thread: nothing reads a figure, and a plot's inputs are written by
// earlier sglab steps. Queued plots start beside the next sglab step that is not timed (or at the
// end). Before a timed step the plots running then are paused (PlotServer::pause) and the queue
// holds the others until the next untimed step: the timed step runs alone, and the main thread
// waits for no plot. After a failure no other plot starts; the first failure is rethrown by the
// next hold() or drain().
class PlotQueue {
 public:
  using Job = std::function<void(PlotServer&)>;
  explicit PlotQueue(std::size_t workers) : servers_(workers > 0 ? workers : 1) {}
  PlotQueue(const PlotQueue&) = delete;
  PlotQueue& operator=(const PlotQueue&) = delete;
  ~PlotQueue();

  // Queues `jobs` and lets the queue run beside what the caller does next.
  void release(std::vector<Job>& jobs);
  // Pauses the plots running now; no other starts until the next release().
  void hold();
  // Queues `jobs`, waits until every queued plot has run, then ends the interpreters (so that
  // their CPU counts among this process's finished children).
  void drain(std::vector<Job>& jobs);

 private:
  void loop(PlotServer& server);
  void rethrow();

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Job> queued_;
  int running_ = 0;
  bool held_ = false, stop_ = false;
  std::exception_ptr failure_;
  std::deque<PlotServer> servers_;    // one per worker; a deque: it does not move them
  std::vector<std::thread> workers_;  // last: started once the members they use exist
};

}  // namespace sglab::experiments
