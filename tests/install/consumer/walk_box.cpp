// walk_box SCENE X Y HEADING SPEED: loads a scene with the installed nestwalk, places the walker's
// body box at map (X, Y) facing HEADING (degrees clockwise from north), walks it 100 steps of
// 1/60 s at SPEED m/s straight ahead and prints every step whose contact state changes:
//   step 37: blocked by bench2/station0/mast
// then "walked 100 steps from X Y to X' Y'". Exit 0, or 1 with the error.
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/version.h"
#include "nestwalk/walker/collision_world.h"
#include "nestwalk/walker/walker.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <numbers>

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: walk_box SCENE X Y HEADING SPEED (nestwalk %s)\n", nestwalk::kVersion);
    return 2;
  }
  try {
    const nestwalk::Scene scene = nestwalk::loadScene(argv[1]);
    const nestwalk::CollisionWorld world = nestwalk::CollisionWorld::fromScene(scene, scene.spec.method);
    nestwalk::WalkerOptions options;
    options.viewer = scene.spec.viewer;
    nestwalk::Walker walker(*scene.terrain, world, scene.origin, options);
    const double x = std::atof(argv[2]), y = std::atof(argv[3]), heading = std::atof(argv[4]);
    const double speed = std::atof(argv[5]);
    const std::string problem = walker.place({x, y, 0}, false, heading, false, 0);
    if (!problem.empty()) {
      std::fprintf(stderr, "walk_box: cannot start there: %s\n", problem.c_str());
      return 1;
    }
    const double rad = heading * std::numbers::pi / 180;
    nestwalk::StepInput in;
    in.move = Eigen::Vector3d(std::sin(rad), std::cos(rad), 0) * speed * options.dt;
    in.headingDeg = heading;
    bool blocked = false;
    for (int k = 1; k <= 100; ++k) {
      walker.step(in);
      const nestwalk::WalkerState& s = walker.state();
      if (s.blocked != blocked) {
        blocked = s.blocked;
        if (blocked && s.blockedUnit >= 0)
          std::printf("step %d: blocked by %s\n", k, world.name(std::size_t(s.blockedUnit)).c_str());
        else
          std::printf("step %d: %s\n", k, blocked ? nestwalk::blockReasonName(s.reason) : "free");
      }
    }
    const Eigen::Vector3d& feet = walker.state().feet;
    std::printf("walked 100 steps from %.3f %.3f to %.3f %.3f\n", x, y, feet.x(), feet.y());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "walk_box: %s\n", e.what());
    return 1;
  }
  return 0;
}
