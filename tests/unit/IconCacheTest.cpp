// The vector layer's icons: read once, shared; a missing file, a file that is not a PNG and one
// too large are null with a reason naming the file.
#include "layers/vector/IconCache.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace orbis::vector {
namespace {

TEST(IconCache, ReadsOnceAndNamesWhatItCannotRead) {
    const auto dir = std::filesystem::temp_directory_path() / "orbis-icon-cache-test";
    std::filesystem::create_directories(dir);
    ASSERT_TRUE(writePng(dir / "pin.png", ImageRgba8{2, 3, std::vector<uint8_t>(2 * 3 * 4, 200)}).ok());
    ASSERT_TRUE(writePng(dir / "huge.png", ImageRgba8{1100, 1, std::vector<uint8_t>(1100 * 4, 200)}).ok());
    std::ofstream(dir / "text.png") << "not a png";

    IconCache cache(dir.string());
    const auto pin = cache.get("pin.png");
    ASSERT_NE(pin, nullptr) << "relative to the base folder";
    EXPECT_EQ(pin->width, 2u);
    EXPECT_EQ(pin->height, 3u);
    EXPECT_EQ(cache.get("pin.png"), pin) << "read once";
    EXPECT_EQ(cache.get((dir / "pin.png").string())->height, 3u);
    EXPECT_EQ(cache.get("missing.png"), nullptr);
    EXPECT_EQ(cache.get("text.png"), nullptr);
    EXPECT_EQ(cache.get("huge.png"), nullptr);
    EXPECT_EQ(cache.get("http://example.com/pin.png"), nullptr);
    const auto errors = cache.errors();
    ASSERT_EQ(errors.size(), 4u);
    EXPECT_NE(errors[0].find("missing.png"), std::string::npos) << errors[0];
    EXPECT_NE(errors[1].find("text.png"), std::string::npos) << errors[1];
    EXPECT_NE(errors[2].find("1100x1"), std::string::npos) << errors[2];
    EXPECT_NE(errors[3].find("URL"), std::string::npos) << errors[3];
    EXPECT_EQ(cache.get("missing.png"), nullptr);
    EXPECT_EQ(cache.errors().size(), 4u) << "each reason once";
}

}  // namespace
}  // namespace orbis::vector
