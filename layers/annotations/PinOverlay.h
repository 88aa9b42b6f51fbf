#pragma once
// The pins of a scene's annotations as screen-space rectangles: a stem from the point up, a
// square head, and the name in a box (base/LabelText). Pins hidden by the ground or the
// ellipsoid, behind the eye or far off the screen are left out. No Vulkan.

#include "engine/scene/Annotation.h"
#include "engine/scene/Camera.h"
#include "engine/scene/Layer.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace orbis::layers {

struct PinStyle {
    glm::dvec3 color{0.95, 0.35, 0.12};   ///< sRGB of the head
    double labelScale = 2.0;              ///< 1: 7 pixels a line of text
    bool labels = true;
    double stemPx = 22.0;
    double headPx = 11.0;
};

/// A filled rectangle in window pixels (x right, y down), colour in linear RGBA.
struct PinQuad {
    glm::dvec2 min, max;
    glm::vec4 color;
};

/// True when the straight line from `eye` to `point` (ECEF) passes under the ground before it
/// gets there: the line is sampled at 64 places and each is compared with `ground` (the
/// ellipsoid where it knows nothing). The last max(5 m, 0.2 %) of the line is not tested, so that
/// a pin on a slope is not hidden by the ground it stands on.
bool pinHidden(const glm::dvec3& eye, const glm::dvec3& point, const scene::GroundHeightFn& ground);

struct PinLayout {
    std::vector<PinQuad> quads;   ///< back to front
    std::size_t drawn = 0;        ///< pins with rectangles
    std::size_t dropped = 0;      ///< pins in view left out for want of room
};

/// Rectangles for the pins seen by `camera` in a `width` x `height` view, at most `maxQuads`:
/// the nearest pins first in the budget, and drawn last (on top).
PinLayout layoutPins(const std::vector<scene::Annotation>& pins, const scene::Camera& camera, uint32_t width,
                     uint32_t height, const scene::GroundHeightFn& ground, const PinStyle& style, std::size_t maxQuads);

}  // namespace orbis::layers
