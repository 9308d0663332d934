// A loaded scene as glTF (scene_gltf.h).
#include "nestwalk/render/scene_gltf.h"

#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/terrain_imagery.h"
#include "nestwalk/version.h"

#include <memory>

namespace nestwalk {

SceneGltf writeSceneGltf(const Scene& scene, SceneGraphOptions options, const std::string& path, bool binary,
                         bool instancing) {
  if (!scene.drapedImagery.empty() && options.terrain) {
    auto imagery = std::make_shared<terrain::TerrainImagery>(scene.drapedImagery, scene.terrain->crsWkt());
    options.terrainCut.imagery = [imagery](double x0, double y0, double sx, double sy, int w, int h) {
      return imagery->read(x0, y0, sx, sy, w, h);
    };
  }
  SceneGltf out;
  const osg::ref_ptr<osg::Group> graph = buildSceneGraph(scene, options, &out.parts);
  // The local frame's parts: glTF is local metres, the map origin goes into the asset's extras.
  osg::ref_ptr<osg::Group> local = new osg::Group;
  local->setName("scene");
  for (osg::Node* part :
       {static_cast<osg::Node*>(out.parts.terrain.get()), static_cast<osg::Node*>(out.parts.equipment.get()),
        static_cast<osg::Node*>(out.parts.volumes.get())})
    if (part) local->addChild(part);
  // As the renderer draws the terrain (view_graph.cpp): unlit (its colours carry the shading), and
  // only from above (back faces culled: the slopes turned away, the skirts' inner sides).
  if (out.parts.terrain) {
    osg::StateSet* terrain = out.parts.terrain->getOrCreateStateSet();
    terrain->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
    terrain->setMode(GL_CULL_FACE, osg::StateAttribute::ON);
  }
  GltfSceneInfo info;
  info.mapOrigin = scene.origin;
  info.crsWkt = scene.terrain->crsWkt();
  info.crsName = info.crsWkt.empty() ? "" : terrain::crsName(info.crsWkt);
  info.generator = std::string("nestwalk ") + kVersion;
  info.instancing = instancing;
  out.gltf = writeGltfScene(*local, info, path, binary);
  return out;
}

}  // namespace nestwalk
