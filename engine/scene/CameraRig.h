#pragma once
// Camera modes that watch a moving thing (a model on its trajectory or on a live feed): the
// camera's pose is a function of the target's pose at the scene's virtual time, so the same
// time gives the same view whatever the path that led there (seeks, steps, playback).
//
//   overview  frames the whole path (the layer's ContentBounds) from above, north up
//   follow    behind and above the target, looking at it; "behind" is the direction of travel
//             over the last `smoothing` seconds (the chord from the pose then to the pose now),
//             so turns and jitter do not whip the camera; `heading` / `pitch` orbit around it
//   pilot     at the eye point inside the target (`eye`, body axes), looking along its attitude
//   inside    as pilot (the live object's "inside" position)
//   above     straight above the target at `distance`, looking down, the target's nose up
//   aside     level with the target at `distance` off its right side, looking at it
//   below     under the target at `distance`, looking up at its belly
//
// Distances of 0 mean "from the target's size": follow 4 radii + 5 m, above/aside/below
// 6 radii + 5 m. Angles in degrees. Switching modes (Scene::setCameraMode with a flight time)
// flies from the current view to the new mode's over that many wall seconds: a user-interface
// motion, the one thing here on wall time; headless renders switch at once.
//
// No Vulkan.

#include "engine/scene/CameraMode.h"
#include "engine/scene/Layer.h"
#include "globe/Viewpoint.h"

namespace orbis::scene {

/// The camera for a mode that needs only the target's pose at one time (all but follow's
/// direction of travel and overview). `travel` is follow's direction of travel (ECEF; any
/// length; zero: the target's nose).
globe::Pose cameraForTarget(const CameraModeSettings& s, const TrackedPose& target, const glm::dvec3& travel);

/// Overview: the whole of `bounds` in view (vertical field of view `fovYRad`, `aspect`), seen
/// from above at 60 degrees down, north up.
globe::Pose cameraForOverview(const ContentBounds& bounds, double fovYRad, double aspect);

/// A flight from `from` to `to` at fraction `f` in [0, 1] (eased): along the ellipsoid between
/// the two places, raised by a third of the distance at mid-flight, orientation slerped.
globe::Pose blendPoses(const globe::Pose& from, const globe::Pose& to, double f);

}  // namespace orbis::scene
