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

}  // namespace nestwalk::tools
