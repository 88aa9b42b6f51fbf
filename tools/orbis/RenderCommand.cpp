// orbis render SCENE -o OUT.png: one frame, headless, to a PNG.
#include "tools/orbis/Commands.h"

#include "engine/core/Log.h"
#include "engine/core/Png.h"
#include "engine/gpu/VkCheck.h"
#include "tools/orbis/Session.h"

#include <chrono>
#include <cstdio>

namespace orbis::cli {

namespace {
const char* kHelp =
    "usage: orbis render SCENE -o OUT.png [options]\n"
    "Renders one frame of SCENE headlessly and writes it as a PNG.\n"
    "  -o, --output FILE  the PNG to write (required)\n"
    "  --size WxH         image size in pixels (default 1280x720)\n"
    "  --time T           virtual time: ISO-8601 (2026-03-20T08:00:00Z) or seconds after the scene start\n"
    "  --wait S           wait at most S seconds for streamed data (tiles) before the frame (default 300)\n"
    "  --first-frame      render the very first frame, without waiting for any data\n";
}

int renderCommand(const std::vector<std::string>& argv) {
    std::set<std::string> valued = gpuValuedOptions();
    valued.insert({"--output", "--size", "--time", "--wait"});
    std::set<std::string> flags = gpuFlagOptions();
    flags.insert({"--help", "--first-frame"});
    Args args(argv, valued, flags, {{"-o", "--output"}, {"-h", "--help"}});
    if (args.flag("--help")) {
        std::printf("%s%s", kHelp, gpuOptionsHelp().c_str());
        return kOk;
    }
    if (args.positional().size() != 1) throw UsageError{"render expects exactly one SCENE file"};
    const auto output = args.value("--output");
    if (!output) throw UsageError{"render needs an output file: -o OUT.png"};
    const auto [width, height] = args.size("--size").value_or(std::make_pair(1280u, 720u));

    auto loaded = loadSceneForCommand(args);
    if (!loaded) return kBadInput;

    const auto t0 = std::chrono::steady_clock::now();
    GpuSession gpu = openGpu(args);
    // Declared after the device so that its layers are destroyed first.
    std::unique_ptr<scene::Scene> scene = std::move(loaded).value();
    render::Renderer renderer(*gpu.device, width, height);
    scene->time().advance(0.0);
    if (!args.flag("--first-frame")) {
        const double wait = args.number("--wait", 0.0, 86400.0).value_or(300.0);
        const int frames = renderer.settle(*scene, wait);
        if (scene->busy()) log::warn("still loading after ", wait, " s (", frames, " frames): the image may lack detail");
    }
    const auto frame = renderer.render(*scene, /*readback=*/true);
    for (const auto& r : scene->resources())
        if (r.visible && !r.layer->status().empty()) log::info(r.name, ": ", r.layer->status());
    ImageRgba8 image{width, height, renderer.readPixels(frame)};
    if (auto ok = writePng(*output, image); !ok) {
        std::fprintf(stderr, "orbis: %s\n", ok.message().c_str());
        return kBadInput;
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    log::info("wrote ", *output, " (", width, "x", height, ") in ", ms, " ms on ", gpu.device->info().name);
    std::printf("wrote %s (%ux%u)\n", output->c_str(), width, height);
    return validationExitCode(gpu);
}

}  // namespace orbis::cli
