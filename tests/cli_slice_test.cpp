// `vdblight slice` end to end and the exports of every volume kind:
// - an EXR slice holds exactly what `vdblight query --raw` returns (the slice is not clamped at 0) at the documented pixel centres;
// - a PNG slice decodes with an independent decoder (scripts/check_png.py) to the right size;
// - bilevel / adaptive SH volumes and irradiance-vector volumes export, and the round-trip
//   script (scripts/check_export.py) matches `query` from the manifest alone;
// - bad input: one line, non-zero exit, no file.
#include <gtest/gtest.h>

#include <ImfArray.h>
#include <ImfInputFile.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfStringAttribute.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "cli_baked_suite.h"
#include "export_readers.h"

namespace fs = std::filesystem;
using namespace vdblight::test;

namespace {
class CliSlice : public BakedSuite<CliSlice> {
public:
    static std::vector<SuiteBake> bakes() {
        return {{"sh.vdb", "--resolution 6 --rays 48 --bounces 2"},
                {"bilevel.vdb", "--resolution 4 --rays 32 --bounces 2 --layout bilevel"},
                {"adaptive.vdb", "--resolution 4 --rays 32 --bounces 2 --layout adaptive --levels 3 --refine 2"},
                {"vectors.vdb", "--method photons --photons 100000 --resolution 6"}};
    }
};

std::vector<double> parseNumbers(const std::string& line) {
    std::vector<double> v;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) v.push_back(std::stod(cell));
    return v;
}

struct Box {
    double lo[3], hi[3];
};

// The volume's node box, as `vdblight info` prints it.
Box nodeBox(const std::string& volume) {
    std::string out;
    EXPECT_EQ(runCommand(cliPath() + " info " + volume, &out), 0) << out;
    Box b{};
    const auto at = out.find("node bounds (");  // level 0: "node bounds (x, y, z) - (x, y, z)"
    EXPECT_NE(at, std::string::npos) << out;
    if (at == std::string::npos) return b;
    std::string rest = out.substr(at + 12, out.find('\n', at) - at - 12);
    for (char& c : rest)
        if (c == '(' || c == ')' || c == ',' || (c == '-' && (&c)[1] == ' ')) c = ' ';
    std::stringstream s(rest);
    s >> b.lo[0] >> b.lo[1] >> b.lo[2] >> b.hi[0] >> b.hi[1] >> b.hi[2];
    EXPECT_FALSE(s.fail()) << rest;
    return b;
}
}  // namespace

TEST_F(CliSlice, ExrPixelsEqualQueryAtThePixelCentres) {
    for (const std::string kind : {"sh", "bilevel", "vectors"}) {
        TempDir out;
        const std::string vol = file(kind + ".vdb");
        const Box box = nodeBox(vol);
        const double at = 0.37 * box.lo[0] + 0.63 * box.hi[0];
        std::string log;
        ASSERT_EQ(runCommand(cliPath() + " slice " + vol + " --axis x --at " + std::to_string(at) +
                                 " --normal 1,0.5,-0.25 --size 12 -o " + out.file("s.exr"), &log), 0) << log;
        Imf::InputFile exr(out.file("s.exr").c_str());
        const auto* axisAttr = exr.header().findTypedAttribute<Imf::StringAttribute>("vdblightAxis");
        ASSERT_NE(axisAttr, nullptr) << kind;
        EXPECT_EQ(axisAttr->value(), "x");
        const Imath::Box2i dw = exr.header().dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        // --axis x: image (u, v) = (z, y), size 12 along the longer side.
        const double su = box.hi[2] - box.lo[2], sv = box.hi[1] - box.lo[1];
        EXPECT_EQ(std::max(w, h), 12) << kind;
        EXPECT_EQ(w, std::max(1, int(std::lround(12 * su / std::max(su, sv))))) << kind;
        std::vector<float> px(std::size_t(w) * h * 3);
        Imf::FrameBuffer fb;
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c)
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(px.data() + c), 12, 12 * std::size_t(w)));
        exr.setFrameBuffer(fb);
        exr.readPixels(dw.min.y, dw.max.y);

        std::ostringstream csv;
        csv.precision(17);
        csv << "x,y,z,nx,ny,nz\n";
        for (int r = 0; r < h; ++r)
            for (int c = 0; c < w; ++c) {
                const double z = box.lo[2] + (c + 0.5) * su / w, y = box.hi[1] - (r + 0.5) * sv / h;
                csv << at << ',' << y << ',' << z << ",1,0.5,-0.25\n";
            }
        writeTextFile(out.file("p.csv"), csv.str());
        ASSERT_EQ(runCommand(cliPath() + " query " + vol + " --raw --points " + out.file("p.csv") + " -o " + out.file("e.csv"), &log), 0)
            << log;
        std::ifstream in(out.file("e.csv"));
        std::string line;
        std::getline(in, line);
        double maxE = 0, worst = 0;
        for (int p = 0; p < w * h; ++p) {
            ASSERT_TRUE(std::getline(in, line)) << kind << " pixel " << p;
            const std::vector<double> v = parseNumbers(line);
            for (int c = 0; c < 3; ++c) {
                maxE = std::max(maxE, std::fabs(v[6 + c]));
                worst = std::max(worst, std::fabs(double(px[3 * p + c]) - v[6 + c]) / (1e-6 + std::fabs(v[6 + c])));
            }
        }
        EXPECT_GT(maxE, 0.0) << kind << ": the slice is black";
        EXPECT_LT(worst, 1e-5) << kind;
    }
}

TEST_F(CliSlice, PngDecodesToTheRightSizeAndShowsTheRedWall) {
    TempDir out;
    std::string log;
    // Looking along -z at the box (u = x to the right): the red wall is at the large-x side.
    const Box box = nodeBox(file("sh.vdb"));
    const double at = 0.5 * (box.lo[2] + box.hi[2]);
    ASSERT_EQ(runCommand(cliPath() + " slice " + file("sh.vdb") + " --axis z --at " + std::to_string(at) +
                             " --normal 0,1,0 --size 40 -o " + out.file("s.png"), &log), 0) << log;
    ASSERT_EQ(runCommand("/usr/bin/python3 " + sourceDir() + "/scripts/check_png.py " + out.file("s.png") + " --left-right", &log),
              0) << log;
    std::stringstream s(log);
    int w = 0, h = 0;
    double r = 0, g = 0, b = 0;
    std::string label;
    double left = 0, right = 0;
    s >> w >> h >> r >> g >> b >> label >> left >> label >> right;
    EXPECT_EQ(std::max(w, h), 40) << log;
    EXPECT_GT(r + g + b, 30.0) << "mean of the 8-bit values: " << log;
    EXPECT_GT(right, left) << log;
}

TEST_F(CliSlice, EveryVolumeKindExportsAndRoundTrips) {
    TempDir out;
    const struct {
        std::string volume, layout, precision;
    } cases[] = {
        {"bilevel", "sh2-packed", "--half"}, {"bilevel", "sh2", "--float"},   {"adaptive", "sh2-packed", "--float"},
        {"adaptive", "sh1", "--half"},      {"vectors", "vectors", "--half"}, {"vectors", "vectors", "--float"},
    };
    for (const auto& c : cases) {
        const std::string where = out.file(c.volume + c.layout + c.precision);
        std::string log;
        ASSERT_EQ(runCommand(cliPath() + " export -q " + file(c.volume + ".vdb") + " -o " + where + " --format raw --layout " +
                                 c.layout + " " + c.precision, &log), 0) << log;
        EXPECT_EQ(checkExport(file(c.volume + ".vdb"), where, &log), 0)
            << c.volume << " " << c.layout << " " << c.precision << ": " << log;
    }
    // compact: texel by texel the section 4.2 encoding of the (float, checked) vectors export.
    std::string log;
    for (const char* format : {"ktx2", "dds"}) {
        const std::string where = out.file(std::string("compact-") + format);
        ASSERT_EQ(runCommand(cliPath() + " export -q " + file("vectors.vdb") + " -o " + where + " --format " + format +
                                 " --layout compact", &log), 0) << log;
        EXPECT_EQ(checkExport(file("vectors.vdb"), where, &log, "--vectors-export " + out.file("vectorsvectors--float")), 0)
            << format << ": " << log;
        EXPECT_NE(log.find("compact encoding vs section 4.2"), std::string::npos) << log;
    }
    if (fs::exists(ktxParseDir())) {
        EXPECT_EQ(checkKtx2(out.file("compact-ktx2"), &log), 0) << log;
    }
}

TEST_F(CliSlice, BadInputFailsWithOneLineAndWritesNothing) {
    TempDir out;
    const struct {
        std::string args, expected;
    } cases[] = {
        {"--axis w --at 0", "--axis must be x, y or z"},
        {"--axis y --at 1000", "outside the volume"},
        {"--axis y --at 0.2 --normal 0,0,0", "non-zero"},
        {"--axis y --at 0.2 --size 0", "size"},
        {"--axis y --at 0.2 --exposure bright", "--exposure"},
    };
    for (const auto& c : cases)
        expectRefusal("slice " + file("sh.vdb") + " -o " + out.file("s.png") + " " + c.args, c.expected, out.file("s.png"), c.args);
    std::string log;
    EXPECT_NE(runCommand(cliPath() + " slice " + file("sh.vdb") + " --at 0.2 -o " + out.file("s.jpg"), &log), 0);
    EXPECT_EQ(countLines(log), 1) << log;
    EXPECT_FALSE(fs::exists(out.file("s.jpg")));
    // A layout that does not fit the volume kind, both ways.
    EXPECT_NE(runCommand(cliPath() + " export " + file("vectors.vdb") + " -o " + out.file("x") + " --layout sh2", &log), 0);
    EXPECT_NE(log.find("does not fit"), std::string::npos) << log;
    EXPECT_NE(runCommand(cliPath() + " export " + file("sh.vdb") + " -o " + out.file("x") + " --layout compact", &log), 0);
    EXPECT_NE(log.find("does not fit"), std::string::npos) << log;
    EXPECT_EQ(countLines(log), 1) << log;
    EXPECT_TRUE(fs::is_empty(out.path()));
    // vdb-preview: too many voxels, or a missing volume, leave no directory behind.
    EXPECT_NE(runCommand(cliPath() + " export " + file("sh.vdb") + " -o " + out.file("p") +
                             " --format vdb-preview --resolution 2000", &log), 0);
    EXPECT_EQ(countLines(log), 1) << log;
    EXPECT_NE(log.find("lower --resolution"), std::string::npos) << log;
    EXPECT_NE(runCommand(cliPath() + " export " + out.file("missing.vdb") + " -o " + out.file("p") + " --format vdb-preview", &log),
              0);
    EXPECT_EQ(countLines(log), 1) << log;
    EXPECT_TRUE(fs::is_empty(out.path()));
}
