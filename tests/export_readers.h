// The readers we did not write that end-to-end export tests run on an export: the round-trip
// script scripts/check_export.py (Python + numpy, manifest.json and docs/engine*.md only,
// against `vdblight query`) and the npm package ktx-parse (scripts/ktx/check_ktx2.mjs).
#pragma once

#include <string>

#include "cli_util.h"

namespace vdblight::test {

/// The source tree (scripts/, data/).
inline std::string sourceDir() { return VDBLIGHT_SOURCE_DIR; }

/// Runs scripts/check_export.py on the export in `exportDir` of `volume` (300 random points;
/// `options` are more of the script's options); returns its exit status, output in `log`.
inline int checkExport(const std::string& volume, const std::string& exportDir, std::string* log,
                       const std::string& options = "") {
    return runCommand("/usr/bin/python3 " + sourceDir() + "/scripts/check_export.py --cli " + cliPath() + " --volume " +
                          volume + " --export " + exportDir + (options.empty() ? "" : " " + options) + " --points 300",
                      log);
}

/// Where ktx-parse is installed (scripts/setup.sh runs `npm ci` in scripts/ktx).
inline std::string ktxParseDir() { return sourceDir() + "/scripts/ktx/node_modules/ktx-parse"; }

/// Runs scripts/ktx/check_ktx2.mjs (ktx-parse reads and rewrites every .ktx2 file of
/// `exportDir`); returns its exit status, output in `log`.
inline int checkKtx2(const std::string& exportDir, std::string* log) {
    return runCommand("node " + sourceDir() + "/scripts/ktx/check_ktx2.mjs " + exportDir, log);
}

}  // namespace vdblight::test
