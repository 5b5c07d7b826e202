// Ceres 2.1 logs through glog; what of it a fit shows.
#pragma once

namespace sglab::fit {

// The WARNINGs Ceres has written in these fits are steps it handles itself (in the environment
// fits, a Levenberg–Marquardt step whose conjugate-gradient solve meets r'z = 0 is rejected and the
// trust region shrunk; twice in a full `sglab reproduce`), while each fit reports its own outcome
// (its summary, the fit record). So glog's least level shown is ERROR,
// unless GLOG_minloglevel is set in the environment (`GLOG_minloglevel=0 sglab …` shows the
// warnings). Called by every function that runs Ceres solves; sets it once per process.
void quiet_ceres_warnings();

}  // namespace sglab::fit
