// A walk session in a window (`nestwalk view`): the session (walk_session.h) drawn by an
// osgViewer window (X, GLX; works under `xvfb-run`) with the same view graph as the offscreen
// renderer, walked by hand through the manipulator (viewer/walk_manipulator.h), with the HUD
// (viewer/hud.h).
//
// Keys beyond the manipulator's (H lists them all: viewer/hud.cpp, viewerHelpText): V toggles the nested
// volumes, H the help, P writes a screenshot (OSG's ScreenCaptureHandler, the frame without the
// HUD: the view as `run --render` draws it) to the next free screenshot_NNN.png, R starts and
// stops a recording. With a script the window plays it in real time (K pauses, L steps).
// Every event is one line through the session's `say` sink: the window, each block, each
// screenshot with its pose, each recording, and at the end the final pose and the frame rate.
//
// Errors: InputError when there is no display (DISPLAY unset) or no window can be opened there,
// and the session's own. Ownership: everything is made and released by runWalkWindow.
// Thread safety: one window per thread (osgViewer runs single-threaded here).
#pragma once

#include "nestwalk/render/view_graph.h"
#include "nestwalk/session/walk_session.h"

#include <string>

namespace nestwalk {

struct WalkWindowOptions {
  WalkSessionOptions session;
  RenderOptions view;              // size (the window's), terrain paging; volumes are always built
  bool fullscreen = false;
  bool showVolumes = false;        // start with the volumes shown
  std::string screenshots = ".";   // folder for screenshot_NNN.png
  int frames = 0;                  // quit after this many frames (0: on Esc)
  double seconds = 0;              // quit after this many seconds (0: on Esc)
};

/// Runs the window until Esc, `frames` or `seconds`. Returns whether a played script met every
/// expectation (true without a script).
bool runWalkWindow(const WalkWindowOptions& options);

}  // namespace nestwalk
