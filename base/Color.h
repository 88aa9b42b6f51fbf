#pragma once
// Colour conversions. Scene files give colours sRGB-encoded; shaders and clears work in linear.

#include <cmath>

namespace orbis {

/// IEC 61966-2-1 sRGB decoding of one channel in [0, 1].
inline double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

}  // namespace orbis
