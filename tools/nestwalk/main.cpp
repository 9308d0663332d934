// nestwalk: the command-line program. Subcommands are registered from their own files
// (commands.h); bad input surfaces as nestwalk::InputError and ends the program with exit code 1
// and a message that names the file and the problem.
#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/osg_messages.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  nestwalk::routeOsgMessagesToStderr();
  CLI::App app{"nestwalk: real-time walkthrough engine for terrain scenes with deployed equipment"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "nestwalk 0.1.0");

  nestwalk::tools::registerDemo(app);
  nestwalk::tools::registerImportTerrain(app);
  nestwalk::tools::registerMakeTerrain(app);
  nestwalk::tools::registerMakeScene(app);
  nestwalk::tools::registerBuildScene(app);
  nestwalk::tools::registerExport(app);
  nestwalk::tools::registerRun(app);
  nestwalk::tools::registerReport(app);
  CLI::App* query = app.add_subcommand("query", "Answer one question about a model, terrain or boxes");
  query->require_subcommand(1);
  nestwalk::tools::registerQueryVolumes(*query);
  nestwalk::tools::registerQueryOverlap(*query);
  nestwalk::tools::registerQueryGround(*query);
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks against peer libraries, printed as a table");
  bench->require_subcommand(1);
  nestwalk::tools::registerBenchVolumes(*bench);
  nestwalk::tools::registerBenchTerrain(*bench);
  nestwalk::tools::registerBenchWalker(*bench);
  nestwalk::tools::registerBenchRender(*bench);
  nestwalk::tools::registerBenchModels(*bench);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const nestwalk::InputError& e) {
    std::fprintf(stderr, "nestwalk: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nestwalk: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
