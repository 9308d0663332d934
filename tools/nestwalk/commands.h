// The subcommands of `nestwalk`. Each register function adds one subcommand (with its options and
// its callback) to the program; each lives in a file of its own.
#pragma once

#include <CLI/CLI.hpp>

namespace nestwalk::tools {

void registerDemo(CLI::App& app);          // nestwalk demo
void registerQueryVolumes(CLI::App& query);  // nestwalk query volumes MODEL
void registerQueryOverlap(CLI::App& query);  // nestwalk query overlap PAIRS.csv
void registerBenchVolumes(CLI::App& bench);  // nestwalk bench volumes [--json]
void registerImportTerrain(CLI::App& app);   // nestwalk import-terrain IN OUT
void registerMakeTerrain(CLI::App& app);     // nestwalk make-terrain OUT
void registerQueryGround(CLI::App& query);   // nestwalk query ground TERRAIN --points POINTS.csv
void registerBenchTerrain(CLI::App& bench);  // nestwalk bench terrain [--json]
void registerMakeScene(CLI::App& app);       // nestwalk make-scene DIR
void registerBuildScene(CLI::App& app);      // nestwalk build-scene --terrain DEM --equipment SOURCE ...
void registerExport(CLI::App& app);          // nestwalk export SCENE OUT.osgb
void registerRoute(CLI::App& app);           // nestwalk route SCENE ROUTE --out SCRIPT
void registerRun(CLI::App& app);             // nestwalk run SCENE --script FILE --headless --out DIR
void registerView(CLI::App& app);            // nestwalk view SCENE [--script FILE] (a window)
void registerBenchWalker(CLI::App& bench);  // nestwalk bench walker [--json]
void registerBenchRender(CLI::App& bench);  // nestwalk bench render [--json]
void registerBenchModels(CLI::App& bench);  // nestwalk bench models [--json]
void registerBenchContact(CLI::App& bench);  // nestwalk bench contact [--json]
void registerReport(CLI::App& app);          // nestwalk report [SCENE] --out DIR [--quick]
void registerPublish(CLI::App& app);         // nestwalk publish RUN_DIR --out SITE

}  // namespace nestwalk::tools
