#include "nestwalk/walker/frame_record.h"

namespace nestwalk {

const char* stepPartName(StepPart p) {
  switch (p) {
    case StepPart::Ground: return "ground";
    case StepPart::BroadPhase: return "broad";
    case StepPart::Narrow: return "narrow";
    case StepPart::Total: return "total";
  }
  return "?";
}

}  // namespace nestwalk
