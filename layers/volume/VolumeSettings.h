#pragma once
// The volume layer's settings as the scene file gives them and live edits change them. No
// Vulkan: the uniform packing (VolumeUniforms.h) and its tests use them without a device.

#include "engine/scene/LayerSetting.h"
#include "layers/volume/VolumeData.h"

#include <vector>

namespace orbis::layers {

// The ranges of the numeric settings, written once for the scene reader (what a file may give),
// setParameter (what a live edit may set: "steps" is clamped to its range, the others refused
// outside theirs) and liveSettings (the panel's sliders).
constexpr scene::SettingRange kStepsRange{1.0, 4096.0};
constexpr scene::SettingRange kOpacityUnitRange{1e-6, 10.0};
constexpr scene::SettingRange kOpacityScaleRange{0.0, 1000.0};
constexpr scene::SettingRange kOpacityRange{0.0, 1.0};            ///< isoOpacity, sliceOpacity
constexpr scene::SettingRange kSliceLatitudeRange{-89.0, 89.0};   ///< a latitude slice's cone (deg)
constexpr scene::SettingRange kRayResolutionRange{0.125, 1.0};
constexpr scene::SettingRange kRefineThresholdRange{0.0, 1.0};

struct VolumeSettings {
    /// How virtual time picks the data's time step: "fixed" (timeStep), "nearest" time step, or
    /// "blend" linearly between the two time steps around the current time.
    enum class TimeMode { Fixed, Nearest, Blend } timeMode = TimeMode::Blend;
    bool dvr = true;
    std::vector<double> isovalues;   ///< mode "iso": up to 8 surfaces, coloured by the colour map
    double isoOpacity = 1.0;
    /// Mode "slice": up to 4 surfaces of constant longitude, latitude or height (data metres),
    /// coloured by the colour map at the field's value.
    struct Slice {
        enum class Axis { Lon, Lat, Height } axis = Axis::Lon;
        double value = 0.0;
    };
    std::vector<Slice> slices;
    double sliceOpacity = 1.0;
    int steps = 100;   ///< ray steps along the box's normalised diagonal
    /// The length, in the box's normalised coordinates (each edge 1), over which a sample's
    /// opacity is the transfer function's alpha (VTK's "scalar opacity unit distance", relative
    /// to the box). Default: a hundredth of the normalised diagonal.
    double opacityUnit = 0.017320508075688773;
    TransferFunctionDesc transfer;
    bool rangeFromData = true;
    double verticalExaggeration = 1.0;
    /// DVR composites each step as the segment between two samples, from a 2-D table of the
    /// transfer function integrated between every pair of values (the value taken as linear
    /// along the segment). Off (the default): each sample's own value. Measured on lavapipe
    /// (tools/peer-volume.sh, layers/volume/PERFORMANCE.md): with narrow opacity peaks it cuts
    /// the error at 25 steps from 21 to 5.7; with the VTK peer's smooth curve the jittered
    /// samples are as good, and the 2-D fetch costs 10-40 % more a step.
    bool preIntegration = false;
    /// Rays at this fraction of the image's resolution along each axis (1: one per pixel). Below
    /// 1, a second pass at full resolution interpolates them where the four around a pixel agree
    /// (each RGBA channel, premultiplied 0..1, spread by no more than `refineThreshold`) and the
    /// scene's depth at their pixels is the pixel's own; elsewhere (the box's edges, sharp
    /// features, surfaces in front) the pixel casts its own ray. The default threshold (0.05,
    /// about 13 levels) was measured on the VTK peer's volume at half resolution: 1/64 refined
    /// twice the pixels for no less error (layers/volume/PERFORMANCE.md).
    double rayResolution = 1.0;
    double refineThreshold = 0.05;
    /// Rays jump over bricks that show nothing under the transfer function and isovalues.
    bool emptySkipping = true;
    /// The field on the GPU: "float32" (exact) or "float16": half the memory and ~10 % faster
    /// on lavapipe; values are stored relative to the data's range (mid-range 0, ends +-1),
    /// so they keep 11 significant bits of the range (0.05 % at its ends, finer near the middle);
    /// no data stays NaN.
    bool halfField = false;
};

}  // namespace orbis::layers
