// The interactive window's heads-up display: text over the view, in the UI font (ui_font.h), drawn
// in the view graph's overlay layer (view_graph.h), so it is never part of what the scene draws.
//
// Bottom left, one line each: frame rate and frame ms; walker µs per step and steps this frame;
// the tests per nested stage (Nv: AABB-AABB, AABB-OBB, OBB-OBB) and triangle tests (Np) of the
// last step; the map position (easting, northing, height) with the terrain's CRS; heading and
// pitch; the ground height under the body; walk or fly, sliding, the contact method; the terrain's
// chunks drawn, their largest error on screen, the cache's memory and chunks still loading. Top right:
// a status line (recording, paused, the last message). The blocked state itself is the graph's
// red frame and "BLOCKED by <unit>" (top left). H shows a help panel with every key; expectations
// of a script played in the window are listed under the status line as they are met or fail.
//
// Units as the walker's: metres, degrees, microseconds, milliseconds.
// Ownership: the nodes live in the graph's overlay layer. Thread safety: the viewer's thread.
#pragma once

#include "nestwalk/geometry/nested.h"

#include <osg/MatrixTransform>
#include <osg/ref_ptr>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace osgText {
class Text;
}

namespace nestwalk {

struct HudState {
  double fps = 0, frameMs = 0;
  double stepMicros = 0;
  int stepsThisFrame = 0;
  StageCounts stageTests{};
  std::uint64_t primitiveTests = 0;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();  // map frame
  std::string crs;
  double headingDeg = 0, pitchDeg = 0;
  bool hasGround = false;
  double ground = 0;
  bool flying = false, sliding = false;
  std::string method;
  std::size_t terrainChunks = 0, terrainLoading = 0;  // drawn; asked for and not yet resident
  double terrainErrorPx = 0, terrainMiB = 0, terrainBudgetMiB = 0;
  std::string status;                   // recording, paused, messages
  std::vector<std::string> expectations;  // "line 12: expect blocked by ...: met" (or FAILED and why)
};

class Hud {
 public:
  // Builds the text nodes under `layer` (a screen layer of width x height pixels). Throws
  // InputError naming the font file when it cannot be loaded.
  Hud(osg::MatrixTransform* layer, int width, int height);
  void update(const HudState& state);
  void setHelpVisible(bool visible);
  bool helpVisible() const { return helpVisible_; }
  // Hides or shows everything the HUD draws (the screenshot hides it, to show the view alone).
  void setVisible(bool visible);
  // The text of the lines as last set (for tests and the log).
  std::string text() const;

 private:
  osg::ref_ptr<osg::Group> root_;
  osg::ref_ptr<osg::Node> helpNode_;
  osg::ref_ptr<osgText::Text> lines_, status_, help_;
  bool helpVisible_ = false;
};

// The help panel's text: every key of `nestwalk view`, one per line, the key and what it does
// separated by a tab.
const char* viewerHelpText();

}  // namespace nestwalk
