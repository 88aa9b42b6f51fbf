// orbis: the command-line front end. Thin: each command lives in its own file.
#include "base/Log.h"
#include "engine/gpu/VkCheck.h"
#include "tools/orbis/Commands.h"
#include "tools/orbis/Session.h"

#include <malloc.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

namespace {

const char* kUsage =
    "usage: orbis [-v|-vv|-q] COMMAND [args]\n"
    "Commands:\n"
    "  view SCENE                open SCENE in a window (mouse, keyboard, panels)\n"
    "  render SCENE -o OUT.png   render one frame headlessly to a PNG\n"
    "  bench SCENE               frame-time statistics (CPU, GPU per pass)\n"
    "  info [FILE]               the GPU and features used, or what FILE holds\n"
    "  measure --path|--sight    geodesic lengths and areas, terrain profiles, lines of sight\n"
    "  viewshed --dem --observer what an observer sees of the ground (GPU), against GDAL's\n"
    "  wps URL [--describe|--run] a WPS processing server: its processes, a process, a run\n"
    "  convert IN OUT            point clouds between LAS and LAZ (--decode: decoding speed)\n"
    "Run 'orbis COMMAND --help' for a command's options.\n"
    "Exit codes: 0 ok, 1 bad input (the message names the file and the problem), 2 usage.\n";

}  // namespace

int main(int argc, char** argv) {
    using namespace orbis;
    // Tiles (imagery with mips: ~350 KB) and GDAL's warp buffers come and go all the time. By
    // default glibc raises its mmap threshold after the first such free, then serves them from
    // the heap, where they fragment: a long flight kept ~75 MB of freed memory resident. A
    // fixed threshold maps them and gives them back on free.
    mallopt(M_MMAP_THRESHOLD, 128 * 1024);
    std::vector<std::string> args(argv + 1, argv + argc);
    // Global options come before the command.
    log::setLevel(log::Level::Warn);
    while (!args.empty() && args.front().size() > 1 && args.front()[0] == '-') {
        const std::string a = args.front();
        if (a == "-v") log::setLevel(log::Level::Info);
        else if (a == "-vv") log::setLevel(log::Level::Debug);
        else if (a == "-vvv") log::setLevel(log::Level::Trace);
        else if (a == "-q" || a == "--quiet") log::setLevel(log::Level::Error);
        else if (a == "-h" || a == "--help") {
            std::printf("%s", kUsage);
            return cli::kOk;
        } else {
            std::fprintf(stderr, "orbis: unknown option %s\n%s", a.c_str(), kUsage);
            return cli::kUsage;
        }
        args.erase(args.begin());
    }
    if (args.empty()) {
        std::fprintf(stderr, "%s", kUsage);
        return cli::kUsage;
    }
    const std::string command = args.front();
    args.erase(args.begin());
    try {
        if (command == "view") return cli::viewCommand(args);
        if (command == "render") return cli::renderCommand(args);
        if (command == "bench") return cli::benchCommand(args);
        if (command == "info") return cli::infoCommand(args);
        if (command == "measure") return cli::measureCommand(args);
        if (command == "viewshed") return cli::viewshedCommand(args);
        if (command == "wps") return cli::wpsCommand(args);
        if (command == "convert") return cli::convertCommand(args);
        if (command == "help") {
            std::printf("%s", kUsage);
            return cli::kOk;
        }
        std::fprintf(stderr, "orbis: unknown command '%s'\n%s", command.c_str(), kUsage);
        return cli::kUsage;
    } catch (const cli::UsageError& e) {
        std::fprintf(stderr, "orbis %s: %s (see 'orbis %s --help')\n", command.c_str(), e.message.c_str(),
                     command.c_str());
        return cli::kUsage;
    } catch (const gpu::GpuError& e) {
        if (e.result() == VK_ERROR_DEVICE_LOST) {   // batch commands have no view to save
            std::fprintf(stderr, "orbis: the GPU device was lost: %s\n", e.what());
            return cli::kDeviceLost;
        }
        std::fprintf(stderr, "orbis: GPU: %s\n", e.what());
        return cli::kBadInput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "orbis: error: %s\n", e.what());
        return cli::kBadInput;
    }
}
