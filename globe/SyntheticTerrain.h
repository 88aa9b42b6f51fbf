#pragma once
// Generated ground for benchmarks and demos that need more terrain than the repository can
// hold: fractal hills (octaves of 3-D gradient noise over the Earth's surface, so there is no
// seam at the antimeridian and no pinch at the poles), deterministic for a seed. A HeightAt, like
// a DEM read through ElevationSampler. No Vulkan, no GDAL.

#include "globe/TerrainAnalysis.h"

#include <cstdint>

namespace orbis::globe {

struct SyntheticTerrainOptions {
    uint32_t seed = 1;
    double base = 300.0;           ///< mean height, metres
    double relief = 400.0;         ///< the largest octave's amplitude, metres
    double wavelengthM = 6000.0;   ///< the largest octave's wavelength
    int octaves = 7;               ///< each half the wavelength and amplitude of the one before
};

/// Heights everywhere (never none).
HeightAt syntheticTerrain(const SyntheticTerrainOptions& options = {});

}  // namespace orbis::globe
