// readTextFile: one bounded whole-file read for scenes, camera paths, input scripts and sidecars.
#include "base/FileText.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <unistd.h>

using namespace orbis;

namespace {

/// A fresh folder for one test (ctest runs tests in parallel processes).
class FileTextTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        folder_ = std::filesystem::temp_directory_path() /
                  ("orbis_filetext_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
        std::filesystem::create_directories(folder_);
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(folder_, ec);
    }
    std::filesystem::path write(const std::string& name, const std::string& bytes) {
        const auto file = folder_ / name;
        std::ofstream(file, std::ios::binary) << bytes;
        return file;
    }
    std::filesystem::path folder_;
};

}  // namespace

TEST_F(FileTextTest, MissingFileSaysNoSuchFile) {
    const auto file = folder_ / "missing.json";
    auto text = readTextFile(file, 1024, "scene file");
    ASSERT_FALSE(text.ok());
    EXPECT_EQ(text.message(), file.string() + ": no such file");
}

TEST_F(FileTextTest, FolderIsAnErrorNamingTheKindOfFile) {
    auto text = readTextFile(folder_, 1024, "camera path file");
    ASSERT_FALSE(text.ok());
    EXPECT_EQ(text.message(), folder_.string() + ": is a folder, not a camera path file");
}

TEST_F(FileTextTest, DeviceIsNotARegularFile) {
    auto text = readTextFile("/dev/null", 1024, "input script");
    ASSERT_FALSE(text.ok());
    EXPECT_EQ(text.message(), "/dev/null: is not a regular file");
}

TEST_F(FileTextTest, FileOverTheCapSaysTheCap) {
    const auto file = write("big.json", std::string(2 * 1024 + 1, 'x'));
    auto text = readTextFile(file, 2 * 1024, "input script");
    ASSERT_FALSE(text.ok());
    EXPECT_EQ(text.message(), file.string() + ": the input script is larger than 2 KB");
}

TEST_F(FileTextTest, FileExactlyAtTheCapIsRead) {
    const auto file = write("edge.json", std::string(100, 'y'));
    auto text = readTextFile(file, 100, "scene file");
    ASSERT_TRUE(text.ok()) << text.message();
    EXPECT_EQ(text->size(), 100u);
}

TEST_F(FileTextTest, EmptyFileIsAnEmptyString) {
    const auto file = write("empty.json", "");
    auto text = readTextFile(file, 1024, "scene file");
    ASSERT_TRUE(text.ok()) << text.message();
    EXPECT_TRUE(text->empty());
}

TEST_F(FileTextTest, NormalFileIsReadByteForByte) {
    // CR LF and a NUL pass unchanged: the read is binary, the parser decides what is valid.
    const std::string withNul = std::string("{\"orbis\": 1}\r\n") + '\0' + "end";
    const auto file = write("scene.json", withNul);
    auto text = readTextFile(file, 1 << 20, "scene file");
    ASSERT_TRUE(text.ok()) << text.message();
    EXPECT_EQ(*text, withNul);
}

TEST_F(FileTextTest, LargerThanOneChunkIsReadWhole) {
    std::string bytes(200 * 1024 + 7, '\0');
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = char('a' + i % 26);
    const auto file = write("long.txt", bytes);
    auto text = readTextFile(file, 1 << 20, "scene file");
    ASSERT_TRUE(text.ok()) << text.message();
    EXPECT_EQ(*text, bytes);
}

TEST(FileText, ByteLimitsAreSaidInWholeUnits) {
    EXPECT_EQ(formatByteLimit(16u << 20), "16 MB");
    EXPECT_EQ(formatByteLimit(4u << 20), "4 MB");
    EXPECT_EQ(formatByteLimit(1u << 20), "1 MB");
    EXPECT_EQ(formatByteLimit(512u << 10), "512 KB");
    EXPECT_EQ(formatByteLimit(1000), "1000 bytes");
    EXPECT_EQ(formatByteLimit(1), "1 byte");
}
