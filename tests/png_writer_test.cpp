// writePng (slice.h), the PNG of `vdblight slice`: whatever encoder makes the bytes (libpng
// since issue 30; compression and filters may change them), an independent decoder
// (scripts/check_png.py, Python's zlib) must read back exactly the pixels it was given.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/slice.h"

namespace vdblight {
namespace {

/// Pixels that exercise every PNG row filter an encoder may choose: smooth gradients (Sub, Up,
/// Average, Paeth pay) next to noise (None pays), at an odd width so rows do not align.
std::vector<uint8_t> testImage(int width, int height) {
    std::vector<uint8_t> rgb(std::size_t(width) * height * 3);
    uint32_t state = 12345;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            uint8_t* p = &rgb[(std::size_t(y) * width + x) * 3];
            state = state * 1664525u + 1013904223u;
            const bool noisy = x > width / 2;
            p[0] = noisy ? uint8_t(state >> 24) : uint8_t(x * 7);
            p[1] = noisy ? uint8_t(state >> 16) : uint8_t(y * 11);
            p[2] = uint8_t((x + y) * 3 + (x == 0 ? 255 : 0));
        }
    return rgb;
}

std::string decodeToRaw(const std::string& png, const std::string& raw, std::string* log) {
    const int status =
        test::runCommand("/usr/bin/python3 " + std::string(VDBLIGHT_SOURCE_DIR) + "/scripts/check_png.py " + png + " --raw " + raw, log);
    return status == 0 ? test::readTextFile(raw) : std::string();
}

TEST(PngWriter, AnIndependentDecoderReadsBackTheExactPixels) {
    test::TempDir dir;
    for (const auto& size : {std::pair<int, int>{37, 23}, {1, 1}, {256, 3}}) {
        const std::vector<uint8_t> rgb = testImage(size.first, size.second);
        const std::string png = dir.file("s.png"), raw = dir.file("s.raw");
        writePng(png, size.first, size.second, rgb);
        std::string log;
        const std::string decoded = decodeToRaw(png, raw, &log);
        EXPECT_EQ(log.substr(0, log.find(' ', log.find(' ') + 1)),
                  std::to_string(size.first) + " " + std::to_string(size.second)) << log;
        ASSERT_EQ(decoded.size(), rgb.size()) << size.first << "x" << size.second << ": " << log;
        EXPECT_TRUE(std::equal(rgb.begin(), rgb.end(), decoded.begin(),
                               [](uint8_t a, char b) { return a == uint8_t(b); }))
            << size.first << "x" << size.second << ": the decoded pixels differ";
    }
}

TEST(PngWriter, PixelsThatDoNotMatchTheSizeAreRefusedAndNoFileIsLeft) {
    test::TempDir dir;
    const std::string png = dir.file("s.png");
    EXPECT_THROW(writePng(png, 4, 4, std::vector<uint8_t>(4 * 4 * 3 - 1)), ValueError);
    EXPECT_THROW(writePng(png, 0, 4, {}), ValueError);
    EXPECT_FALSE(std::filesystem::exists(png));
    EXPECT_THROW(writePng(dir.file("missing/s.png"), 1, 1, {1, 2, 3}), IoError);
}

}  // namespace
}  // namespace vdblight
