// nestwalk publish RUN_DIR --out SITE [--scene SCENE] [--report DIR] [--max-error M] [--overwrite]:
// a recorded run as a static web page (session/walkthrough_site.h): the scene as GLB, the camera
// path, contacts and expectations, the figures, and the page (tools/web, three.js bundled at build
// time). SITE is written as a temporary folder beside it and renamed at the end; an existing SITE
// is replaced only with --overwrite. Prints what it wrote and how to open it.
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/number_text.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/render/view_options.h"
#include "nestwalk/session/walkthrough_site.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <filesystem>
#include <memory>

namespace nestwalk::tools {
namespace {

namespace fs = std::filesystem;

struct PublishArgs {
  std::string run, out, scene, report;
  double maxErrorM = WalkthroughSiteOptions{}.maxErrorM;
  bool overwrite = false;
};

/// The page's files: beside the installed program (PREFIX/share/nestwalk/web), else in the build.
std::string pageFolder() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = self.parent_path().parent_path() / "share" / "nestwalk" / "web";
    if (fs::exists(installed / "walkthrough.js")) return installed.string();
  }
  return NESTWALK_WEB_BUILD_DIR;
}

void runPublish(const PublishArgs& a) {
  if (fs::exists(a.out) && !a.overwrite) throw InputError(a.out + ": exists; pass --overwrite to replace it");
  WalkthroughSiteOptions o;
  o.runFolder = a.run;
  o.sceneFile = a.scene;
  o.reportFolder = a.report;
  o.pageFolder = pageFolder();
  o.maxErrorM = a.maxErrorM;
  o.fovYDegrees = RenderOptions{}.fovYDegrees;
  OutputFolder site(a.out);
  const WalkthroughSite w = writeWalkthroughSite(o, site.tempPath());
  site.commit();
  std::printf(
      "published %s as %s: %zu frames, %zu contacts, %zu expectations, %zu figures; scene.glb %s MB "
      "(%s, terrain within %s m)\n",
      a.run.c_str(), a.out.c_str(), w.frames, w.contacts, w.expectations, w.figures,
      shortText(double(w.gltf.bytes) / 1e6).c_str(), w.sceneFile.c_str(), shortText(a.maxErrorM).c_str());
  std::printf(
      "  open it through any static file server: cd %s && python3 -m http.server, then http://localhost:8000/\n",
      a.out.c_str());
}

}  // namespace

void registerPublish(CLI::App& app) {
  auto args = std::make_shared<PublishArgs>();
  CLI::App* cmd =
      app.add_subcommand("publish", "Publish a recorded run as a static web page (3-D walkthrough, contacts, figures)");
  cmd->add_option("RUN_DIR", args->run, "A run's folder (nestwalk run --out)")->required();
  cmd->add_option("--out", args->out, "The site's folder")->required();
  cmd->add_option("--scene", args->scene, "The run's scene (default: the one its summary.json names)");
  cmd->add_option("--report", args->report, "A `nestwalk report` folder whose figures to show too");
  cmd->add_option("--max-error", args->maxErrorM, "The terrain's largest vertical error in scene.glb, metres")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing SITE");
  cmd->callback([args] { runPublish(*args); });
}

}  // namespace nestwalk::tools
