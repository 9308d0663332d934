// The interactive window's heads-up display (hud.h).
#include "nestwalk/viewer/hud.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/ui_font.h"

#include <osg/Geode>
#include <osgText/Font>
#include <osgText/Text>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace nestwalk {
namespace {

const osg::Vec4 kHudText(1.0f, 1.0f, 1.0f, 1.0f);
const osg::Vec4 kHudShadow(0.0f, 0.0f, 0.0f, 0.8f);
const osg::Vec4 kStatusText(1.0f, 0.85f, 0.2f, 1.0f);

std::string format(const char* f, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

osg::ref_ptr<osgText::Text> makeText(osgText::Font* font, float size, const osg::Vec4& colour) {
  osg::ref_ptr<osgText::Text> t = new osgText::Text;
  t->setFont(font);
  t->setCharacterSize(size);
  t->setColor(colour);
  // A dark outline keeps the text readable over the bright sky and the dark equipment alike.
  t->setBackdropType(osgText::Text::OUTLINE);
  t->setBackdropColor(kHudShadow);
  t->setDataVariance(osg::Object::DYNAMIC);
  return t;
}

}  // namespace

const char* viewerHelpText() {
  return "W / S, Up / Down\tforward, back\n"
         "A / D\tsideways\n"
         "Shift\trun\n"
         "mouse drag\tlook around\n"
         "M\tcapture the mouse (look without dragging)\n"
         "F\twalk / fly\n"
         "Q / E, PgUp / PgDn\tup / down (flying)\n"
         "G\tslide along contact faces on / off\n"
         "V\tshow the nested volumes\n"
         "R\tstart / stop recording (script + .path)\n"
         "P\tscreenshot (PNG)\n"
         "K / L\tpause / single step (a script)\n"
         "H\tthis help\n"
         "Esc\tquit";
}

Hud::Hud(osg::MatrixTransform* layer, int width, int height) {
  const std::string fontPath = uiFontPath();
  osg::ref_ptr<osgText::Font> font = osgText::readRefFontFile(fontPath);
  if (!font) throw InputError(fontPath + ": osgText cannot load the HUD's font (is OpenSceneGraph's freetype plugin installed?)");
  const float size = float(std::clamp(0.022 * height, 11.0, 28.0));
  const float margin = 0.6f * size;
  lines_ = makeText(font.get(), size, kHudText);
  lines_->setAlignment(osgText::Text::LEFT_BOTTOM);
  lines_->setPosition(osg::Vec3(margin, margin, 0));
  status_ = makeText(font.get(), size, kStatusText);
  status_->setAlignment(osgText::Text::RIGHT_TOP);
  status_->setPosition(osg::Vec3(float(width) - margin, float(height) - margin, 0));
  // The help: two columns, the keys right-aligned against the middle, what they do left-aligned.
  std::string keys, actions;
  for (const char* p = viewerHelpText(); *p;) {
    const char* tab = std::strchr(p, '\t');
    const char* end = std::strchr(p, '\n');
    if (!end) end = p + std::strlen(p);
    keys += std::string(p, tab) + "\n";
    actions += std::string(tab + 1, end) + "\n";
    p = *end ? end + 1 : end;
  }
  const float middle = 0.42f * float(width);
  osg::ref_ptr<osgText::Text> keyColumn = makeText(font.get(), size, kStatusText);
  keyColumn->setAlignment(osgText::Text::RIGHT_CENTER);
  keyColumn->setPosition(osg::Vec3(middle - margin, 0.5f * float(height), 0));
  keyColumn->setText(keys);
  help_ = makeText(font.get(), size, kHudText);
  help_->setAlignment(osgText::Text::LEFT_CENTER);
  help_->setPosition(osg::Vec3(middle + margin, 0.5f * float(height), 0));
  help_->setText(actions);
  osg::ref_ptr<osg::Geode> text = new osg::Geode;
  text->addDrawable(lines_);
  text->addDrawable(status_);
  text->setCullingActive(false);
  osg::ref_ptr<osg::Geode> help = new osg::Geode;
  help->addDrawable(keyColumn);
  help->addDrawable(help_);
  help->setCullingActive(false);
  help->setNodeMask(0);
  helpNode_ = help;
  osg::ref_ptr<osg::Group> root = new osg::Group;
  root->addChild(text);
  root->addChild(help);
  root_ = root;
  layer->addChild(root_);
}

void Hud::setHelpVisible(bool visible) {
  helpVisible_ = visible;
  helpNode_->setNodeMask(visible ? ~0u : 0u);
}

void Hud::setVisible(bool visible) { root_->setNodeMask(visible ? ~0u : 0u); }

void Hud::update(const HudState& s) {
  std::string t;
  t += format("%.1f fps   %.1f ms per frame\n", s.fps, s.frameMs);
  t += format("walker %.1f \u00b5s per step, %.0f steps this frame\n", s.stepMicros, s.stepsThisFrame);
  t += format("Nv aabb-aabb %.0f  aabb-obb %.0f  obb-obb %.0f", double(s.stageTests[OverlapStage::AabbAabb]),
              double(s.stageTests[OverlapStage::AabbObb]), double(s.stageTests[OverlapStage::ObbObb]));
  t += format("   Np %.0f\n", double(s.primitiveTests));
  t += format("E %.3f  N %.3f  H %.3f", s.eye.x(), s.eye.y(), s.eye.z()) + "  (" + s.crs + ")\n";
  t += format("heading %.1f  pitch %.1f", s.headingDeg, s.pitchDeg);
  t += s.hasGround ? format("   ground %.3f\n", s.ground) : std::string("   no ground\n");
  t += std::string(s.flying ? "flying" : "walking") + (s.sliding ? ", sliding" : "") + "   method " + s.method + "\n";
  t += format("terrain %.0f chunks, %.2f px", double(s.terrainChunks), s.terrainErrorPx);
  t += format("   %.0f of %.0f MiB", s.terrainMiB, s.terrainBudgetMiB);
  if (s.terrainLoading > 0) t += format("   loading %.0f", double(s.terrainLoading));
  lines_->setText(t, osgText::String::ENCODING_UTF8);
  std::string status = s.status;
  for (std::size_t i = 0; i < s.expectations.size(); ++i) status += (status.empty() ? "" : "\n") + s.expectations[i];
  status_->setText(status, osgText::String::ENCODING_UTF8);
}

std::string Hud::text() const { return lines_->getText().createUTF8EncodedString() + "\n" + status_->getText().createUTF8EncodedString(); }

}  // namespace nestwalk
