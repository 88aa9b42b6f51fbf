#pragma once
// The ray caster's numbers, computed on the CPU without Vulkan: the curved box's frame (once,
// when the layer is prepared) and each frame's shader::VolumeUniforms (the block raycast.comp
// reads; shaders/shared/VolumeTypes.h). Pure functions: any thread.

#include "layers/volume/VolumeSettings.h"
#include "shared/VolumeTypes.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace orbis::layers {

/// The curved box of a (lon, lat, height) grid in its own frame, in double precision.
struct VolumeBox {
    glm::dvec3 origin{0.0};   ///< ECEF: on the bottom surface (drawn height), at the box's centre
    glm::dvec3 min{0.0}, max{0.0};   ///< bounds of the box in ECEF axes, relative to the origin (m)
    /// Drawn heights of the shell's bottom and top surfaces (m): the data's, with a margin.
    double shellLow = 0.0, shellHigh = 0.0;
    /// The longest jump over empty bricks: metres, and metres per metre from the polar axis.
    glm::dvec2 jumpLimit{0.0};
};

/// The box of a grid on WGS84: `lonDeg` as uploaded (with the wrap column of a periodic field),
/// `latDeg` and `heightM` ascending, heights drawn `verticalExaggeration` times.
VolumeBox makeVolumeBox(const std::vector<double>& lonDeg, const std::vector<double>& latDeg,
                        const std::vector<double>& heightM, double verticalExaggeration);

/// What one frame's uniforms are made of.
struct VolumeFrameInputs {
    const VolumeSettings& settings;
    const VolumeBox& box;
    // The grid as uploaded: the first and last coordinates along each axis (degrees, degrees,
    // data metres) and the samples along them (lon with the wrap column).
    glm::dvec2 lonRange{0.0}, latRange{0.0}, heightRange{0.0};
    glm::uvec3 samples{1u};
    glm::uvec3 bricks{1u};             ///< bricks along lon, lat, height
    uint32_t brickSize = 8;            ///< voxels along a brick's edge
    glm::dvec2 valueScale{1.0, 0.0};   ///< field value = stored * x + y
    size_t timeSteps = 1;              ///< stacked along the texture's z
    glm::vec3 timeBlend{0.0f};         ///< the time steps shown (A, B) and the weight of B
    // The camera and the frame.
    glm::dvec3 eye{0.0};               ///< ECEF
    glm::dvec3 forward{0.0, 0.0, -1.0};   ///< the view direction
    double nearPlane = 1.0;
    uint64_t frame = 0;
};

/// Every field of the ray caster's uniform block for one frame.
shader::VolumeUniforms packVolumeUniforms(const VolumeFrameInputs& in);

}  // namespace orbis::layers
