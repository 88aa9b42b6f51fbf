#pragma once
// What the volume renderer uploads, prepared on the CPU (no Vulkan, unit-testable):
// - axis lookups: sample coordinate (lon, lat or height) -> texture coordinate, exact for
//   uniform axes and through a small table for irregular ones (Gaussian latitudes, pressure
//   levels turned into heights);
// - a min/max brick grid over the field for empty-space skipping;
// - the transfer function: a named colour map and opacity control points over a data range,
//   sampled into a table for a 1-D texture.

#include "layers/volume/VolumeReader.h"

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace orbis::layers {

/// Coordinate -> texture coordinate along one axis, with texel centres at the samples:
/// sample i of n maps to (i + 0.5) / n, linear in between, clamped beyond the ends.
struct AxisLookup {
    double first = 0.0, last = 0.0;   ///< coordinates of the first and last samples
    size_t samples = 0;
    bool uniform = true;              ///< evenly spaced: u is linear in the coordinate
    /// Irregular axes: u at `table.size()` coordinates spread evenly from first to last. On the
    /// GPU it is a linearly filtered 1-D texture read at (f (size - 1) + 0.5) / size, with
    /// f = (x - first) / (last - first) clamped to 0..1.
    std::vector<float> table;

    /// Builds the lookup; `tableSize` entries for an irregular axis (at least 2).
    static AxisLookup build(const std::vector<double>& coordinates, size_t tableSize = 256);
    /// Exact texture coordinate of a coordinate (piecewise linear between samples).
    double exact(const std::vector<double>& coordinates, double x) const;
    /// What the GPU computes: linear for uniform axes, the table (linearly filtered) otherwise.
    double lookup(double x) const;
};

/// Min/max of the valid values in bricks of `size`^3 voxels (each brick also covers the one
/// voxel row past its end, which linear filtering reaches). A brick without valid values has
/// min = +inf and max = -inf, so no range test ever picks it.
struct BrickGrid {
    int size = 8;
    size_t bx = 0, by = 0, bz = 0;
    std::vector<std::pair<float, float>> minMax;   ///< (x fastest)
    const std::pair<float, float>& at(size_t i, size_t j, size_t k) const { return minMax[(k * by + j) * bx + i]; }
    size_t emptyBricks() const;
};
BrickGrid buildBrickGrid(const VolumeField& field, int brickSize = 8);
/// The same over a raw array of nx * ny * nz values (x fastest).
BrickGrid buildBrickGrid(const float* values, size_t nx, size_t ny, size_t nz, int brickSize = 8);
/// Widens each brick of `into` to cover the same brick of `other` (same layout): the union
/// over time steps, which also holds for any blend of two steps.
void mergeBrickGrid(BrickGrid& into, const BrickGrid& other);

/// Which bricks can show anything, one bit each (bit b % 32 of word b / 32, bricks x fastest):
/// with `dvr`, those where the transfer table (`table`, evenly spaced over [rangeMin,
/// rangeMax], read with linear interpolation and clamped beyond the ends) has an opacity
/// above zero anywhere in the brick's value range; and those whose range holds an isovalue.
/// Bricks without valid values never do. Ray casting jumps over the others.
std::vector<uint32_t> brickOccupancy(const BrickGrid& grid, const std::vector<std::array<float, 4>>& table,
                                     double rangeMin, double rangeMax, bool dvr, const std::vector<double>& isovalues);

/// A colour map by name: "viridis", "magma", "inferno", "plasma", "cividis", "coolwarm",
/// "greys", "turbo". Colours are sRGB anchors, interpolated in linear light.
bool hasColorMap(const std::string& name);
std::vector<std::string> colorMapNames();

/// Opacity control points a transfer function may have (the scene file and the editor).
constexpr size_t kMaxOpacityPoints = 256;

struct OpacityPoint {
    double value;   ///< data units
    double alpha;   ///< 0..1, per unit of "reference step" (see VolumeSettings)
};

struct TransferFunctionDesc {
    std::string colorMap = "viridis";
    double rangeMin = 0.0, rangeMax = 1.0;   ///< data values at the two ends of the colour map
    /// Piecewise-linear opacity over data values (sorted by value; clamped beyond the ends).
    /// Empty: a ramp from 0 at rangeMin to 1 at rangeMax.
    std::vector<OpacityPoint> opacity;
    double opacityScale = 1.0;
};

/// The transfer function sampled at `size` evenly spaced values over [rangeMin, rangeMax]:
/// linear RGB + alpha, floats. Errors for an unknown colour map or an empty range.
Result<std::vector<std::array<float, 4>>> buildTransferTable(const TransferFunctionDesc& desc, size_t size = 256);

/// The pre-integrated transfer function of a transfer table (`table`, as buildTransferTable
/// makes it, `n` entries): for a ray segment `step` long (box-normalised units, opacity per
/// 1 / `opacityPerUnit` of them) along which the value runs linearly from table position i at
/// its front to j at its back, entry [j * n + i] holds
///   rgb: the colour the segment adds per unit of its opacity, its self-attenuation included
///        (what it adds is alpha * rgb, premultiplied);
///   a:   the mean of log2(1 - alpha) over the segment, alpha clamped to 0.9999 as the ray
///        caster's table is: the segment's opacity is 1 - exp2(a * length * opacityPerUnit),
///        exact for any length, since the values between table entries are linear.
/// The colour is integrated in sub-steps (at least 2 per table entry crossed, at most 128);
/// it is exact for segments `step` long and a close approximation for others (the ray caster
/// marches in steps of about `step`). i == j is the plain table's entry.
std::vector<std::array<float, 4>> buildPreIntegratedTable(const std::vector<std::array<float, 4>>& table, double step,
                                                          double opacityPerUnit);

/// Opacity of one step of length `step` when `alpha` is the opacity of a step of `reference`:
/// 1 - (1 - alpha)^(step / reference), so that the result does not depend on the step count.
double correctOpacity(double alpha, double step, double reference);

}  // namespace orbis::layers
