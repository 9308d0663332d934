#include "tools/bench/peers/peer_versions.h"

#include <Eigen/Core>
#include <LinearMath/btScalar.h>
#include <ccd/ccd.h>
#include <embree3/rtcore.h>
#include <fcl/config.h>
#include <osg/Version>

#include <string>

namespace nestwalk::bench {

Json peerVersions() {
  return {{"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                        std::to_string(EIGEN_MINOR_VERSION)},
          {"fcl", FCL_VERSION},
          {"ccd", sizeof(ccd_real_t) == 8 ? "double" : "float"},
          {"bullet",
           std::to_string(BT_BULLET_VERSION) + (sizeof(btScalar) == 8 ? " (btScalar double)" : " (btScalar float)")},
          {"embree", RTC_VERSION_STRING},
          {"openscenegraph", osgGetVersion()}};
}

}  // namespace nestwalk::bench
