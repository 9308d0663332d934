// nestwalk report [SCENE] [--scripts A B C] --out DIR [--quick] [--overwrite]: the methods report
// (tools/bench/method_report.h): every contact method over the flythroughs against the exact
// reference, the terrain levels of detail and the OBB fitters, as report.md with PNG plots and
// report.json in DIR. SCENE defaults to the bundled mining dump; the scripts to every .txt in the
// scripts/ folder beside the scene file (the bundled scene's three flythroughs).
#include "nestwalk/core/input_error.h"
#include "nestwalk/report/method_report.h"
#include "tools/nestwalk/commands.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

namespace nestwalk::tools {
namespace {

/// The flythrough scripts beside a scene file: scripts/*.txt, sorted by name.
std::vector<std::string> scriptsBeside(const std::filesystem::path& scene) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(scene.parent_path() / "scripts", ec))
    if (entry.is_regular_file() && entry.path().extension() == ".txt") found.push_back(entry.path().string());
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace

void registerReport(CLI::App& app) {
  auto opts = std::make_shared<MethodReportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "report", "Every contact method over the flythroughs (time, missed contacts, false blocks, stop gap), terrain "
                "LOD error and OBB fitters: report.md with PNG plots and report.json");
  cmd->add_option("SCENE", opts->scene, "Scene file (default: the bundled mining dump)");
  cmd->add_option("--scripts", opts->scripts, "Flythrough scripts (default: scripts/*.txt beside the scene file)");
  cmd->add_option("--out", opts->out, "Folder for the report's files")->required();
  cmd->add_flag("--quick", opts->quick,
                "Quick settings (CI): one timing play per method and flythrough, 20k terrain points, one fit per model");
  cmd->add_flag("--overwrite", opts->overwrite, "Replace the report's files in the folder");
  cmd->callback([opts] {
    MethodReportOptions o = *opts;
    if (o.scene.empty()) {
      o.scene = (std::filesystem::path(NESTWALK_BUNDLED_SCENE_DIR) / "scene.json").string();
      if (!std::filesystem::exists(o.scene))
        throw InputError(o.scene + ": the bundled scene is absent; build the bundled_scene target or give SCENE");
    }
    if (o.scripts.empty()) o.scripts = scriptsBeside(o.scene);
    if (o.scripts.empty())
      throw InputError(o.scene + ": no flythrough scripts in its scripts/ folder; give them with --scripts");
    const int rc = runMethodReport(o, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace nestwalk::tools
