#include "nestwalk/scene/osg_messages.h"

#include <osg/Notify>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace nestwalk {
namespace {

class StderrNotifyHandler : public osg::NotifyHandler {
 public:
  void notify(osg::NotifySeverity, const char* message) override {
    const std::size_t n = std::strlen(message);
    if (n == 0 || (n == 1 && message[0] == '\n')) return;
    std::fprintf(stderr, "nestwalk: osg: %s%s", message, message[n - 1] == '\n' ? "" : "\n");
  }
};

}  // namespace

void routeOsgMessagesToStderr() {
  osg::setNotifyHandler(new StderrNotifyHandler);
  if (!std::getenv("OSG_NOTIFY_LEVEL")) osg::setNotifyLevel(osg::WARN);
}

}  // namespace nestwalk
