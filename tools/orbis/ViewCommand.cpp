// orbis view SCENE: the desktop viewer (ui/Viewer.h).
#include "tools/orbis/Commands.h"

#include "tools/orbis/Session.h"
#include "ui/Viewer.h"

#include <cstdio>

namespace orbis::cli {

namespace {
const char* kHelp =
    "usage: orbis view SCENE [options]\n"
    "Opens SCENE in a window. Mouse: left-drag rotates the globe, right-drag or the wheel zooms\n"
    "toward the cursor, middle-drag or Ctrl+left-drag tilts and turns, double-click flies to a\n"
    "point. Keys: W A S D / arrows move, Q E turn, R F / PageUp PageDown zoom, Home goes to the\n"
    "scene's viewpoint, F1 hides the panels, F12 saves a screenshot, Ctrl+S saves the scene,\n"
    "Esc quits.\n"
    "  --size WxH         window size (default 1280x720)\n"
    "  --no-vsync         present without waiting for the display (MAILBOX or IMMEDIATE)\n"
    "  --no-panels        start with the panels hidden (F1 shows them)\n"
    "  --script FILE      play an input script (JSON; see ui/InputScript.h) instead of waiting\n"
    "                     for the user: tests, demos, screenshots of the live UI\n"
    "  --screenshots DIR  where F12 writes its PNGs (default: the current folder)\n"
    "  --save-to FILE     where Ctrl+S saves the scene (camera, time, layers, settings) for\n"
    "                     orbis render (default: SCENE-view.json beside SCENE)\n"
    "  --wps URL          a processing server (OGC WPS 1.0.0) for the Processes panel; repeat\n"
    "                     for more (tools/serve-wps.sh starts the demo server)\n"
    "  --results DIR      where processing results are written (default: ~/.cache/orbis/wps)\n";
}  // namespace

int viewCommand(const std::vector<std::string>& argv) {
    std::set<std::string> valued = gpuValuedOptions();
    valued.insert({"--size", "--script", "--screenshots", "--save-to", "--wps", "--results"});
    std::set<std::string> flags = gpuFlagOptions();
    flags.insert({"--help", "--no-vsync", "--no-panels"});
    Args args(argv, valued, flags, {{"-h", "--help"}});
    if (args.flag("--help")) {
        std::printf("%s%s", kHelp, gpuOptionsHelp().c_str());
        return kOk;
    }
    if (args.positional().size() != 1) throw UsageError{"view expects exactly one SCENE file"};
    ui::ViewerOptions o;
    o.scene = args.positional().at(0);
    const auto [width, height] = args.size("--size").value_or(std::make_pair(1280u, 720u));
    o.width = width;
    o.height = height;
    o.vsync = !args.flag("--no-vsync");
    o.panels = !args.flag("--no-panels");
    o.device = args.value("--device").value_or("");
    o.validation = args.flag("--validation");
    o.script = args.value("--script").value_or("");
    o.screenshotFolder = args.value("--screenshots").value_or(".");
    o.saveTo = args.value("--save-to").value_or("");
    for (const std::string& url : args.values("--wps")) {
        if (url.rfind("http://", 0) != 0 && url.rfind("https://", 0) != 0)
            throw UsageError{"--wps: \"" + url + "\" is not an http(s) address"};
        o.wpsServers.push_back(url);
    }
    o.resultsFolder = args.value("--results").value_or("");
    const int code = ui::runViewer(o);
    if (code == ui::Viewer::kDeviceLostExit) return kDeviceLost;
    return code == 0 ? kOk : kBadInput;
}

}  // namespace orbis::cli
