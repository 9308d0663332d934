// OpenSceneGraph's messages (plugin warnings such as "Obj unable to find material") go to stderr
// with a prefix, so that a command's stdout holds only its result (JSON, CSV).
// Thread safety: sets OSG's process-wide notify handler and level: call once at start-up, before
// other threads use OSG. The handler writes each message with one fprintf to stderr.
#pragma once

namespace nestwalk {

/// Installs the handler; OSG's level stays WARN unless OSG_NOTIFY_LEVEL says otherwise.
void routeOsgMessagesToStderr();

}  // namespace nestwalk
