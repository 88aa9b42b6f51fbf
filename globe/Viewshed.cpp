#include "globe/Viewshed.h"

#include "globe/Ellipsoid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

namespace orbis::globe {
namespace {

/// The tangent plane at a grid's centre.
struct Plane {
    glm::dvec3 origin, east, north;
    explicit Plane(LonLat centre) {
        const auto& e = Ellipsoid::wgs84();
        origin = e.toEcef(centre.x, centre.y, 0.0);
        const glm::dmat3 enu = e.enuFrame(centre.x, centre.y);
        east = enu[0];
        north = enu[1];
    }
    LonLat at(double eastM, double northM) const {
        const Geodetic g = Ellipsoid::wgs84().toGeodetic(origin + east * eastM + north * northM);
        return {g.lonDeg, g.latDeg};
    }
};

/// Runs `rows(first, last)` on `threads` threads over [0, count).
template <typename F>
void inParallel(int count, unsigned threads, F&& rows) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = std::min<unsigned>(threads, unsigned(std::max(1, count / 16)));
    if (threads <= 1) {
        rows(0, count);
        return;
    }
    std::vector<std::thread> pool;
    const int per = (count + int(threads) - 1) / int(threads);
    for (unsigned t = 0; t < threads; ++t) {
        const int a = int(t) * per, b = std::min(count, a + per);
        if (a < b) pool.emplace_back([&rows, a, b] { rows(a, b); });
    }
    for (auto& t : pool) t.join();
}

/// Heights relative to the eye, lowered by the Earth's curve (and refraction), in double.
struct Relative {
    const ViewshedGrid& grid;
    const ViewshedOptions& options;
    double eye = 0.0, dropPerM2 = 0.0, radius2 = 0.0;
    int side = 0;

    double at(int col, int row) const {
        const double h = grid.at(col, row);
        const double dx = (col - options.observerCol) * grid.cellM, dy = (row - options.observerRow) * grid.cellM;
        return h - eye - dropPerM2 * (dx * dx + dy * dy);
    }
    bool inRange(int col, int row) const {
        if (radius2 <= 0.0) return true;
        const double dx = (col - options.observerCol) * grid.cellM, dy = (row - options.observerRow) * grid.cellM;
        return dx * dx + dy * dy <= radius2;
    }
};

Result<Relative> relative(const ViewshedGrid& grid, const ViewshedOptions& options) {
    auto eye = viewshedEyeHeight(grid, options);
    if (!eye) return eye.error();
    if (!std::isfinite(options.targetHeight) || std::abs(options.targetHeight) > 1e5)
        return makeError("the target height " + std::to_string(options.targetHeight) + " m is not a usable height");
    if (!std::isfinite(options.curvature) || options.curvature < 0.0 || options.curvature > 2.0)
        return makeError("the curvature coefficient " + std::to_string(options.curvature) + " is outside 0 .. 2");
    if (!std::isfinite(options.radiusM) || options.radiusM < 0.0)
        return makeError("the viewshed radius " + std::to_string(options.radiusM) + " m is not a distance");
    Relative r{grid, options};
    r.eye = *eye;
    r.dropPerM2 = options.curvature / kViewshedEarthDiameter;
    r.radius2 = options.radiusM * options.radiusM;
    r.side = grid.side();
    return r;
}

}  // namespace

ViewshedPlane::ViewshedPlane(const ViewshedGrid& grid) : cellM_(grid.cellM), radiusCells_(grid.radiusCells) {
    const Plane p(grid.centre);
    origin_ = p.origin;
    east_ = p.east;
    north_ = p.north;
    up_ = Ellipsoid::wgs84().surfaceNormal(grid.centre.x, grid.centre.y);
}

GeoExtentLonLat ViewshedPlane::bounds(const ViewshedGrid& grid) const {
    // The box: the border's cells, longitudes unwrapped from the centre's.
    const double half = (grid.radiusCells + 0.5) * grid.cellM;
    GeoExtentLonLat b{grid.centre.x, grid.centre.y, grid.centre.x, grid.centre.y};
    const int steps = 64;
    for (int i = 0; i <= steps; ++i) {
        const double t = -half + 2.0 * half * i / steps;
        for (const auto& [e, n] : {std::pair{t, -half}, std::pair{t, half}, std::pair{-half, t}, std::pair{half, t}}) {
            const LonLat q = at(e, n);
            double lon = q.x;
            while (lon - grid.centre.x > 180.0) lon -= 360.0;
            while (lon - grid.centre.x < -180.0) lon += 360.0;
            b.west = std::min(b.west, lon), b.east = std::max(b.east, lon);
            b.south = std::min(b.south, q.y), b.north = std::max(b.north, q.y);
        }
    }
    // A margin of a cell, and the whole turn when a pole is in the grid.
    const double margin = grid.cellM / 111000.0;
    b.south = std::max(-90.0, b.south - margin), b.north = std::min(90.0, b.north + margin);
    for (double pole : {90.0, -90.0})
        if (cellOf(0.0, pole)) {
            b.west = grid.centre.x - 180.0, b.east = grid.centre.x + 180.0;
            (pole > 0 ? b.north : b.south) = pole;
        }
    const double lonMargin = margin / std::max(0.01, std::cos(grid.centre.y * M_PI / 180.0));
    if (b.east - b.west < 360.0) b.west -= lonMargin, b.east += lonMargin;
    return b;
}

LonLat ViewshedPlane::at(double eastM, double northM) const {
    const Geodetic g = Ellipsoid::wgs84().toGeodetic(origin_ + east_ * eastM + north_ * northM);
    return {g.lonDeg, g.latDeg};
}

std::optional<std::pair<int, int>> ViewshedPlane::cellOf(double lonDeg, double latDeg) const {
    const glm::dvec3 d = Ellipsoid::wgs84().toEcef(lonDeg, latDeg, 0.0) - origin_;
    if (glm::dot(d, up_) < -0.5 * Ellipsoid::wgs84().equatorialRadius()) return std::nullopt;   // the far side of the Earth
    const double c = std::round(glm::dot(d, east_) / cellM_), r = std::round(glm::dot(d, north_) / cellM_);
    if (std::abs(c) > radiusCells_ || std::abs(r) > radiusCells_) return std::nullopt;
    return std::pair{radiusCells_ + int(c), radiusCells_ - int(r)};
}

LonLat ViewshedGrid::lonLatOf(int col, int row) const { return Plane(centre).at(east(col), north(row)); }

std::optional<std::pair<int, int>> ViewshedGrid::cellOf(double lonDeg, double latDeg) const { return ViewshedPlane(*this).cellOf(lonDeg, latDeg); }

Result<ViewshedGrid> sampleViewshedGrid(const HeightAt& ground, LonLat centre, double radiusM, double cellM, size_t maxCells) {
    if (!std::isfinite(centre.x) || !std::isfinite(centre.y) || std::abs(centre.y) > 90.0)
        return makeError("the viewshed centre (" + std::to_string(centre.x) + ", " + std::to_string(centre.y) + ") is not a place on the Earth");
    if (!std::isfinite(cellM) || cellM < 0.01 || cellM > 100000.0)
        return makeError("the viewshed cell size " + std::to_string(cellM) + " m is outside 0.01 .. 100000 m");
    if (!std::isfinite(radiusM) || radiusM < cellM || radiusM > 2000000.0)
        return makeError("the viewshed radius " + std::to_string(radiusM) + " m is outside one cell (" + std::to_string(cellM) +
                         " m) .. 2000 km");
    const double cells = std::ceil(radiusM / cellM - 1e-9);
    const double sideD = 2.0 * cells + 1.0;
    if (sideD * sideD > double(maxCells))
        return makeError("a viewshed " + std::to_string(radiusM) + " m around at " + std::to_string(cellM) + " m cells needs " +
                         std::to_string(size_t(sideD * sideD)) + " cells, more than " + std::to_string(maxCells) +
                         ": use larger cells or a smaller radius");
    ViewshedGrid grid;
    grid.centre = {wrapLongitude(centre.x), centre.y};
    grid.cellM = cellM;
    grid.radiusCells = int(cells);
    const int side = grid.side();
    grid.heights.assign(size_t(side) * size_t(side), std::numeric_limits<float>::quiet_NaN());
    const Plane plane(grid.centre);
    inParallel(side, 0, [&](int first, int last) {
        for (int row = first; row < last; ++row)
            for (int col = 0; col < side; ++col) {
                const LonLat p = plane.at(grid.east(col), grid.north(row));
                if (auto h = ground(p.x, p.y)) grid.heights[size_t(row) * size_t(side) + size_t(col)] = float(*h);
            }
    });
    return grid;
}

ViewshedGrid coarsenViewshedGrid(const ViewshedGrid& grid, int factor) {
    if (factor <= 1) return grid;
    ViewshedGrid out;
    out.centre = grid.centre;
    out.cellM = grid.cellM * factor;
    out.radiusCells = grid.radiusCells / factor;
    const int side = out.side(), fineSide = grid.side();
    out.heights.resize(size_t(side) * size_t(side));
    for (int row = 0; row < side; ++row)
        for (int col = 0; col < side; ++col) {
            const int fc = grid.radiusCells + (col - out.radiusCells) * factor, fr = grid.radiusCells + (row - out.radiusCells) * factor;
            out.heights[size_t(row) * size_t(side) + size_t(col)] =
                fc >= 0 && fr >= 0 && fc < fineSide && fr < fineSide ? grid.at(fc, fr) : std::numeric_limits<float>::quiet_NaN();
        }
    return out;
}

size_t Viewshed::count(Sight s) const { return size_t(std::count(cells.begin(), cells.end(), s)); }

Result<double> viewshedEyeHeight(const ViewshedGrid& grid, const ViewshedOptions& options) {
    const int side = grid.side();
    if (grid.heights.size() != size_t(side) * size_t(side) || side < 3) return makeError("the viewshed grid is empty or inconsistent");
    if (options.observerCol < 0 || options.observerRow < 0 || options.observerCol >= side || options.observerRow >= side)
        return makeError("the observer (cell " + std::to_string(options.observerCol) + ", " + std::to_string(options.observerRow) +
                         ") is outside the viewshed grid of " + std::to_string(side) + " cells a side");
    if (!std::isfinite(options.observerHeight) || std::abs(options.observerHeight) > 1e6)
        return makeError("the observer height " + std::to_string(options.observerHeight) + " m is not a usable height");
    const float ground = grid.at(options.observerCol, options.observerRow);
    if (!std::isfinite(ground)) return makeError("the DEM has no data under the observer");
    return double(ground) + options.observerHeight;
}

Result<Viewshed> viewshedRings(const ViewshedGrid& grid, const ViewshedOptions& options) {
    auto rel = relative(grid, options);
    if (!rel) return rel.error();
    const Relative& r = *rel;
    const int side = r.side, ox = options.observerCol, oy = options.observerRow;
    Viewshed out;
    out.side = side;
    out.cells.assign(size_t(side) * size_t(side), Sight::OutOfRange);
    std::vector<double> horizon(size_t(side) * size_t(side), 0.0);
    auto idx = [side](int col, int row) { return size_t(row) * size_t(side) + size_t(col); };
    auto Z = [&](int dx, int dy) { return horizon[idx(ox + dx, oy + dy)]; };

    out.cells[idx(ox, oy)] = Sight::Visible;
    horizon[idx(ox, oy)] = -options.observerHeight;
    const int rings = std::max({ox, oy, side - 1 - ox, side - 1 - oy});
    for (int d = 1; d <= rings; ++d) {
        for (int k = 0; k < 8 * d; ++k) {
            const int t = k % (2 * d), s = k / (2 * d);
            const int dx = s == 0 ? -d + t : s == 1 ? d : s == 2 ? d - t : -d;
            const int dy = s == 0 ? -d : s == 1 ? -d + t : s == 2 ? d : d - t;
            const int col = ox + dx, row = oy + dy;
            if (col < 0 || row < 0 || col >= side || row >= side) continue;
            const size_t at = idx(col, row);
            const double h = r.at(col, row);
            if (!r.inRange(col, row)) {
                horizon[at] = std::isfinite(h) ? h : 0.0;
                continue;
            }
            const int i = std::abs(dx), j = std::abs(dy), sx = dx > 0 ? 1 : dx < 0 ? -1 : 0, sy = dy > 0 ? 1 : dy < 0 ? -1 : 0;
            double z;
            bool own = false;
            if (i <= 1 && j <= 1) own = true, z = h;
            else if (i == j) z = Z(dx - sx, dy - sy) * i / (i - 1);
            else if (j == 0) z = Z(dx - sx, 0) * i / (i - 1);
            else if (i == 0) z = Z(0, dy - sy) * j / (j - 1);
            else if (i > j) z = (Z(dx - sx, dy - sy) * j + Z(dx - sx, dy) * (i - j)) / (i - 1);
            else z = (Z(dx - sx, dy - sy) * i + Z(dx, dy - sy) * (j - i)) / (j - 1);
            if (!std::isfinite(h)) {
                out.cells[at] = Sight::NoData;
                horizon[at] = own ? -options.observerHeight : z;
                continue;
            }
            out.cells[at] = own || h + options.targetHeight >= z ? Sight::Visible : Sight::Hidden;
            horizon[at] = std::max(h, z);
        }
    }
    return out;
}

Result<Viewshed> viewshedSightlines(const ViewshedGrid& grid, const ViewshedOptions& options, unsigned threads) {
    auto rel = relative(grid, options);
    if (!rel) return rel.error();
    const Relative& r = *rel;
    const int side = r.side, ox = options.observerCol, oy = options.observerRow;
    // The relative heights once (NaN stays NaN).
    std::vector<double> h(size_t(side) * size_t(side));
    for (int row = 0; row < side; ++row)
        for (int col = 0; col < side; ++col) h[size_t(row) * size_t(side) + size_t(col)] = r.at(col, row);
    auto H = [&](int col, int row) { return h[size_t(row) * size_t(side) + size_t(col)]; };

    Viewshed out;
    out.side = side;
    out.cells.assign(size_t(side) * size_t(side), Sight::OutOfRange);
    inParallel(side, threads, [&](int first, int last) {
        for (int row = first; row < last; ++row)
            for (int col = 0; col < side; ++col) {
                Sight& cell = out.cells[size_t(row) * size_t(side) + size_t(col)];
                if (!r.inRange(col, row)) continue;
                const double target = H(col, row);
                if (!std::isfinite(target)) {
                    cell = Sight::NoData;
                    continue;
                }
                const double top = target + options.targetHeight;
                const int dx = col - ox, dy = row - oy, i = std::abs(dx), j = std::abs(dy);
                bool seen = true;
                // Where the sight line crosses each column line between the two ends...
                for (int k = 1; k < i && seen; ++k) {
                    const double t = double(k) / i, y = oy + t * dy;
                    const int y0 = int(std::floor(y)), y1 = std::min(y0 + 1, side - 1);
                    const double f = y - y0, g = (1.0 - f) * H(ox + k * (dx > 0 ? 1 : -1), y0) + f * H(ox + k * (dx > 0 ? 1 : -1), y1);
                    if (std::isfinite(g) && g > t * top) seen = false;
                }
                // ... and each row line.
                for (int k = 1; k < j && seen; ++k) {
                    const double t = double(k) / j, x = ox + t * dx;
                    const int x0 = int(std::floor(x)), x1 = std::min(x0 + 1, side - 1);
                    const double f = x - x0, g = (1.0 - f) * H(x0, oy + k * (dy > 0 ? 1 : -1)) + f * H(x1, oy + k * (dy > 0 ? 1 : -1));
                    if (std::isfinite(g) && g > t * top) seen = false;
                }
                cell = seen ? Sight::Visible : Sight::Hidden;
            }
    });
    return out;
}

ViewshedAgreement compareViewsheds(const Viewshed& a, const Viewshed& b) {
    ViewshedAgreement out;
    const size_t n = std::min(a.cells.size(), b.cells.size());
    for (size_t i = 0; i < n; ++i) {
        const Sight x = a.cells[i], y = b.cells[i];
        const bool xs = x == Sight::Visible || x == Sight::Hidden, ys = y == Sight::Visible || y == Sight::Hidden;
        if (!xs || !ys) continue;
        ++out.compared;
        if (x != y) {
            ++out.differ;
            (x == Sight::Visible ? out.seenOnlyByA : out.seenOnlyByB)++;
        }
    }
    return out;
}

Viewshed refineViewshed(const Viewshed& coarse, int factor, int fineSide) {
    Viewshed out;
    out.side = fineSide;
    out.cells.assign(size_t(fineSide) * size_t(fineSide), Sight::OutOfRange);
    const int fr = fineSide / 2, cr = coarse.side / 2;
    for (int row = 0; row < fineSide; ++row)
        for (int col = 0; col < fineSide; ++col) {
            const int cc = cr + int(std::lround(double(col - fr) / factor)), rr = cr + int(std::lround(double(row - fr) / factor));
            if (cc >= 0 && rr >= 0 && cc < coarse.side && rr < coarse.side) out.cells[size_t(row) * size_t(fineSide) + size_t(col)] = coarse.at(cc, rr);
        }
    return out;
}

}  // namespace orbis::globe
