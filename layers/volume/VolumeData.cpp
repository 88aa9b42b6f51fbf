#include "layers/volume/VolumeData.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

namespace orbis::layers {

// ---------------------------------------------------------------------------------------------
// Axes

namespace {

/// Texture coordinate of a coordinate on an ascending axis (piecewise linear between samples).
double texcoordOf(const std::vector<double>& c, double x) {
    const size_t n = c.size();
    if (n == 0) return 0.5;
    if (n == 1 || x <= c.front()) return 0.5 / double(n);
    if (x >= c.back()) return (double(n) - 0.5) / double(n);
    const size_t hi = size_t(std::upper_bound(c.begin(), c.end(), x) - c.begin());
    const size_t lo = hi - 1;
    const double f = (x - c[lo]) / (c[hi] - c[lo]);
    return (double(lo) + f + 0.5) / double(n);
}

}  // namespace

AxisLookup AxisLookup::build(const std::vector<double>& c, size_t tableSize) {
    AxisLookup a;
    a.samples = c.size();
    if (c.empty()) return a;
    a.first = c.front();
    a.last = c.back();
    if (c.size() < 3) return a;
    const double step = (a.last - a.first) / double(c.size() - 1);
    for (size_t i = 1; i < c.size() && a.uniform; ++i)
        a.uniform = std::abs((c[i] - c[i - 1]) - step) <= 1e-6 * std::abs(step);
    if (a.uniform) return a;
    tableSize = std::max<size_t>(tableSize, 2);
    a.table.resize(tableSize);
    for (size_t t = 0; t < tableSize; ++t) {
        const double x = a.first + (a.last - a.first) * double(t) / double(tableSize - 1);
        a.table[t] = float(texcoordOf(c, x));
    }
    return a;
}

double AxisLookup::exact(const std::vector<double>& c, double x) const { return texcoordOf(c, x); }

double AxisLookup::lookup(double x) const {
    if (samples == 0) return 0.5;
    const double n = double(samples);
    if (samples == 1 || last == first) return 0.5 / n;
    const double f = std::clamp((x - first) / (last - first), 0.0, 1.0);
    if (uniform || table.empty()) return (f * (n - 1.0) + 0.5) / n;
    // A 1-D texture with linear filtering: texel centres at (t + 0.5) / size.
    const double s = f * double(table.size() - 1);
    const size_t t0 = std::min(size_t(s), table.size() - 2);
    const double w = s - double(t0);
    return double(table[t0]) * (1.0 - w) + double(table[t0 + 1]) * w;
}

// ---------------------------------------------------------------------------------------------
// Bricks

size_t BrickGrid::emptyBricks() const {
    return size_t(std::count_if(minMax.begin(), minMax.end(), [](const auto& m) { return m.first > m.second; }));
}

BrickGrid buildBrickGrid(const VolumeField& field, int brickSize) {
    return buildBrickGrid(field.values.data(), field.nx(), field.ny(), field.nz(), brickSize);
}

BrickGrid buildBrickGrid(const float* values, size_t nx, size_t ny, size_t nz, int brickSize) {
    BrickGrid g;
    g.size = std::max(brickSize, 1);
    const size_t s = size_t(g.size);
    g.bx = (nx + s - 1) / s;
    g.by = (ny + s - 1) / s;
    g.bz = (nz + s - 1) / s;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    g.minMax.assign(g.bx * g.by * g.bz, {kInf, -kInf});
    for (size_t bk = 0; bk < g.bz; ++bk)
        for (size_t bj = 0; bj < g.by; ++bj)
            for (size_t bi = 0; bi < g.bx; ++bi) {
                auto& mm = g.minMax[(bk * g.by + bj) * g.bx + bi];
                // One voxel past the brick: trilinear samples near its far faces read it.
                for (size_t k = bk * s; k < std::min(nz, (bk + 1) * s + 1); ++k)
                    for (size_t j = bj * s; j < std::min(ny, (bj + 1) * s + 1); ++j)
                        for (size_t i = bi * s; i < std::min(nx, (bi + 1) * s + 1); ++i) {
                            const float v = values[(k * ny + j) * nx + i];
                            if (!std::isfinite(v)) continue;
                            mm.first = std::min(mm.first, v);
                            mm.second = std::max(mm.second, v);
                        }
            }
    return g;
}

void mergeBrickGrid(BrickGrid& into, const BrickGrid& other) {
    if (into.minMax.size() != other.minMax.size()) return;
    for (size_t b = 0; b < into.minMax.size(); ++b) {
        into.minMax[b].first = std::min(into.minMax[b].first, other.minMax[b].first);
        into.minMax[b].second = std::max(into.minMax[b].second, other.minMax[b].second);
    }
}

std::vector<uint32_t> brickOccupancy(const BrickGrid& grid, const std::vector<std::array<float, 4>>& table,
                                     double rangeMin, double rangeMax, bool dvr, const std::vector<double>& isovalues) {
    std::vector<uint32_t> bits((grid.minMax.size() + 31) / 32, 0u);
    const size_t n = table.size();
    const double scale = rangeMax > rangeMin ? 1.0 / (rangeMax - rangeMin) : 0.0;
    // The largest opacity of the table between two positions (linear interpolation between
    // entries: the largest lies at an entry or an end).
    const auto entry = [&](double v) { return std::clamp((v - rangeMin) * scale, 0.0, 1.0) * double(n - 1); };
    for (size_t b = 0; b < grid.minMax.size(); ++b) {
        const auto [lo, hi] = grid.minMax[b];
        if (!(lo <= hi)) continue;   // no valid values
        bool visible = false;
        for (double c : isovalues) visible = visible || (c >= double(lo) && c <= double(hi));
        if (dvr && !visible && n > 0) {
            const size_t first = size_t(std::floor(entry(lo))), last = std::min(n - 1, size_t(std::ceil(entry(hi))));
            for (size_t e = first; e <= last && !visible; ++e) visible = table[e][3] > 0.0f;
        }
        if (visible) bits[b / 32] |= 1u << (b % 32);
    }
    return bits;
}

// ---------------------------------------------------------------------------------------------
// Colour maps: sRGB anchors at even spacing (approximations of the published maps, enough
// anchors that linear-light interpolation stays within a few levels of them).

namespace {

struct ColorMap {
    const char* name;
    std::vector<std::array<uint8_t, 3>> anchors;
};

const std::vector<ColorMap>& colorMaps() {
    static const std::vector<ColorMap> maps = {
        {"viridis", {{68, 1, 84}, {72, 40, 120}, {62, 73, 137}, {49, 104, 142}, {38, 130, 142}, {31, 158, 137},
                     {53, 183, 121}, {109, 205, 89}, {180, 222, 44}, {253, 231, 37}}},
        {"magma", {{0, 0, 4}, {28, 16, 68}, {79, 18, 123}, {129, 37, 129}, {181, 54, 122}, {229, 80, 100},
                   {251, 135, 97}, {254, 194, 135}, {252, 253, 191}}},
        {"inferno", {{0, 0, 4}, {31, 12, 72}, {85, 15, 109}, {136, 34, 106}, {186, 54, 85}, {227, 89, 51},
                     {249, 140, 10}, {249, 201, 50}, {252, 255, 164}}},
        {"plasma", {{13, 8, 135}, {84, 2, 163}, {139, 10, 165}, {185, 50, 137}, {219, 92, 104}, {244, 136, 73},
                    {254, 188, 43}, {240, 249, 33}}},
        {"cividis", {{0, 34, 78}, {35, 62, 108}, {82, 89, 110}, {124, 123, 120}, {166, 157, 117}, {212, 194, 98},
                     {254, 232, 56}}},
        {"coolwarm", {{59, 76, 192}, {98, 130, 234}, {141, 176, 254}, {184, 208, 249}, {221, 221, 221},
                      {245, 196, 173}, {244, 154, 123}, {222, 96, 77}, {180, 4, 38}}},
        {"greys", {{0, 0, 0}, {255, 255, 255}}},
        {"turbo", {{48, 18, 59}, {70, 107, 227}, {41, 187, 236}, {49, 241, 152}, {164, 252, 60}, {237, 208, 58},
                   {251, 128, 34}, {209, 49, 5}, {122, 4, 3}}},
    };
    return maps;
}

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

}  // namespace

bool hasColorMap(const std::string& name) {
    const auto& maps = colorMaps();
    return std::any_of(maps.begin(), maps.end(), [&](const ColorMap& m) { return name == m.name; });
}

std::vector<std::string> colorMapNames() {
    std::vector<std::string> names;
    for (const auto& m : colorMaps()) names.emplace_back(m.name);
    return names;
}

Result<std::vector<std::array<float, 4>>> buildTransferTable(const TransferFunctionDesc& desc, size_t size) {
    const auto& maps = colorMaps();
    const auto map = std::find_if(maps.begin(), maps.end(), [&](const ColorMap& m) { return desc.colorMap == m.name; });
    if (map == maps.end()) {
        std::string names;
        for (const auto& m : maps) names += (names.empty() ? "" : ", ") + std::string(m.name);
        return makeError("unknown colour map \"" + desc.colorMap + "\" (known: " + names + ")");
    }
    if (!(desc.rangeMax > desc.rangeMin) || !std::isfinite(desc.rangeMin) || !std::isfinite(desc.rangeMax))
        return makeError("the data range must be [low, high] with low < high (got [" + std::to_string(desc.rangeMin) +
                         ", " + std::to_string(desc.rangeMax) + "])");
    std::vector<OpacityPoint> points = desc.opacity;
    if (points.empty()) points = {{desc.rangeMin, 0.0}, {desc.rangeMax, 1.0}};
    std::stable_sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.value < b.value; });
    for (const auto& p : points)
        if (!std::isfinite(p.value) || !(p.alpha >= 0.0 && p.alpha <= 1.0))
            return makeError("opacity points need a finite value and an alpha in 0..1");

    size = std::max<size_t>(size, 2);
    std::vector<std::array<float, 4>> table(size);
    const auto& anchors = map->anchors;
    for (size_t t = 0; t < size; ++t) {
        const double f = double(t) / double(size - 1);
        const double value = desc.rangeMin + f * (desc.rangeMax - desc.rangeMin);
        const double a = f * double(anchors.size() - 1);
        const size_t a0 = std::min(size_t(a), anchors.size() - 2);
        const double w = a - double(a0);
        for (int c = 0; c < 3; ++c) {
            const double lo = srgbToLinear(anchors[a0][size_t(c)] / 255.0), hi = srgbToLinear(anchors[a0 + 1][size_t(c)] / 255.0);
            table[t][size_t(c)] = float(lo + (hi - lo) * w);
        }
        double alpha;
        if (value <= points.front().value) alpha = points.front().alpha;
        else if (value >= points.back().value) alpha = points.back().alpha;
        else {
            size_t i = 1;
            while (points[i].value < value) ++i;
            const auto& p0 = points[i - 1];
            const auto& p1 = points[i];
            alpha = p1.value > p0.value ? p0.alpha + (p1.alpha - p0.alpha) * (value - p0.value) / (p1.value - p0.value)
                                        : p1.alpha;
        }
        table[t][3] = float(std::clamp(alpha * desc.opacityScale, 0.0, 1.0));
    }
    return table;
}

std::vector<std::array<float, 4>> buildPreIntegratedTable(const std::vector<std::array<float, 4>>& table, double step,
                                                          double opacityPerUnit) {
    const size_t n = table.size();
    std::vector<std::array<float, 4>> out(n * n);
    if (n == 0) return out;
    // log2(1 - alpha) per entry (what the plain table holds) and its running integral over
    // the table's index, exact for the linear interpolation between entries.
    std::vector<double> logT(n), integral(n, 0.0);
    for (size_t t = 0; t < n; ++t) logT[t] = std::log2(1.0 - std::min(double(table[t][3]), 0.9999));
    for (size_t t = 1; t < n; ++t) integral[t] = integral[t - 1] + 0.5 * (logT[t - 1] + logT[t]);
    const auto lerp = [&](double x, size_t c) {
        const size_t i0 = std::min(size_t(x), n - 1), i1 = std::min(i0 + 1, n - 1);
        const double w = x - double(i0);
        return c == 3 ? logT[i0] + (logT[i1] - logT[i0]) * w : double(table[i0][c]) + double(table[i1][c] - table[i0][c]) * w;
    };
    // Rows are independent: they are shared out over the cores (the table is rebuilt when the
    // transfer function, the step or the opacity unit change: ~160 ms of one core at 256^2).
    const auto rows = [&](size_t first, size_t stride) {
        for (size_t j = first; j < n; j += stride)
            for (size_t i = 0; i < n; ++i) {
                std::array<float, 4>& e = out[j * n + i];
                const size_t span = i > j ? i - j : j - i;
                if (span == 0) {
                    e = {table[i][0], table[i][1], table[i][2], float(logT[i])};
                    continue;
                }
                const double meanLog = (integral[j] - integral[i]) / (double(j) - double(i));
                // Front to back in sub-steps at their midpoints: the colour weighted by what each
                // sub-step lets through of the ones before it.
                const size_t subs = std::min<size_t>(std::max<size_t>(4, 2 * span), 128);
                const double h = step * opacityPerUnit / double(subs);
                double transmit = 1.0, rgb[3] = {0.0, 0.0, 0.0}, mean[3] = {0.0, 0.0, 0.0};
                for (size_t k = 0; k < subs; ++k) {
                    const double x = double(i) + (double(j) - double(i)) * (double(k) + 0.5) / double(subs);
                    const double alpha = 1.0 - std::exp2(lerp(x, 3) * h);
                    for (size_t c = 0; c < 3; ++c) {
                        const double colour = lerp(x, c);
                        rgb[c] += transmit * alpha * colour;
                        mean[c] += colour / double(subs);
                    }
                    transmit *= 1.0 - alpha;
                }
                const double opacity = 1.0 - transmit;
                for (size_t c = 0; c < 3; ++c) e[c] = float(opacity > 1e-7 ? rgb[c] / opacity : mean[c]);
                e[3] = float(meanLog);
            }
    };
    const size_t threads = std::clamp<size_t>(std::thread::hardware_concurrency(), 1, 8);
    std::vector<std::thread> helpers;
    for (size_t t = 1; t < threads && n >= 64; ++t) helpers.emplace_back(rows, t, threads);
    rows(0, helpers.size() + 1);
    for (auto& h : helpers) h.join();
    return out;
}

double correctOpacity(double alpha, double step, double reference) {
    if (alpha >= 1.0) return 1.0;
    if (alpha <= 0.0 || reference <= 0.0) return alpha <= 0.0 ? 0.0 : alpha;
    return 1.0 - std::pow(1.0 - alpha, step / reference);
}

}  // namespace orbis::layers
