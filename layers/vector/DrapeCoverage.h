#pragma once
// The pixel side of draping (DrapeRaster.h): the coverage buffers one feature is drawn into,
// and the "over" composite of a buffer into the tile. Pixel space has x east and y south; pixel
// (i, j) covers [i, i + 1] x [j, j + 1], so its centre is (i + 0.5, j + 0.5). No Vulkan; one
// set per tile, used by one thread.
//
// The colours are sRGB in 0..1 and the tile is straight-alpha sRGB RGBA8, composited in sRGB
// (as the imagery it is drawn over was): no linearisation.

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace orbis::vector::drape {

/// "Over" in straight alpha: `rgb` (0..255) with alpha `a` (0..1) over the pixel at `dst`.
void compositeOver(uint8_t* dst, const glm::vec3& rgb, float a);

/// Exact area coverage of closed rings, as font rasterisers compute it (font-rs, stb_truetype
/// v2): each edge adds its signed covered area to the cells it crosses, and a prefix sum along
/// each row turns those into the winding, coverage = min(|winding|, 1). A ring that runs the
/// other way adds the opposite sign, so holes subtract when their edges are given with the
/// opposite sign to their outer ring's; overlapping polygons of the same sign union.
class AreaCoverage {
public:
    explicit AreaCoverage(int size);

    /// Adds the edge a -> b (pixel space, any values) times `sign` (+1 or -1). The part above
    /// or below the tile adds nothing; the part left of it adds the same as a vertical edge on
    /// its west side (it covers every pixel to its east); the part right of it adds nothing
    /// (it only covers pixels past the tile). So an edge costs the cells it crosses and no more.
    void addEdge(glm::dvec2 a, glm::dvec2 b, float sign);
    /// Composites `rgb` (0..1) at alpha `alpha` * coverage into `rgba` (size * size * 4), then
    /// clears the accumulation for the next feature. True when any pixel was composited.
    bool compositeInto(std::vector<uint8_t>& rgba, const glm::dvec3& rgb, double alpha);
    size_t edges() const { return edges_; }

private:
    /// The font-rs cell walk of one edge inside the tile (0 <= y0 < y1 <= size, x in [0, size]).
    void accumulate(glm::dvec2 p0, glm::dvec2 p1, float sign);

    int size_ = 0, stride_ = 0;   ///< the row stride leaves room for x == size's two cells
    std::vector<float> acc_;
    int rowMin_ = 0, rowMax_ = -1, colMin_ = 0;
    size_t edges_ = 0;
};

/// Antialiased strokes (round joins and caps: the distance to each segment, with a 1 px ramp)
/// combined with max, so that joints and self-overlaps of one feature are not darker. The
/// whole feature is then composited once.
class StrokeCoverage {
public:
    explicit StrokeCoverage(int size);

    /// Adds the capsule around a -> b: coverage = scale * clamp(radius - distance, 0, 1), at
    /// pixel centres. A line of width w >= 1 has radius w / 2 + 0.5 (its coverage across
    /// sums to w); a thinner one radius 1 and scale w. Touches only pixels near the segment
    /// (clipped to the tile first).
    void addSegment(glm::dvec2 a, glm::dvec2 b, double radius, float scale);
    /// The stretch [t0, t1] of a -> b (a + (b - a) t) that a capsule of `radius` around it
    /// could paint a pixel centre from: the segment clipped to the tile grown by the radius
    /// (Liang-Barsky). False when none.
    bool reach(glm::dvec2 a, glm::dvec2 b, double radius, double& t0, double& t1) const;
    /// Ground length of a pixel's width over its height (the cosine of the tile's latitude:
    /// a degree of longitude is shorter than one of latitude). Distances are measured on the
    /// ground, so that a stroke is as wide running north as running east.
    void setXScale(double k) { xScale_ = k; }
    bool compositeInto(std::vector<uint8_t>& rgba, const glm::dvec3& rgb, double alpha);
    size_t segments() const { return segments_; }

private:
    int size_ = 0;
    double xScale_ = 1.0;
    std::vector<float> coverage_;
    int x0_ = 0, y0_ = 0, x1_ = -1, y1_ = -1;   ///< the touched rectangle, inclusive
    size_t segments_ = 0;
};

/// A point marker: a disk of `radius` px (on the ground: pixels are `xScale` as wide as high) in
/// `rgb` with a dark outline ring of `outlinePx`
/// inside its edge, antialiased (area about pi * radius^2), composited at `alpha`. True when
/// any pixel was composited.
bool paintMarker(std::vector<uint8_t>& rgba, int size, glm::dvec2 centre, double radius, double outlinePx,
                 const glm::dvec3& rgb, double alpha, double xScale = 1.0);

/// An icon (straight-alpha sRGB RGBA8, `iconWidth` x `iconHeight`, top row first) centred at
/// `centre` (pixel space), `heightPx` high and as wide as its aspect makes it on the ground
/// (divided by `xScale` across), its alpha times `alpha`, composited "over". Each pixel takes
/// the mean of n x n samples of the icon (bilinear; n up to 8 as the icon shrinks), so a
/// large icon drawn small does not alias and its edge is antialiased. True when a pixel changed.
bool paintIcon(std::vector<uint8_t>& rgba, int size, glm::dvec2 centre, double heightPx, const uint8_t* icon, int iconWidth,
               int iconHeight, double alpha, double xScale);

}  // namespace orbis::vector::drape
