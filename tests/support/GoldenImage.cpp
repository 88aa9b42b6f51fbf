#include "tests/support/GoldenImage.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include <unistd.h>

namespace orbis::test {

std::string goldenDir() { return ORBIS_GOLDEN_DIR; }

std::string testOutputDir() {
    const std::string dir = ORBIS_TEST_OUTPUT_DIR;
    std::filesystem::create_directories(dir);
    return dir;
}

size_t countDifferentPixels(const ImageRgba8& a, const ImageRgba8& b, int tolerance) {
    if (a.width != b.width || a.height != b.height) return size_t(-1);
    size_t failing = 0;
    for (size_t i = 0; i < a.pixels.size(); i += 4) {
        int worst = 0;
        for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c])));
        if (worst > tolerance) ++failing;
    }
    return failing;
}

namespace {
ImageRgba8 diffImage(const ImageRgba8& actual, const ImageRgba8& golden, int tolerance) {
    ImageRgba8 diff{actual.width, actual.height, std::vector<uint8_t>(actual.pixels.size())};
    for (size_t i = 0; i < actual.pixels.size(); i += 4) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(actual.pixels[i + c]) - int(golden.pixels[i + c])));
        const uint8_t grey = uint8_t((actual.pixels[i] + actual.pixels[i + 1] + actual.pixels[i + 2]) / 12);
        const bool fail = worst > tolerance;
        diff.pixels[i + 0] = fail ? 255 : grey;
        diff.pixels[i + 1] = fail ? uint8_t(std::min(255, worst * 4)) : grey;
        diff.pixels[i + 2] = grey;
        diff.pixels[i + 3] = 255;
    }
    return diff;
}
}  // namespace

::testing::AssertionResult imagesAgree(const ImageRgba8& a, const ImageRgba8& b, const std::string& name, int tolerance,
                                       size_t maxPixels) {
    const size_t failing = countDifferentPixels(a, b, tolerance);
    if (failing <= maxPixels) return ::testing::AssertionSuccess();
    const std::filesystem::path out = testOutputDir();
    (void)writePng(out / (name + ".a.png"), a);
    (void)writePng(out / (name + ".b.png"), b);
    if (a.width == b.width && a.height == b.height) (void)writePng(out / (name + ".diff.png"), diffImage(a, b, tolerance));
    return ::testing::AssertionFailure() << name << ": " << failing << " pixels differ by more than " << tolerance
                                         << "/255 (allowed " << maxPixels << "); wrote " << (out / name).string()
                                         << ".{a,b,diff}.png";
}

::testing::AssertionResult matchesGolden(const ImageRgba8& actual, const std::string& name, GoldenTolerance tol) {
    namespace fs = std::filesystem;
    const fs::path golden = fs::path(goldenDir()) / (name + ".png");
    const fs::path out = testOutputDir();
    const fs::path actualFile = out / (name + ".actual.png");
    if (!fs::exists(golden)) {
        (void)writePng(actualFile, actual);
        return ::testing::AssertionFailure() << "no golden image " << golden << "; look at " << actualFile
                                             << " and accept it with tools/accept-goldens " << name;
    }
    auto expected = readPng(golden);
    if (!expected) return ::testing::AssertionFailure() << expected.message();
    if (expected->width != actual.width || expected->height != actual.height) {
        (void)writePng(actualFile, actual);
        return ::testing::AssertionFailure() << "size " << actual.width << "x" << actual.height << " differs from golden "
                                             << expected->width << "x" << expected->height << " (" << golden << ")";
    }
    const size_t failing = countDifferentPixels(actual, *expected, tol.channel);
    const size_t total = size_t(actual.width) * actual.height;
    const double fraction = double(failing) / double(total);
    if (fraction > tol.maxFailFraction) {
        (void)writePng(actualFile, actual);
        const fs::path diffFile = out / (name + ".diff.png");
        (void)writePng(diffFile, diffImage(actual, *expected, tol.channel));
        return ::testing::AssertionFailure()
               << name << ": " << failing << " of " << total << " pixels (" << fraction * 100.0 << " %) differ by more than "
               << tol.channel << "/255 (allowed " << tol.maxFailFraction * 100.0 << " %); wrote " << actualFile << " and "
               << diffFile;
    }
    return ::testing::AssertionSuccess();
}


bool makeFixture(const std::string& path, const std::function<bool(const std::string& tmp)>& make) {
    namespace fs = std::filesystem;
    const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    std::error_code ec;
    fs::remove_all(tmp, ec);
    if (!make(tmp)) {
        fs::remove_all(tmp, ec);
        return false;
    }
    if (fs::is_directory(tmp)) {
        fs::rename(tmp, path, ec);   // fails when another process put its copy there first
        if (ec) fs::remove_all(tmp, ec);
    } else {
        fs::rename(tmp, path, ec);   // a file replaces the other's atomically (same content)
    }
    return fs::exists(path);
}

}  // namespace orbis::test
