// Input scripts for the viewer: each step kind read with its defaults, and clear errors that
// name the file, the step and the key. CPU only (no window).
#include "ui/InputScript.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <unistd.h>

namespace orbis::ui {
namespace {

/// Writes `json` to a script file of this test's own and reads it back.
Result<std::vector<ScriptStep>> readScript(const std::string& json) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const auto folder = std::filesystem::temp_directory_path() /
                        ("orbis_inputscript_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    const auto file = folder / "script.json";
    std::ofstream(file, std::ios::binary) << json;
    auto steps = readInputScript(file);
    std::error_code ec;
    std::filesystem::remove_all(folder, ec);
    return steps;
}

/// The error for a one-step script, or "" when it was accepted.
std::string stepError(const std::string& step) {
    auto steps = readScript("[" + step + "]");
    return steps ? std::string() : steps.message();
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(InputScript, EveryStepKindIsReadWithItsDefaults) {
    auto steps = readScript(R"([
        {"do": "drag", "from": [1, 2], "to": [3, 4]},
        {"do": "scroll", "at": [5, 6], "lines": -3},
        {"do": "key", "key": "PageUp", "frames": 4},
        {"do": "doubleClick", "at": [7, 8]},
        {"do": "click", "item": "Visible##Earth"},
        {"do": "settle"},
        {"do": "screenshot", "file": "shot.png"},
        {"do": "idle", "seconds": 2},
        {"do": "quit"}])");
    ASSERT_TRUE(steps.ok()) << steps.message();
    ASSERT_EQ(steps->size(), 9u);
    const auto& s = *steps;
    EXPECT_EQ(s[0].kind, ScriptStep::Kind::Drag);
    EXPECT_EQ(s[0].button, "left");
    EXPECT_EQ(s[0].frames, 8);
    EXPECT_EQ(s[0].to[1], 4.0);
    EXPECT_FALSE(s[0].shift);
    EXPECT_EQ(s[1].kind, ScriptStep::Kind::Scroll);
    EXPECT_EQ(s[1].lines, -3.0);
    EXPECT_EQ(s[2].kind, ScriptStep::Kind::Key);
    EXPECT_EQ(s[2].frames, 4);
    EXPECT_EQ(s[3].kind, ScriptStep::Kind::DoubleClick);
    EXPECT_EQ(s[4].item, "Visible##Earth");
    EXPECT_EQ(s[5].kind, ScriptStep::Kind::Settle);
    EXPECT_EQ(s[6].file.filename(), "shot.png");
    EXPECT_TRUE(s[6].file.is_absolute() || s[6].file.has_parent_path());   // beside the script
    EXPECT_EQ(s[7].seconds, 2.0);
    EXPECT_EQ(s[8].kind, ScriptStep::Kind::Quit);
}

TEST(InputScript, ADragMayHoldShift) {
    auto steps = readScript(R"([{"do": "drag", "from": [1, 2], "to": [3, 4], "shift": true}])");
    ASSERT_TRUE(steps.ok()) << steps.message();
    EXPECT_TRUE((*steps)[0].shift);
    EXPECT_TRUE(contains(stepError(R"({"do": "drag", "from": [1, 2], "to": [3, 4], "shift": 1})"), "\"shift\" is true or false"));
}

TEST(InputScript, ShortcutKeysAreAccepted) {
    for (const char* key : {"F1", "F12", "Ctrl+S", "Escape", "Home", "W"})
        EXPECT_EQ(stepError(std::string(R"({"do": "key", "key": ")") + key + "\"}"), "") << key;
}

TEST(InputScript, ErrorsNameTheStepAndWhatIsWrong) {
    EXPECT_TRUE(contains(stepError(R"({"do": "jump"})"), ": step 1: unknown \"do\": \"jump\""));
    EXPECT_TRUE(contains(stepError(R"({"at": [1, 2]})"), "each step is an object with \"do\""));
    EXPECT_TRUE(contains(stepError(R"({"do": "drag", "from": [1, 2]})"), "drag needs \"from\" and \"to\""));
    EXPECT_TRUE(contains(stepError(R"({"do": "drag", "item": "x", "from": [0, 2], "to": [1, 1]})"),
                         "fractions of the item (0 to 1)"));
    EXPECT_TRUE(contains(stepError(R"({"do": "drag", "from": [1, 2], "to": [3, 4], "button": "side"})"),
                         "\"button\" is left, right or middle, not \"side\""));
    EXPECT_TRUE(contains(stepError(R"({"do": "drag", "from": [1, 2], "to": [3, 4], "frames": 0})"), "\"frames\" is 1 to 1000"));
    EXPECT_TRUE(contains(stepError(R"({"do": "key", "key": "Tab"})"), "\"key\" is one of"));
    EXPECT_TRUE(contains(stepError(R"({"do": "scroll", "at": [1, 2], "lines": 500})"), "\"lines\" from -100 to 100"));
    EXPECT_TRUE(contains(stepError(R"({"do": "click"})"), "click needs \"at\""));
    EXPECT_TRUE(contains(stepError(R"({"do": "screenshot"})"), "screenshot needs \"file\""));
    EXPECT_TRUE(contains(stepError(R"({"do": "idle", "seconds": 0})"), "idle needs \"seconds\" from 0.1 to 600"));
}

TEST(InputScript, PointsMustBeFiniteAndOnScreenSized) {
    EXPECT_TRUE(contains(stepError(R"({"do": "doubleClick", "at": [1e9, 0]})"), "doubleClick needs \"at\""));
    EXPECT_TRUE(contains(stepError(R"({"do": "doubleClick", "at": [1]})"), "doubleClick needs \"at\""));
}

TEST(InputScript, TheFileMustBeAListOfSteps) {
    auto notJson = readScript("not json");
    ASSERT_FALSE(notJson.ok());
    EXPECT_TRUE(contains(notJson.message(), ": not valid JSON"));
    auto object = readScript(R"({"do": "quit"})");
    ASSERT_FALSE(object.ok());
    EXPECT_TRUE(contains(object.message(), "expected a list of steps"));
}

TEST(InputScript, MissingFileSaysSo) {
    auto steps = readInputScript("/nonexistent/script.json");
    ASSERT_FALSE(steps.ok());
    EXPECT_EQ(steps.message(), "/nonexistent/script.json: no such file");
}

}  // namespace orbis::ui
