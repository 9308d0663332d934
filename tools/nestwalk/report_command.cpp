// nestwalk report [SCENE] [--scripts A B C] --out DIR [--quick] [--overwrite]: the methods report
// (engine/report/method_report.h): every contact method over the flythroughs against the exact
// reference, the terrain levels of detail and the OBB fitters, as report.md with PNG plots and
// report.json in DIR. SCENE defaults to the bundled mining dump; the scripts to every .txt in the
// scripts/ folder beside the scene file (the bundled scene's three flythroughs).
#include "assets/generators/bundled_scene.h"
#include "nestwalk/report/method_report.h"
#include "tools/nestwalk/commands.h"

#include <iostream>
#include <memory>

namespace nestwalk::tools {

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
    assets::defaultSceneAndScripts(o.scene, o.scripts);
    const int rc = runMethodReport(o, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace nestwalk::tools
