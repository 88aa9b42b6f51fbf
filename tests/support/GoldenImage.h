#pragma once
// Golden-image comparison. A pixel fails when any channel differs by more than `tolerance`
// (default 5/255); the image fails when more than `maxFailFraction` of its pixels fail
// (default 0.1 %). On failure, or when the golden is missing, NAME.actual.png and
// NAME.diff.png are written to the test output folder; tools/accept-goldens copies actual
// images over the goldens after you have looked at them.

#include "base/Png.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>

namespace orbis::test {

struct GoldenTolerance {
    int channel = 5;                  ///< per channel, out of 255
    double maxFailFraction = 0.001;   ///< of all pixels
};

std::string goldenDir();
std::string testOutputDir();

/// Makes `path` (a file or a folder of files) once, safely when ctest runs test processes in
/// parallel: `make` writes to a temporary path of this process, which is then renamed into
/// place (a folder only if none is there yet). Readers never see a half-written fixture.
/// Returns false when `make` did.
bool makeFixture(const std::string& path, const std::function<bool(const std::string& tmp)>& make);

::testing::AssertionResult matchesGolden(const ImageRgba8& actual, const std::string& name,
                                         GoldenTolerance tolerance = {});

/// Pixels whose channels differ by more than `tolerance` between two images of one size.
size_t countDifferentPixels(const ImageRgba8& a, const ImageRgba8& b, int tolerance);

/// Passes when at most `maxPixels` pixels differ by more than `tolerance`; otherwise writes
/// NAME.a.png, NAME.b.png and NAME.diff.png to the test output folder.
::testing::AssertionResult imagesAgree(const ImageRgba8& a, const ImageRgba8& b, const std::string& name,
                                       int tolerance, size_t maxPixels = 0);

}  // namespace orbis::test
