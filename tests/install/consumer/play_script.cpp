// play_script SCENE SCRIPT OUT: plays a flythrough script on a scene with the installed nestwalk
// and writes the run's folder (frames.csv, summary.json, the plots, camera.path) through the
// session module, as `nestwalk run` does; prints "N frames, M of K expectations met".
// Exit 0 when every expectation was met, 3 when one failed, 1 with the error.
#include "nestwalk/session/recorded_run.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: play_script SCENE SCRIPT OUT\n");
    return 2;
  }
  try {
    nestwalk::RecordedRunOptions options;
    options.scene = argv[1];
    options.script = argv[2];
    options.out = argv[3];
    const nestwalk::RecordedRun run = nestwalk::recordRun(options);
    std::printf("%zu frames, %zu of %zu expectations met\n", run.flythrough.records.size(), run.expectationsMet,
                run.flythrough.expectations.size());
    return run.flythrough.expectationsMet() ? 0 : 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "play_script: %s\n", e.what());
    return 1;
  }
}
