// Registration of the subcommands; each lives in its own cmd_*.cpp file.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace vdblight::app {

void addBakeCommand(CLI::App& app);
void addQueryCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addReferenceCommand(CLI::App& app);
void addExportCommand(CLI::App& app);
void addSliceCommand(CLI::App& app);
void addCheckSceneCommand(CLI::App& app);
void addPrtCommand(CLI::App& app);
void addMergeCommand(CLI::App& app);
void addSlurmCommand(CLI::App& app);
/// The stages of a tiled bake with these bake options (after the scene): 1 + its probe-to-probe
/// passes, each tiled in turn (tiles.h, "Staged bakes"). Throws ValueError for bad options.
int bakeStageCount(const std::string& scene, const std::vector<std::string>& bakeArgs);
/// What `prt info` prints (also used by `info` when given a PRT file).
void printPrtInfo(const std::string& path);

}  // namespace vdblight::app
