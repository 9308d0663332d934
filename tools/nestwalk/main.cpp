// nestwalk: the command-line program. Subcommands are registered from their own files
// (commands.h). Exit codes (README, "Exit codes"):
//   0  done (also --help, --version)
//   1  bad input: nestwalk::InputError, with a message that names the file and the problem (and a
//      benchmark that failed)
//   2  usage: the command line itself (unknown option, missing argument), with CLI11's message
//   3  `run`: the flythrough played, but an expectation was not met
//   4  internal error: a bug, with the exception's message
#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/osg_messages.h"
#include "nestwalk/version.h"
#include "tools/nestwalk/commands.h"

#include <malloc.h>

#include <cstdio>
#include <exception>
#include <string>

namespace {
constexpr int kExitInputError = 1, kExitUsage = 2, kExitInternalError = 4;
/// glibc's malloc arenas at most: by default each thread that allocates may get its own (up to 8 a
/// core), and memory one thread frees stays in the arena of the thread that allocated it. The
/// terrain's loader threads build chunks that the drawing thread frees, so a run over a 1 G-sample
/// survey held 150 MiB more at its peak with the default than with 2 (1,463 against 1,315 MiB), at
/// the same frame and settle times.
constexpr int kMallocArenas = 2;
}  // namespace

int main(int argc, char** argv) {
  mallopt(M_ARENA_MAX, kMallocArenas);  // before any thread starts
  nestwalk::routeOsgMessagesToStderr();
  CLI::App app{"nestwalk: real-time walkthrough engine for terrain scenes with deployed equipment"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("nestwalk ") + nestwalk::kVersion);

  nestwalk::tools::registerDemo(app);
  nestwalk::tools::registerImportTerrain(app);
  nestwalk::tools::registerMakeTerrain(app);
  nestwalk::tools::registerMakeScene(app);
  nestwalk::tools::registerBuildScene(app);
  nestwalk::tools::registerExport(app);
  nestwalk::tools::registerRoute(app);
  nestwalk::tools::registerRun(app);
  nestwalk::tools::registerView(app);
  nestwalk::tools::registerPublish(app);
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
  nestwalk::tools::registerBenchContact(*bench);

  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a subcommand's own status (run: 3; bench: 1)
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, the version, or the usage error
    return code == 0 ? 0 : kExitUsage;
  } catch (const nestwalk::InputError& e) {
    std::fprintf(stderr, "nestwalk: error: %s\n", e.what());
    return kExitInputError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nestwalk: internal error: %s\n", e.what());
    return kExitInternalError;
  }
  return 0;
}
