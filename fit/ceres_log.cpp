#include "ceres_log.hpp"

#include <cstdlib>
#include <mutex>

#include <glog/logging.h>

namespace sglab::fit {

void quiet_ceres_warnings() {
  static std::once_flag once;
  // glog reads GLOG_minloglevel into FLAGS_minloglevel itself; only its absence is overridden.
  std::call_once(once, [] {
    if (!std::getenv("GLOG_minloglevel")) FLAGS_minloglevel = google::GLOG_ERROR;
  });
}

}  // namespace sglab::fit
