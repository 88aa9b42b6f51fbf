#pragma once
// The camera modes a scene can ask for (engine/scene/CameraRig.h computes them) and their
// settings, as the scene file gives them:
//   "camera": {"mode": "follow", "target": "Train", "distance": 0, "heading": 0, "pitch": -15,
//              "smoothing": 2, "eye": [0, 0, 0]}
// No Vulkan.

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace orbis::scene {

enum class CameraMode { Free, Overview, Follow, Pilot, Inside, Above, Aside, Below };

/// "free", "overview", "follow", "pilot", "inside", "above", "aside", "below".
const char* toString(CameraMode mode);
std::optional<CameraMode> parseCameraMode(std::string_view text);

struct CameraModeSettings {
    CameraMode mode = CameraMode::Free;
    std::string target;              ///< the layer (resource name) whose trackedPose is watched
    double distance = 0.0;           ///< metres; 0: from the target's size
    double headingDeg = 0.0;         ///< follow: orbit about the target from straight behind (+ = to its right)
    double pitchDeg = -15.0;         ///< follow: the camera looks down by this (negative) angle
    double smoothingSeconds = 2.0;   ///< follow: the direction of travel is taken over this window
    glm::dvec3 eye{0.0};             ///< pilot/inside: eye point in body axes (x fwd, y right, z down), metres
};

}  // namespace orbis::scene
