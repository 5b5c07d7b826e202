// Ceres 2.1 logs through glog; what of it a fit shows.
#pragma once

namespace sglab::fit {

// Ceres' WARNINGs in these fits are steps it handles itself (a Levenberg–Marquardt step whose
// conjugate-gradient solve meets r'z = 0 is rejected and the trust region shrunk), while each fit
// reports its own outcome (its summary, the fit record). So glog's least level shown is ERROR,
// unless GLOG_minloglevel is set in the environment (`GLOG_minloglevel=0 sglab …` shows the
// warnings). Called before every Ceres solve; sets it once per process.
void quiet_ceres_warnings();

}  // namespace sglab::fit
