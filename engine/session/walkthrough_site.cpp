// A recorded run as a static web page (walkthrough_site.h).
#include "nestwalk/session/walkthrough_site.h"

#include "nestwalk/core/csv_reader.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/render/scene_gltf.h"
#include "nestwalk/render/view_depth.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/dem_reader.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// The run's own figures, in the order the page shows them, with their titles.
const std::pair<const char*, const char*> kRunFigures[] = {{"top_down.png", "Top-down map"},
                                                           {"frame_times.png", "Frame times"}};
/// The report's figures the page shows when a report folder is given.
const std::pair<const char*, const char*> kReportFigures[] = {{"pareto.png", "Speed against error (contact methods)"},
                                                              {"methods.png", "Microseconds per frame per method"},
                                                              {"model_weight.png", "Cost by model weight"}};

Json readJson(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": could not be opened");
  try {
    return Json::parse(in);
  } catch (const Json::exception& e) {
    throw InputError(file.string() + ": not valid JSON (" + e.what() + ")");
  }
}

/// The scene the run played: the options' one, else summary.json's "scene" as written (relative to
/// where the run was made), else relative to the run folder's parent.
fs::path sceneOf(const WalkthroughSiteOptions& o, const Json& summary, const fs::path& summaryFile) {
  if (!o.sceneFile.empty()) return o.sceneFile;
  if (!summary.contains("scene") || !summary["scene"].is_string())
    throw InputError(summaryFile.string() + ": names no scene (pass --scene)");
  const fs::path named = summary["scene"].get<std::string>();
  if (fs::exists(named)) return named;
  const fs::path beside = fs::path(o.runFolder).parent_path() / named;
  if (named.is_relative() && fs::exists(beside)) return beside;
  throw InputError(summaryFile.string() + ": its scene " + named.string() + " is not there (pass --scene)");
}

struct Frames {
  Json json = Json::object();
  std::map<long, std::size_t> rowOfFrame;
};

Frames readFrames(const fs::path& file, const Eigen::Vector3d& origin) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": could not be opened");
  CsvReader csv(in, file.string());
  const int frame = csv.column("frame"), time = csv.column("time"), x = csv.column("x"), y = csv.column("y"),
            z = csv.column("z"), heading = csv.column("heading"), pitch = csv.column("pitch"),
            blocked = csv.column("blocked");
  std::vector<double> t, xs, ys, zs, hs, ps;
  std::vector<int> bs;
  Frames out;
  std::vector<std::string> fields;
  while (csv.next(fields)) {
    out.rowOfFrame[std::lround(csv.number(fields, frame))] = t.size();
    t.push_back(csv.number(fields, time));
    xs.push_back(csv.number(fields, x) - origin.x());
    ys.push_back(csv.number(fields, y) - origin.y());
    zs.push_back(csv.number(fields, z) - origin.z());
    hs.push_back(csv.number(fields, heading));
    ps.push_back(csv.number(fields, pitch));
    bs.push_back(csv.number(fields, blocked) != 0 ? 1 : 0);
  }
  if (t.empty()) throw InputError(file.string() + ": holds no frame");
  out.json = {{"t", t}, {"x", xs}, {"y", ys}, {"z", zs}, {"heading", hs}, {"pitch", ps}, {"blocked", bs}};
  return out;
}

/// results.geojson's contacts, each at its frame's eye (local frame).
Json readContacts(const fs::path& file, const Frames& frames) {
  Json out = Json::array();
  if (!fs::exists(file)) return out;  // a run written before results.geojson existed: no contacts shown
  const Json doc = readJson(file);
  if (!doc.contains("features") || !doc["features"].is_array()) throw InputError(file.string() + ": no features");
  for (const Json& f : doc["features"]) {
    const Json& p = f.value("properties", Json::object());
    if (p.value("feature", "") != "contact") continue;
    const long frame = p.value("frame", -1L);
    const auto row = frames.rowOfFrame.find(frame);
    if (row == frames.rowOfFrame.end())
      throw InputError(file.string() + ": a contact at frame " + std::to_string(frame) +
                       ", which frames.csv does not hold");
    const std::size_t r = row->second;
    out.push_back({{"unit", p.value("unit", "")},
                   {"kind", p.value("kind", "")},
                   {"time_s", p.value("time_s", 0.0)},
                   {"frame", frame},
                   {"stop_gap_m", p.value("stop_gap_m", 0.0)},
                   {"approach_deg", p.value("approach_deg", 0.0)},
                   {"x", frames.json["x"][r]},
                   {"y", frames.json["y"][r]},
                   {"z", frames.json["z"][r]}});
  }
  return out;
}

std::string summaryLine(const Json& summary, std::size_t contacts) {
  std::ostringstream s;
  s << summary.value("frames", 0) << " frames, " << std::fixed;
  s.precision(1);
  s << summary.value("simulated_seconds", 0.0) << " s simulated; method " << summary.value("method", std::string("?"))
    << "; " << contacts << " contact" << (contacts == 1 ? "" : "s");
  return s.str();
}

}  // namespace

WalkthroughSite writeWalkthroughSite(const WalkthroughSiteOptions& o, const std::string& folder) {
  const fs::path run(o.runFolder), out(folder);
  if (!fs::is_directory(run)) throw InputError(o.runFolder + ": not a folder");
  for (const char* needed : {"summary.json", "frames.csv"})
    if (!fs::exists(run / needed))
      throw InputError(o.runFolder + ": is not a run's folder: " + needed +
                       " missing (write one with `nestwalk run --out`)");
  for (const char* page : {"index.html", "walkthrough.js"})
    if (!fs::exists(fs::path(o.pageFolder) / page))
      throw InputError(o.pageFolder + ": the walkthrough page's " + page + " is missing (build the web_page target)");

  WalkthroughSite site;
  const Json summary = readJson(run / "summary.json");
  site.sceneFile = sceneOf(o, summary, run / "summary.json").string();
  const Scene scene = loadScene(site.sceneFile);

  SceneGraphOptions graph;
  graph.terrainCut.maxErrorM = o.maxErrorM;
  // Instanced equipment: one draw call per model mesh instead of one per instance, in the browser.
  site.gltf = writeSceneGltf(scene, graph, (out / "scene.glb").string(), true, true).gltf;

  const Frames frames = readFrames(run / "frames.csv", scene.origin);
  site.frames = frames.json["t"].size();
  Json doc;
  doc["title"] = fs::path(summary.value("script", std::string("run"))).stem().string() + " on " +
                 fs::path(site.sceneFile).parent_path().filename().string();
  doc["fov_y_deg"] = o.fovYDegrees;
  const ViewDepth depth = viewDepth(scene);  // the renderer's camera range and haze
  doc["near_m"] = depth.nearM;
  doc["far_m"] = depth.farM;
  doc["haze_m"] = {depth.hazeStartM, depth.hazeEndM};
  doc["sky_horizon_rgb"] = kSkyHorizonRgb;
  doc["scene"] = "scene.glb";
  doc["map_origin"] = {scene.origin.x(), scene.origin.y(), scene.origin.z()};
  const std::string& wkt = scene.terrain->crsWkt();
  doc["crs_name"] = wkt.empty() ? std::string() : terrain::crsName(wkt);
  doc["frames"] = frames.json;
  doc["contacts"] = readContacts(run / "results.geojson", frames);
  site.contacts = doc["contacts"].size();
  doc["summary"] = summaryLine(summary, site.contacts);
  doc["expectations"] = Json::array();
  if (summary.contains("expectations") && summary["expectations"].contains("list"))
    for (const Json& e : summary["expectations"]["list"])
      doc["expectations"].push_back({{"text", e.value("text", std::string())}, {"met", e.value("met", false)}});
  site.expectations = doc["expectations"].size();

  doc["figures"] = Json::array();
  auto figure = [&](const fs::path& from, const char* file, const char* title) {
    if (!fs::exists(from / file)) return;
    const std::string name = fs::exists(out / file) ? std::string("report_") + file : std::string(file);
    fs::copy_file(from / file, out / name);
    doc["figures"].push_back({{"file", name}, {"title", title}});
  };
  for (const auto& [file, title] : kRunFigures) figure(run, file, title);
  if (!o.reportFolder.empty()) {
    if (!fs::is_directory(o.reportFolder))
      throw InputError(o.reportFolder + ": not a folder (a `nestwalk report --out` folder)");
    for (const auto& [file, title] : kReportFigures) figure(o.reportFolder, file, title);
  }
  site.figures = doc["figures"].size();

  writeFileAtomically((out / "run.json").string(), doc.dump());
  for (const char* page : {"index.html", "walkthrough.js"}) fs::copy_file(fs::path(o.pageFolder) / page, out / page);
  return site;
}

}  // namespace nestwalk
