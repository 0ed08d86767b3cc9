#include "cli_util.h"

#include <gtest/gtest.h>

#include <sstream>

namespace vdblight::test {

const std::string& cliPath() {
    static const std::string path = VDBLIGHT_CLI_PATH;
    return path;
}

CliRun runCli(const std::string& args) {
    CliRun r;
    r.status = runCommand(cliPath() + " " + args, &r.output);
    return r;
}

int countLines(const std::string& text) {
    int n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

std::size_t filesIn(const std::filesystem::path& dir) {
    std::size_t n = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) n += e.is_regular_file() ? 1 : 0;
    return n;
}

void expectCleanFailure(const TempDir& dir, const std::string& args, const std::string& expectedText) {
    const std::size_t before = filesIn(dir.path());
    const CliRun r = runCli(args);
    EXPECT_NE(r.status, 0) << args << "\n" << r.output;
    EXPECT_LT(r.status, 128) << "crashed: " << args << "\n" << r.output;
    EXPECT_EQ(countLines(r.output), 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(expectedText), std::string::npos)
        << args << "\nexpected '" << expectedText << "' in: " << r.output;
    EXPECT_EQ(filesIn(dir.path()), before) << "a file was left behind by: " << args;
}

void expectCleanFailureWithOutput(const TempDir& dir, const std::string& args, const std::string& expectedText) {
    expectCleanFailure(dir, args + " -o " + dir.file("bad.vdb"), expectedText);
}

void expectCleanFailuresWithOutput(const TempDir& dir, const std::vector<CleanFailure>& cases) {
    for (const CleanFailure& c : cases) expectCleanFailureWithOutput(dir, c.args, c.expectedText);
}

void expectRefusal(const std::string& args, const std::string& expectedText, const std::string& output,
                   const std::string& label) {
    const CliRun r = runCli(args);
    EXPECT_NE(r.status, 0) << label;
    EXPECT_EQ(countLines(r.output), 1) << label << ": " << r.output;
    EXPECT_NE(r.output.find(expectedText), std::string::npos) << label << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(output)) << label;
}

Rgbd firstIrradianceRgb(const std::string& csv) {
    std::istringstream lines(csv);
    std::string header, row;
    std::getline(lines, header);
    std::getline(lines, row);
    std::istringstream rs(row);
    double v[9] = {};
    char comma;
    for (double& x : v) rs >> x >> comma;
    return Rgbd(v[6], v[7], v[8]);
}

double firstIrradiance(const std::string& csv) { return firstIrradianceRgb(csv).x; }

}  // namespace vdblight::test
