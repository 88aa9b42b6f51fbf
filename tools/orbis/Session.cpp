#include "tools/orbis/Session.h"

#include "base/TimeFormat.h"
#include "layers/BuiltinLayers.h"

#include <cstdio>

#include <charconv>

namespace orbis::cli {

int badInput(const std::string& message) {
    std::fprintf(stderr, "orbis: %s\n", message.c_str());
    return kBadInput;
}

const std::set<std::string>& gpuValuedOptions() {
    static const std::set<std::string> s{"--device"};
    return s;
}

const std::set<std::string>& gpuFlagOptions() {
    static const std::set<std::string> s{"--validation"};
    return s;
}

std::string gpuOptionsHelp() {
    return "  --device SEL      GPU to use: discrete | integrated | cpu | an index | part of its name\n"
           "                    (default: the first discrete GPU, else the CPU renderer lavapipe)\n"
           "  --validation      load the Khronos validation layer and report its messages\n";
}

GpuSession openGpu(const Args& args) {
    GpuSession s;
    gpu::InstanceOptions io;
    io.validation = args.flag("--validation");
    s.instance = std::make_unique<gpu::Instance>(io);
    gpu::DeviceOptions dopt;
    dopt.select = args.value("--device").value_or("");
    s.device = std::make_unique<gpu::Device>(*s.instance, dopt);
    return s;
}

Result<std::unique_ptr<scene::Scene>> loadScene(const std::string& file, const scene::LayerRegistry& registry) {
    auto desc = scene::parseSceneFile(file);
    if (!desc) return desc.error();
    return scene::Scene::build(std::move(desc).value(), registry);
}

Result<std::unique_ptr<scene::Scene>> loadSceneForCommand(const Args& args) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    auto loaded = loadScene(args.positional().at(0), registry);
    if (!loaded) {
        std::fprintf(stderr, "orbis: %s\n", loaded.message().c_str());
        return loaded;
    }
    applyTimeOption(args, **loaded);
    return loaded;
}

Result<std::optional<scene::CameraPath>> loadCameraPathOption(const Args& args) {
    const auto file = args.value("--camera-path");
    if (!file) return std::optional<scene::CameraPath>();
    auto parsed = scene::CameraPath::parseFile(*file);
    if (!parsed) {
        std::fprintf(stderr, "orbis: %s\n", parsed.message().c_str());
        return parsed.error();
    }
    return std::optional<scene::CameraPath>(std::move(parsed).value());
}

int validationExitCode(const GpuSession& gpu) {
    if (gpu.instance->validationMessages() == 0) return kOk;
    std::fprintf(stderr, "orbis: validation reported %d message(s); first: %s\n", gpu.instance->validationMessages(),
                 gpu.instance->firstValidationMessage().c_str());
    return kBadInput;
}

void applyTimeOption(const Args& args, scene::Scene& scene) {
    auto text = args.value("--time");
    if (!text) return;
    TimeNs t = 0;
    double seconds = 0.0;
    auto [ptr, ec] = std::from_chars(text->data(), text->data() + text->size(), seconds);
    if (ec == std::errc() && ptr == text->data() + text->size()) {
        t = scene.time().start() + fromSeconds(seconds);
    } else {
        auto parsed = parseIso8601(*text);
        if (!parsed) throw UsageError{"option --time: " + parsed.message()};
        t = *parsed;
    }
    if (t < scene.time().start() || t > scene.time().end())
        throw UsageError{"option --time: " + formatIso8601(t) + " is outside the scene's time range [" +
                         formatIso8601(scene.time().start()) + ", " + formatIso8601(scene.time().end()) + "]"};
    scene.time().seek(t);
}

}  // namespace orbis::cli
