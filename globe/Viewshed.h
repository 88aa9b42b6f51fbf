#pragma once
// Viewsheds on the CPU: what an observer standing above the ground sees of it, cell by cell of a
// height grid. No Vulkan, no GDAL (layers/analysis/ViewshedGpu.h runs the same propagation on
// the GPU; globe/ViewshedGdal.h asks GDAL's for comparison).
//
// The grid is square and local to a centre: a plane tangent to the ellipsoid there, cells of
// `cellM` metres along east and north, row 0 the northernmost. Built from any height function
// (the finest DEM data through ElevationSampler), so it works the same at the poles and across
// the antimeridian, whatever the DEM's CRS. Heights are metres above the ellipsoid (NaN: no
// data).
//
// The model is gdal_viewshed's (GDAL 3.6, "edge" cell mode), so that the two agree cell for
// cell on the same grid: the ground drops by `curvature` d^2 / D at a distance d in the plane
// (D the equatorial diameter; 0.85714 = the Earth's curve less the usual refraction), and each
// cell's horizon is interpolated from the two cells next to it on the side of the observer
// (Wang, Robinson and White 2000, "Generating viewsheds without using sightlines"). A cell is
// seen when its ground plus `targetHeight` is not below that horizon. The horizon of ring d
// (the cells at Chebyshev distance d from the observer) depends on ring d - 1 only, which is
// what lets the GPU run a whole ring at once.
//
// `viewshedSightlines` is the slow exact reference: a straight sight line to each cell, the
// ground on it interpolated linearly where it crosses every row and column line (Franklin's R3).

#include "base/Result.h"
#include "globe/TerrainAnalysis.h"

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace orbis::globe {

/// west, south, east, north in degrees.
struct GeoExtentLonLat {
    double west = -180.0, south = -90.0, east = 180.0, north = 90.0;
};

struct ViewshedGrid {
    LonLat centre{0.0};   ///< the tangent point (cell radiusCells, radiusCells)
    double cellM = 30.0;
    int radiusCells = 0;  ///< the grid is 2 r + 1 cells a side
    std::vector<float> heights;   ///< row-major, row 0 north; NaN: no data

    int side() const { return 2 * radiusCells + 1; }
    float at(int col, int row) const { return heights[size_t(row) * size_t(side()) + size_t(col)]; }
    /// The plane offsets (east, north metres) of a cell's centre from the grid's centre.
    double east(int col) const { return (col - radiusCells) * cellM; }
    double north(int row) const { return (radiusCells - row) * cellM; }
    /// Where a cell's centre is on the ellipsoid. Each call sets up the tangent plane: for
    /// one lookup; in a loop use a ViewshedPlane made once.
    LonLat lonLatOf(int col, int row) const;
    /// The cell under a point (nothing outside the grid). As lonLatOf: one lookup.
    std::optional<std::pair<int, int>> cellOf(double lonDeg, double latDeg) const;
};

/// The tangent plane of a grid, made once for many lookups (drawing a viewshed on tiles).
class ViewshedPlane {
public:
    explicit ViewshedPlane(const ViewshedGrid& grid);
    LonLat at(double eastM, double northM) const;
    /// The cell under a point (nothing outside the grid or on the far side of the Earth).
    std::optional<std::pair<int, int>> cellOf(double lonDeg, double latDeg) const;
    /// A lon/lat box around the grid (longitudes continuous from the centre's, so that it may
    /// run past +-180; the whole turn when a pole is inside).
    GeoExtentLonLat bounds(const ViewshedGrid& grid) const;

private:
    glm::dvec3 origin_, east_, north_, up_;
    double cellM_;
    int radiusCells_;
};

/// Samples `ground` at every cell of a grid centred at `centre`, `radiusM` around it (rounded up
/// to whole cells). Fails on a radius or cell size out of range or more than `maxCells` cells.
Result<ViewshedGrid> sampleViewshedGrid(const HeightAt& ground, LonLat centre, double radiusM, double cellM,
                                        size_t maxCells = size_t(64) << 20);

/// The same area at a coarser cell (`factor` times the size): every factor-th cell from the
/// centre, which is what sampling the ground at that spacing gives.
ViewshedGrid coarsenViewshedGrid(const ViewshedGrid& grid, int factor);

struct ViewshedOptions {
    int observerCol = 0, observerRow = 0;   ///< the observer's cell
    double observerHeight = 2.0;            ///< eye above the ground, metres
    double targetHeight = 0.0;              ///< what must be seen above the ground at each cell
    double radiusM = 0.0;                   ///< cells farther (in the plane) are out of range; 0: the grid
    double curvature = 0.85714;             ///< gdal_viewshed's -cc; 0: a flat Earth
};

/// One byte a cell.
enum class Sight : uint8_t { Hidden = 0, Visible = 1, OutOfRange = 2, NoData = 3 };

struct Viewshed {
    int side = 0;
    std::vector<Sight> cells;   ///< row-major as the grid
    Sight at(int col, int row) const { return cells[size_t(row) * size_t(side) + size_t(col)]; }
    size_t count(Sight s) const;
};

/// The equatorial diameter gdal_viewshed divides by (WGS84).
inline constexpr double kViewshedEarthDiameter = 2.0 * 6378137.0;

/// The observer's cell for a point and its height (the ground at that cell plus the eye height);
/// fails outside the grid or on no data under the observer.
Result<double> viewshedEyeHeight(const ViewshedGrid& grid, const ViewshedOptions& options);

/// The ring propagation on the CPU in double (what the GPU computes in float).
Result<Viewshed> viewshedRings(const ViewshedGrid& grid, const ViewshedOptions& options);

/// The exact sight-line reference (slow: O(cells x radius)); `threads` 0: the hardware's.
Result<Viewshed> viewshedSightlines(const ViewshedGrid& grid, const ViewshedOptions& options, unsigned threads = 0);

struct ViewshedAgreement {
    size_t compared = 0;   ///< cells in range with data in both
    size_t differ = 0;
    size_t seenOnlyByA = 0, seenOnlyByB = 0;
    double percent() const { return compared ? 100.0 * double(compared - differ) / double(compared) : 100.0; }
};

/// Cell-by-cell agreement of two viewsheds of the same grid (cells out of range or without data
/// in either are not compared).
ViewshedAgreement compareViewsheds(const Viewshed& a, const Viewshed& b);

/// A coarse viewshed (of coarsenViewshedGrid(grid, factor)) spread back onto the fine grid:
/// each fine cell takes the coarse cell it falls in.
Viewshed refineViewshed(const Viewshed& coarse, int factor, int fineSide);

}  // namespace orbis::globe
