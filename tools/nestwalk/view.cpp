// nestwalk view SCENE [--script FILE] [--size WxH] [--fullscreen] [--method M] ...: the scene in a
// window, walked by hand with the same walker and the same view graph as `nestwalk run`
// (engine/session/walk_window.h: the window, its keys and its loop; engine/session/walk_session.h:
// the start, the played script, the recordings, the HUD's data and the frame rate).
//
// Standard output gets one line per event, for people and tests alike: the window, each block
// ("blocked by NAME at E N H"), each screenshot with its pose, each recording, and at the end the
// final pose and the frame rate ("frames N in T s: F fps, frame ms p50 A p95 B").
// Exit: 0; 1 for bad input and for no display (the message says to use xvfb-run or run --render);
// 3 when a played script's expectation failed.
#include "nestwalk/session/walk_window.h"
#include "tools/nestwalk/commands.h"
#include "tools/nestwalk/walk_options.h"

#include <cstdio>
#include <memory>

namespace nestwalk::tools {
namespace {

struct ViewArgs {
  WalkWindowOptions window;
  std::string size = "1280x720";
  MethodOverrides method;
  TerrainArgs terrain;
};

void runView(ViewArgs& args) {
  WalkWindowOptions& w = args.window;
  std::tie(w.view.width, w.view.height) = parseFrameSize(args.size);
  applyTerrainArgs(args.terrain, w.view);
  w.session.method = [&args](const MethodSpec& m) { return applyMethodOverrides(args.method, m); };
  w.session.say = [](const std::string& line) {
    std::printf("view: %s\n", line.c_str());
    std::fflush(stdout);
  };
  if (!runWalkWindow(w)) throw CLI::RuntimeError(3);
}

}  // namespace

void registerView(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  WalkWindowOptions& w = args->window;
  CLI::App* cmd = app.add_subcommand("view", "Walk a scene by hand in a window (X; xvfb-run works), with the same walker as run");
  cmd->add_option("SCENE", w.session.scene, "Scene file (JSON, see README)")->required();
  cmd->add_option("--script", w.session.script, "Play this flythrough script in the window (K pauses, L steps)")->check(CLI::ExistingFile);
  cmd->add_option("--size", args->size, "Window size, WIDTHxHEIGHT (default 1280x720)");
  cmd->add_flag("--fullscreen", w.fullscreen, "Fill the screen instead of a window");
  cmd->add_option("--start", w.session.start, "Start at map X Y [HEADING] (default: the terrain's centre, heading north)")
      ->expected(2, 3);
  cmd->add_flag("--fly", w.session.fly, "Start flying");
  cmd->add_flag("--show-volumes", w.showVolumes, "Start with the nested volumes shown (V toggles)");
  cmd->add_option("--record", w.session.recordFolder, "Folder for recordings (R): walk_NNN.txt and walk_NNN.path (default ./recordings)");
  cmd->add_option("--screenshots", w.screenshots, "Folder for screenshots (P): screenshot_NNN.png (default .)");
  cmd->add_flag("--overwrite", w.session.overwrite, "Write into an existing recording folder, replacing its files");
  cmd->add_option("--hz", w.session.hz, "Walker steps per second (fixed time step 1/hz; default 60)")->check(CLI::Range(1.0, 10000.0));
  cmd->add_option("--method", args->method.volumes, "Contact test: nested (default), aabb, obb, nested+mesh, kdop18, auto (overrides the scene)");
  addTerrainOptions(*cmd, args->terrain, "background");
  cmd->add_option("--frames", w.frames, "Quit after this many frames (0: on Esc)");
  cmd->add_option("--seconds", w.seconds, "Quit after this many seconds (0: on Esc)");
  cmd->callback([args]() { runView(*args); });
}

}  // namespace nestwalk::tools
