#pragma once
// Which terrain tiles to draw this frame: a screen-space-error walk of the geodetic quadtree
// (two roots, TileKey) with frustum and horizon culling and hysteresis. Pure CPU maths: no
// Vulkan, no GDAL, no engine/scene (the caller builds a SelectorView from its camera).
//
// The selection is a set of disjoint tiles that covers every part of the globe that may be
// visible (culling is conservative), listed in depth-first order (roots west then east,
// children NW, NE, SW, SE), so identical inputs give an identical list.

#include "globe/Culling.h"
#include "globe/Ellipsoid.h"
#include "globe/TileKey.h"
#include "globe/Viewpoint.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace orbis::globe {

/// Terrain heights (above the ellipsoid, metres) that a tile may contain. The selector trusts
/// it completely, so an unknown tile must get a conservative range (its parent's, or the
/// defaults below: lowest land about -430 m, highest 8849 m, with margin).
struct TileHeightRange {
    double minHeight = -500.0;
    double maxHeight = 9000.0;
};

struct SelectorSettings {
    /// Refine while a tile's projected geometric error exceeds this many pixels.
    double maxScreenSpaceError = 2.0;
    uint32_t maxLevel = 22;
    /// Always refine at least to this level (culled tiles are still dropped).
    uint32_t minLevel = 0;
    /// Samples per tile edge of the terrain mesh; sets the geometric error of a tile.
    int gridSize = 65;
    /// Finest level at which the sources have detail (their finest data level): a tile there
    /// already draws every data sample, and deeper tiles only show the same data, upsampled.
    /// From this level on a tile's error is what its grid misses of the ellipsoid's curvature
    /// (millimetres at level 12), so refinement stops at the data's resolution instead of
    /// spending tiles that add nothing. The default keeps refining on the grid's error alone.
    uint32_t detailLevel = 30;
    /// A tile refined last frame stays refined until its error drops below
    /// maxScreenSpaceError * (1 - hysteresis), as long as its heights are known as well as
    /// then (a tile refined on the padded heights of a coarse ancestor is judged again once its
    /// own arrive: the selection of a still view does not depend on the order data came in).
    double hysteresis = 0.15;
    /// Safety net on the number of selected tiles. Only pathological views reach it (a camera
    /// a few metres above a pole, where every pole tile touches the camera): refinement then
    /// goes to the tiles with the largest error first, the rest stay coarser. Refinement forced
    /// by minLevel ignores it.
    uint32_t maxTiles = 4096;
    /// The horizon test hides tiles behind the ellipsoid lowered by this much: the lowest
    /// visible surface on Earth (Dead Sea shore, about -430 m; geoid lows about -106 m) is above
    /// it, so no visible ground is culled. An eye below this occluder culls nothing; a value
    /// below minus the polar radius turns the horizon test off.
    double occluderHeight = -500.0;
};

/// The camera as the selector needs it. Build it with makeSelectorView(camera.pose(), ...) or
/// field by field from a scene::Camera: {cam.position(), glm::dmat3(cam.viewRotation()),
/// cam.verticalFovRad(), aspect, cam.nearPlane(), viewportHeightPx}.
struct SelectorView {
    glm::dvec3 eye{0.0};                   ///< ECEF
    glm::dmat3 worldToView{1.0};           ///< rotation only; view looks along -Z, +Y up
    double fovYRad = 0.7853981633974483;   ///< 45 degrees
    double aspect = 1.0;                   ///< width / height
    double nearPlane = 1.0;                ///< also the least distance used for the error
    double viewportHeightPx = 1080.0;
};

SelectorView makeSelectorView(const Pose& pose, double fovYRad, double aspect, double nearPlane,
                              double viewportHeightPx);

struct SelectedTile {
    TileKey key;
    double screenSpaceError = 0.0;   ///< pixels
    double distance = 0.0;           ///< eye to the closest point of the tile's volume, metres
};

struct SelectionStats {
    uint32_t visited = 0;         ///< tiles whose bounds were evaluated
    uint32_t culledFrustum = 0;
    uint32_t culledHorizon = 0;
    uint32_t selected = 0;
    uint32_t maxLevelReached = 0;
    bool budgetLimited = false;   ///< maxTiles stopped some refinement
};

class TileSelector {
public:
    using HeightRangeFn = std::function<TileHeightRange(const TileKey&)>;

    explicit TileSelector(SelectorSettings settings = {}, const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

    /// Selects the tiles to draw. The returned list stays valid until the next select() or
    /// reset(). Remembers which tiles it refined, for hysteresis on the next call.
    /// Not thread-safe: one selector per view, called from one thread. `heightRange` is called
    /// on that thread, once per visited tile.
    const std::vector<SelectedTile>& select(const SelectorView& view, const HeightRangeFn& heightRange);

    const std::vector<SelectedTile>& selection() const { return selected_; }
    const SelectionStats& stats() const { return stats_; }
    /// Forgets the previous frame (no hysteresis on the next select()).
    void reset();

    const SelectorSettings& settings() const { return settings_; }
    void setSettings(const SelectorSettings& settings) { settings_ = settings; }

    /// Metric error of drawing `key` with a gridSize x gridSize mesh: a quarter of the grid's
    /// cell size at the equator (see TileSelector.cpp for why).
    static double geometricError(const TileKey& key, int gridSize, const Ellipsoid& ellipsoid = Ellipsoid::wgs84());
    /// Metric error of a tile whose data is drawn in full: the sagitta of one grid cell's arc
    /// on the equator (the flat triangles under the curved ellipsoid).
    static double curvatureError(const TileKey& key, int gridSize, const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

private:
    struct Node {
        TileKey key;
        double sse;
        double distance;
        double facing;   // cosine between the view axis and the direction to the tile
        TileHeightRange range;   // the heights its error was judged with
        bool refine;
    };
    /// A tile refined by a select(), and the heights it was judged with.
    struct Refined {
        TileKey key;
        TileHeightRange range;
        bool operator<(const Refined& o) const { return key < o.key; }
    };
    // select()'s steps.
    /// Clears the per-select state and derives what the view fixes.
    void beginSelect(const SelectorView& view);
    /// Which frontier tiles refine: those that want to, as many as the tile budget allows.
    void markRefinements();
    /// Selects the frontier tiles that do not refine; their visible children are the next frontier.
    void expandFrontier(const HeightRangeFn& heightRange);
    /// Sorts the selection depth-first, keeps this frame's refined tiles, fills the stats.
    void finishSelect();

    bool evaluate(const TileKey& key, const HeightRangeFn& heightRange, Node& out);
    bool wantsRefine(const Node& node) const;
    /// Whether the last select() refined the tile with the heights known now (refining on
    /// heights since narrowed is not held: the selection does not depend on when data came).
    bool wasRefined(const Node& node) const;

    SelectorSettings settings_;
    const Ellipsoid* ellipsoid_;

    // Per-select state (members so that their capacity is reused from frame to frame).
    std::vector<Node> frontier_, next_;
    std::vector<uint32_t> candidates_;
    std::vector<Refined> refinedPrev_, refinedNow_;   // sorted after each select()
    std::vector<SelectedTile> selected_;
    SelectionStats stats_;

    // Derived from the view once per select().
    glm::dvec3 eye_{0.0};
    Geodetic eyeGeo_;
    glm::dmat3 worldToView_{1.0};
    double sseFactor_ = 0.0;     // viewportHeightPx / (2 tan(fovY/2))
    double minDistance_ = 1.0;
    double geometricError_[TileKey::kMaxLevel + 1] = {};
    ViewFrustum frustum_ = ViewFrustum::perspective(1.0, 1.0, 1.0);
};

struct BoundingSphere {
    glm::dvec3 center{0.0};   ///< ECEF
    double radius = 0.0;
};

/// A sphere that contains every point of the tile between the two heights. Built in double
/// from the corners, edge midpoints and centre at both heights, centred on the tile's normal
/// axis, so it holds the whole curved patch (the farthest point of a lat/lon rectangle from
/// that axis is a corner), then padded for the ellipsoid's flattening.
BoundingSphere tileBoundingSphere(const TileKey& key, const TileHeightRange& heights,
                                  const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

/// The point of the tile's volume (extent x height range) nearest to `eye`: the point of the
/// extent nearest to the eye's lon/lat (on the eye's meridian when it is inside the extent, else
/// on the nearer edge meridian, found in closed form on a sphere; on the ellipsoid within
/// 0.1 %), at the eye's height clamped into the range. Longitudes wrap: an eye at 179 is near
/// a tile at -179.
glm::dvec3 closestTilePoint(const TileKey& key, const TileHeightRange& heights, const Geodetic& eye,
                            const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

/// True when every point of the tile between its heights is hidden behind the ellipsoid lowered
/// by `occluderHeight`, seen from `eye` (ECEF). Exact up to a small slack for the heights (two
/// points over a sphere see each other when their angle is at most the sum of their horizon
/// angles), so much tighter than a bounding-sphere test on big tiles. Conservative: never true
/// for a tile any point of which can be seen. An eye inside the occluder hides nothing.
bool tileHiddenByEllipsoid(const TileKey& key, const TileHeightRange& heights, const glm::dvec3& eye,
                           double occluderHeight, const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

/// True when a sphere (ECEF) is entirely hidden behind an ellipsoid with semi-axes (a, a, b)
/// seen from `eye`: the sphere must lie both beyond the horizon plane and inside the shadow
/// cone. Conservative, and correct for spheres high above the surface (a mountain top behind
/// the horizon plane can still be seen over the horizon).
bool sphereHiddenByEllipsoid(const glm::dvec3& eye, const glm::dvec3& center, double radius, double a, double b);

/// A depth-first (pre-order) sort key: for disjoint tiles, sorting by it lists them in the
/// order of a NW, NE, SW, SE walk from the west root.
uint64_t depthFirstCode(const TileKey& key);

}  // namespace orbis::globe
