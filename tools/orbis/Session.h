#pragma once
// What every command that renders needs: a Vulkan instance and device, the layer registry and
// a loaded scene. Keeps the commands themselves short.

#include "base/Result.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Instance.h"
#include "engine/render/Renderer.h"
#include "engine/scene/CameraPath.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/Scene.h"
#include "tools/orbis/Args.h"

#include <memory>
#include <optional>
#include <string>

namespace orbis::cli {

/// Exit codes shared by every command.
enum ExitCode { kOk = 0, kBadInput = 1, kUsage = 2, kDeviceLost = 3 };

/// Prints "orbis: MESSAGE" on stderr, as every command reports bad input; returns kBadInput.
int badInput(const std::string& message);

/// Options every GPU command accepts.
const std::set<std::string>& gpuValuedOptions();
const std::set<std::string>& gpuFlagOptions();
std::string gpuOptionsHelp();

struct GpuSession {
    std::unique_ptr<gpu::Instance> instance;
    std::unique_ptr<gpu::Device> device;
};

/// Creates the instance and device from --device / --validation. Throws GpuError.
GpuSession openGpu(const Args& args);

/// Loads and builds a scene (exit code 1 on failure, with the message already printed).
Result<std::unique_ptr<scene::Scene>> loadScene(const std::string& file, const scene::LayerRegistry& registry);

/// Loads the scene named by the command's one positional argument with every built-in layer
/// type, applying --time; prints the problem and returns it on failure. Throws UsageError.
Result<std::unique_ptr<scene::Scene>> loadSceneForCommand(const Args& args);

/// "--camera-path FILE" (render, bench): the parsed path, or nothing without the option; prints
/// the problem and returns it when the file is missing or invalid (exit with kBadInput then).
Result<std::optional<scene::CameraPath>> loadCameraPathOption(const Args& args);

/// kBadInput (after printing the first message) when validation reported anything, else kOk.
int validationExitCode(const GpuSession& gpu);

/// "--time": an ISO-8601 instant, or seconds after the scene's start. Throws UsageError.
void applyTimeOption(const Args& args, scene::Scene& scene);

}  // namespace orbis::cli
