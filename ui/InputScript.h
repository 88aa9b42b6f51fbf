#pragma once
// A scripted session for the viewer (tests, demos, batch screenshots of the live UI): a JSON
// list of steps that the viewer plays one per frame, feeding the same input path as the mouse
// and keyboard. Positions are framebuffer pixels, origin top left.
//
// [
//   {"do": "drag", "button": "left", "from": [640, 360], "to": [700, 360], "frames": 8},
//   {"do": "drag", "from": [640, 360], "to": [700, 360], "shift": true},   (Shift held)
//   {"do": "drag", "item": "opacity##Plume", "from": [0.8, 0.9], "to": [0.8, 0.2]},
//                                                 (on a panel item: fractions of its rectangle)
//   {"do": "scroll", "at": [640, 360], "lines": -3},
//   {"do": "key", "key": "Home"},                 (also W A S D Q E R F, arrows, PageUp/Down,
//                                                  F1, F12, Ctrl+S, Escape; "frames": held that long)
//   {"do": "doubleClick", "at": [640, 360]},
//   {"do": "click", "at": [20, 40]}  or  {"do": "click", "item": "Visible##Earth"},
//   {"do": "settle"},                             (until nothing loads or moves)
//   {"do": "screenshot", "file": "step1.png"},    (relative to the script's folder)
//   {"do": "idle", "seconds": 5},                 (sleeps as a user would; reports CPU use)
//   {"do": "quit"}
// ]

#include "base/Result.h"
#include "ui/input/InputEvents.h"

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace orbis::ui {

struct ScriptStep {
    enum class Kind { Drag, Scroll, Key, DoubleClick, Click, Settle, Screenshot, Idle, Quit };
    Kind kind = Kind::Settle;
    std::string button = "left";      ///< Drag: left | right | middle
    bool shift = false;               ///< Drag: with Shift held (moves a viewshed's observer)
    std::array<double, 2> from{0, 0}, to{0, 0};   ///< Drag; Click/DoubleClick/Scroll use `from`
    int frames = 1;                   ///< Drag: frames the move takes; Key: frames held
    double lines = 0.0;               ///< Scroll: + up (zoom in), - down
    std::string key;                  ///< Key
    std::string item;                 ///< Click: an item label the panels remember, instead of `at`;
                                      ///< Drag: `from` and `to` are fractions of that item
    std::filesystem::path file;       ///< Screenshot: absolute
    double seconds = 0.0;             ///< Idle
};

/// The navigation key a script names ("W", "PageUp", "Home", ...), or nothing.
std::optional<Key> navigationKey(const std::string& name);

/// Reads and checks a script; errors name the file, the step and the key.
Result<std::vector<ScriptStep>> readInputScript(const std::filesystem::path& file);

}  // namespace orbis::ui
