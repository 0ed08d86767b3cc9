// Helpers for end-to-end tests of the `vdblight` program (tests/cli_*_test.cpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "test_util.h"

namespace vdblight::test {

/// Path of the built `vdblight` executable.
const std::string& cliPath();

struct CliRun {
    int status;          ///< exit status (128 + signal if it was killed)
    std::string output;  ///< stdout and stderr together
};

/// Runs `vdblight ARGS` through the shell.
CliRun runCli(const std::string& args);

int countLines(const std::string& text);
/// Number of regular files directly in `dir`.
std::size_t filesIn(const std::filesystem::path& dir);

/// Expects `vdblight ARGS` to fail cleanly: non-zero exit without a crash, exactly one line
/// of output containing `expectedText`, and no new file in `dir`.
void expectCleanFailure(const TempDir& dir, const std::string& args, const std::string& expectedText);

/// The same for a command that would write a volume: ARGS is given `-o DIR/bad.vdb`.
void expectCleanFailureWithOutput(const TempDir& dir, const std::string& args, const std::string& expectedText);

/// One command line that must fail cleanly and the text its one line of output must contain.
struct CleanFailure {
    std::string args, expectedText;
};

/// expectCleanFailureWithOutput for each case, in order.
void expectCleanFailuresWithOutput(const TempDir& dir, const std::vector<CleanFailure>& cases);

/// Expects `vdblight ARGS` to be refused: a non-zero exit, exactly one line of output
/// containing `expectedText`, and no file `output`. Failures name `label`.
void expectRefusal(const std::string& args, const std::string& expectedText, const std::string& output,
                   const std::string& label);

/// (E_r, E_g, E_b) of the first data row of a `vdblight query` CSV.
Rgbd firstIrradianceRgb(const std::string& csv);

/// E_r (red irradiance) of the first data row of a `vdblight query` CSV.
double firstIrradiance(const std::string& csv);

}  // namespace vdblight::test
