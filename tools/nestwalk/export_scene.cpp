// nestwalk export SCENE OUT [--volumes] [--no-terrain] [--max-error M] [--chunk-cells N] [--overwrite]:
// loads a scene and writes its OpenSceneGraph graph (render/scene_graph.h: the terrain as one cut of
// the chunk quadtree the renderer draws, within M metres of the DEM's surface, render/terrain_cut.h)
// in any format OSG writes, chosen by OUT's extension (.osgb, .osgt, .ive, ...), for viewing in
// osgviewer or other tools, or as glTF 2.0 (.glb, .gltf: render/gltf_scene_writer.h, the terrain
// with the scene's imagery as textures, the map origin in the asset's extras). The file is written under a temporary name in OUT's folder and renamed
// at the end; an existing OUT is replaced only with --overwrite. Prints one summary line.
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/number_text.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/render/scene_gltf.h"
#include "nestwalk/render/scene_graph.h"
#include "nestwalk/scene/scene_loader.h"
#include "tools/nestwalk/commands.h"

#include <osgDB/FileNameUtils>
#include <osgDB/Registry>

#include <cstdio>
#include <filesystem>
#include <memory>

namespace nestwalk::tools {
namespace {

namespace fs = std::filesystem;

/// OSG's text writers' option for the digits of floating-point output: 17 round-trips a double.
constexpr const char* kPrecisionOption = "precision 17";

struct ExportArgs {
  std::string scene, out;
  bool volumes = false, noTerrain = false, overwrite = false, instancing = false;
  TerrainCutOptions terrain;
};

bool isGltf(const std::string& ext) { return ext == "glb" || ext == "gltf"; }

/// Checks OUT before anything is loaded: a known format, a folder that exists, not a folder itself,
/// not an existing file unless --overwrite.
std::string checkOutput(const ExportArgs& a) {
  const std::string ext = osgDB::getLowerCaseFileExtension(a.out);
  if (ext.empty()) throw InputError(a.out + ": no file extension: name the format (.glb, .gltf, .osgb, .osgt, .ive, ...)");
  if (!isGltf(ext) && !osgDB::Registry::instance()->getReaderWriterForExtension(ext))
    throw InputError(a.out + ": OpenSceneGraph has no plugin for '." + ext + "' files (try .glb, .gltf, .osgb, .osgt or .ive)");
  const fs::path out(a.out);
  const fs::path folder = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  if (!fs::is_directory(folder)) throw InputError(a.out + ": the folder " + folder.string() + " does not exist");
  if (fs::is_directory(out)) throw InputError(a.out + ": is a folder");
  if (fs::exists(out) && !a.overwrite) throw InputError(a.out + ": exists; pass --overwrite to replace it");
  const int cells = a.terrain.chunkCells;
  if (cells < 2 || (cells & (cells - 1)) != 0)
    throw InputError("--chunk-cells: expected a power of two >= 2, got " + std::to_string(cells));
  return ext;
}

void printSummary(const ExportArgs& a, const Scene& scene, const SceneGraphOptions& go, const SceneGraphParts& parts);

void runExport(const ExportArgs& a) {
  const std::string ext = checkOutput(a);
  const Scene scene = loadScene(a.scene);
  SceneGraphOptions go;
  go.terrain = !a.noTerrain;
  go.volumes = a.volumes;
  go.terrainCut = a.terrain;
  OutputFile file(a.out, "." + ext);
  if (isGltf(ext)) {
    SceneGltf written;
    try {
      written = writeSceneGltf(scene, go, file.tempPath(), ext == "glb", a.instancing);
    } catch (const InputError&) {
      throw;  // names its own file (the imagery, a model)
    } catch (const std::runtime_error& e) {
      throw InputError(a.out + ": " + e.what());  // the glTF file could not be written
    }
    const GltfWriteStats& gltf = written.gltf;
    const SceneGraphParts& parts = written.parts;
    file.commit();
    printSummary(a, scene, go, parts);
    std::printf("  glTF: %zu nodes, %zu meshes, %zu materials, %zu images, %s MB\n", gltf.nodes, gltf.meshes,
                gltf.materials, gltf.images, shortText(double(gltf.bytes) / 1e6).c_str());
    for (const std::string& note : gltf.notes) std::fprintf(stderr, "nestwalk: export: %s\n", note.c_str());
    return;
  }
  SceneGraphParts parts;
  const osg::ref_ptr<osg::Group> graph = buildSceneGraph(scene, go, &parts);
  osgDB::Registry* registry = osgDB::Registry::instance();
  osg::ref_ptr<osgDB::Options> options =
      registry->getOptions() ? static_cast<osgDB::Options*>(registry->getOptions()->clone(osg::CopyOp::SHALLOW_COPY))
                             : new osgDB::Options;
  // Text formats (.osgt, .osg) print doubles with 17 significant digits, so the UTM translations
  // read back bit for bit (OSG's default loses the last bit, ~1e-9 m); binary formats ignore it.
  options->setOptionString(options->getOptionString() + (options->getOptionString().empty() ? "" : " ") + kPrecisionOption);
  const osgDB::ReaderWriter::WriteResult wr = registry->writeNode(*graph, file.tempPath(), options.get());
  if (!wr.success() || !fs::exists(file.tempPath()))
    throw InputError(a.out + ": OpenSceneGraph could not write the file" + (wr.message().empty() ? "" : ": " + wr.message()));
  file.commit();
  printSummary(a, scene, go, parts);
}

void printSummary(const ExportArgs& a, const Scene& scene, const SceneGraphOptions& go, const SceneGraphParts& parts) {
  std::size_t triangles = 0;
  for (const auto& inst : scene.instances) triangles += scene.models[inst.model].mesh.triangles.size();
  std::printf("wrote %s: %zu instances, %zu models, %zu equipment triangles, %zu units", a.out.c_str(),
              scene.instances.size(), scene.models.size(), triangles, scene.units.size());
  if (go.terrain) {
    const TerrainCutStats& cut = parts.terrainCut;
    std::printf(", terrain %d x %d samples: %zu chunk%s, %zu triangles, error <= %s m", scene.terrain->cols(),
                scene.terrain->rows(), cut.chunks, cut.chunks == 1 ? "" : "s", cut.surfaceTriangles,
                shortText(cut.maxErrorM).c_str());
  }
  if (go.volumes) std::printf(", volume wireframes");
  std::printf("\n");
}

}  // namespace

void registerExport(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "export", "Write a scene's OpenSceneGraph graph (terrain, equipment, optional volume wireframes) to a file");
  cmd->add_option("SCENE", args->scene, "Scene file (.json)")->required();
  cmd->add_option("OUT", args->out,
                  "Output file; the extension picks the format (.glb, .gltf: glTF 2.0; .osgb, .osgt, .ive, ...: OpenSceneGraph)")
      ->required();
  cmd->add_flag("--volumes", args->volumes, "Add the units' outer AABBs and inner OBBs as wireframes");
  cmd->add_flag("--no-terrain", args->noTerrain, "Leave the terrain out");
  cmd->add_option("--max-error", args->terrain.maxErrorM,
                  "The terrain's largest vertical error against the DEM, metres (0: the full grid)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--chunk-cells", args->terrain.chunkCells, "Terrain chunk side in cells, a power of two")
      ->capture_default_str();
  cmd->add_flag("--instancing", args->instancing,
                "glTF: each model's instances as EXT_mesh_gpu_instancing (fewer draw calls; readers must support it)");
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing OUT");
  cmd->callback([args] { runExport(*args); });
}

}  // namespace nestwalk::tools
