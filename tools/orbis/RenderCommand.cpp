// orbis render SCENE -o OUT.png: one frame, headless, to a PNG.
#include "tools/orbis/Commands.h"

#include "base/Log.h"
#include "base/Png.h"
#include "engine/gpu/VkCheck.h"
#include "engine/scene/CameraPath.h"
#include "tools/orbis/Session.h"

#include <chrono>
#include <cctype>
#include <cstdio>
#include <optional>

namespace orbis::cli {

namespace {
const char* kHelp =
    "usage: orbis render SCENE -o OUT.png [options]\n"
    "Renders one frame of SCENE headlessly and writes it as a PNG.\n"
    "  -o, --output FILE  the PNG to write (required)\n"
    "  --size WxH         image size in pixels (default 1280x720)\n"
    "  --time T           virtual time: ISO-8601 (2026-03-20T08:00:00Z) or seconds after the scene start\n"
    "  --wait S           wait at most S seconds for streamed data (tiles) before the frame (default 300)\n"
    "  --first-frame      render the very first frame, without waiting for any data\n"
    "  --camera-path FILE take the camera from this path (orbis-camera-path JSON): at --path-time S\n"
    "                     (seconds, default the path's start), or, when OUT contains a printf\n"
    "                     pattern such as frame_%04d.png, as --frames N images along the whole path\n"
    "  --path-time S      see --camera-path\n"
    "  --frames N         see --camera-path (default 30)\n";
}

namespace {
/// OUT with its one "%d" / "%04d" replaced by the frame number. Anything else after a '%' is
/// a usage error (the pattern never reaches printf).
std::string frameFileName(const std::string& pattern, long frame) {
    const size_t p = pattern.find('%');
    size_t q = p + 1;
    while (q < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[q]))) ++q;
    if (q >= pattern.size() || pattern[q] != 'd' || pattern.find('%', q) != std::string::npos || q - p - 1 > 2)
        throw UsageError{"-o: a frame pattern takes one %d or %0Nd (N < 100), got '" + pattern + "'"};
    const int width = q > p + 1 ? std::stoi(pattern.substr(p + 1, q - p - 1)) : 0;
    std::string number = std::to_string(frame);
    if (int(number.size()) < width) number.insert(0, size_t(width) - number.size(), '0');
    return pattern.substr(0, p) + number + pattern.substr(q + 1);
}
}  // namespace

int renderCommand(const std::vector<std::string>& argv) {
    std::set<std::string> valued = gpuValuedOptions();
    valued.insert({"--output", "--size", "--time", "--wait", "--camera-path", "--path-time", "--frames"});
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
    auto loadedPath = loadCameraPathOption(args);
    if (!loadedPath) return kBadInput;
    const std::optional<scene::CameraPath> path = std::move(loadedPath).value();
    const bool sequence = path && output->find('%') != std::string::npos;
    if (sequence) (void)frameFileName(*output, 0);   // a bad pattern is a usage error before any work
    const long count = sequence ? args.integer("--frames", 1, 100000).value_or(30) : 1;
    const double wait = args.number("--wait", 0.0, 86400.0).value_or(300.0);
    scene->time().advance(0.0);
    for (long i = 0; i < count; ++i) {
        if (path) {
            const double t = sequence ? path->startTime() + (count > 1 ? double(i) / double(count - 1) : 0.0) * path->duration()
                                      : args.number("--path-time", -1e9, 1e9).value_or(path->startTime());
            scene->camera().setPose(scene->keptAboveGround(globe::poseFromViewpoint(path->at(t))));
        }
        if (!args.flag("--first-frame")) {
            int frames = renderer.settle(*scene, wait);
            // The ground under the eye may only be known now that the view has loaded.
            const globe::Pose lifted = scene->keptAboveGround(scene->camera().pose());
            if (path && lifted.position != scene->camera().pose().position) {
                scene->camera().setPose(lifted);
                frames += renderer.settle(*scene, wait);
            }
            if (scene->busy()) log::warn("still loading after ", wait, " s (", frames, " frames): the image may lack detail");
        }
        const auto frame = renderer.render(*scene, /*readback=*/true);
        for (const auto& r : scene->resources())
            if (r.visible && !r.layer->status().empty()) log::info(r.name, ": ", r.layer->status());
        ImageRgba8 image{width, height, renderer.readPixels(frame)};
        const std::string file = sequence ? frameFileName(*output, i) : *output;
        if (auto ok = writePng(file, image); !ok) return badInput(ok.message());
        if (sequence) std::printf("wrote %s\n", file.c_str());
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    log::info("wrote ", *output, " (", width, "x", height, ") in ", ms, " ms on ", gpu.device->info().name);
    std::printf("wrote %s (%ux%u)\n", output->c_str(), width, height);
    return validationExitCode(gpu);
}

}  // namespace orbis::cli
