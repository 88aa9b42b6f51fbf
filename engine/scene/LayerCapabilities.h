#pragma once
// What a layer may offer beyond drawing, each an interface it opts into by inheriting it and
// returning itself from the matching Layer::as...() accessor. Callers ask for the capability
// and skip layers that have none, so a layer without live settings, ground or moving content
// writes nothing for them. No Vulkan.

#include "base/Result.h"
#include "base/TimeFormat.h"
#include "engine/scene/FrameContext.h"
#include "engine/scene/LayerSetting.h"
#include "globe/TileImageSource.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace orbis::scene {

/// Settings the viewer's panels show and edit, benchmark sweeps set, and saved scenes keep.
/// Main thread only.
class LiveSettings {
public:
    virtual ~LiveSettings() = default;
    /// Every setting with its current value, range and place in the scene file.
    virtual std::vector<LayerSetting> liveSettings() const = 0;
    /// Sets a numeric setting (Number, Integer, Toggle) by name, live. False when the layer has
    /// no such setting or the value is outside what it takes (the setting is then unchanged,
    /// or clamped where its doc says so).
    virtual bool setParameter(std::string_view /*name*/, double /*value*/) { return false; }
    /// Sets a Choice setting (a colour map's name, ...), live. False when there is no such
    /// setting or the value is not one of its choices.
    virtual bool setOption(std::string_view /*name*/, std::string_view /*value*/) { return false; }
    /// Sets a Curve setting to these control points, live. False when there is no such
    /// setting or the points are not valid for it (the setting is then unchanged).
    virtual bool setCurve(std::string_view /*name*/, const std::vector<glm::dvec2>& /*points*/) { return false; }
};

/// A layer that is the ground (terrain): heights for cameras, clamping, FMV and pins.
/// Main thread only.
class GroundSource {
public:
    virtual ~GroundSource() = default;
    /// Height of the ground (metres above the ellipsoid, as drawn) at a point; nothing where
    /// the layer knows no height.
    virtual std::optional<double> groundHeightAt(double lonDeg, double latDeg) const = 0;
    /// Changes whenever groundHeightAt's answers may have changed (tiles loaded or evicted):
    /// layers that sample the ground (FMV's heightfield) resample only then.
    virtual uint64_t groundVersion() const = 0;
    /// groundHeightAt's answers as they are now, callable from any thread for as long as the
    /// caller keeps the function (it holds what it reads): for work on the pool.
    virtual GroundHeightFn groundSnapshot() const = 0;
};

/// Where a moving thing is (a vehicle along its trajectory, a live position), for cameras that
/// follow it and for the scene's time range.
struct TrackedPose {
    glm::dvec3 position{0.0};              ///< ECEF metres
    glm::dquat bodyToEcef{1.0, 0.0, 0.0, 0.0};   ///< body axes (x forward, y right, z down) in ECEF
    glm::dvec3 velocity{0.0};              ///< ECEF metres per second
    double radius = 1.0;                   ///< bounding radius of what is drawn there, metres
};

struct TimeRange {
    TimeNs start = 0, end = 0;
};

/// A sphere around everything a layer may draw over time (a whole path), for overview cameras.
struct ContentBounds {
    glm::dvec3 center{0.0};   ///< ECEF
    double radius = 0.0;
};

/// A layer whose content moves with the scene's time (models on trajectories or live feeds):
/// the camera modes follow it and scenes without a time range take its. Main thread only.
class MovingContent {
public:
    virtual ~MovingContent() = default;
    /// The time span of the layer's data (a trajectory's samples).
    virtual std::optional<TimeRange> timeRange() const = 0;
    /// The pose of the thing the layer moves at `t` (its first copy) on `ground`; nothing where
    /// it is hidden at `t`.
    virtual std::optional<TrackedPose> trackedPose(TimeNs t, const GroundHeightFn& ground) const = 0;
    /// Where the moving content goes over its whole time range.
    virtual std::optional<ContentBounds> contentBounds() const = 0;
};

/// A layer whose content may float above the ground (a point cloud seen from 2 m at 8 000 m, a
/// model in the air): the near plane must never cut it. Main thread only.
class FloatingContent {
public:
    virtual ~FloatingContent() = default;
    /// Distance from `eye` (ECEF) to the nearest content the layer draws (its bounds, 0 when the
    /// eye is inside them); nothing when it has nothing to draw.
    virtual std::optional<double> nearestContent(const glm::dvec3& eye) const = 0;
};

/// A layer whose content lies on the ground (vector features clamped to the terrain): it
/// paints it into the ground's tile images, which the ground layer (terrain) blends over its
/// own imagery, so the content is exactly on the surface at every zoom (no floating, no
/// cutting into hills, no z-fighting). Main thread only; the source is read on workers.
class DrapedContent {
public:
    virtual ~DrapedContent() = default;
    /// What paints the tiles; null while there is nothing to paint yet (data loading).
    virtual std::shared_ptr<const globe::TileImageSource> drapeSource() const = 0;
    /// Changes whenever what the source paints has changed (data arrived, a style or the time
    /// changed what is shown): the ground paints its tiles again.
    virtual uint64_t drapeVersion() const = 0;
    /// Opacity of the painted images over the ground.
    virtual double drapeOpacity() const { return 1.0; }
    /// Where what the source paints changed between `version` and drapeVersion() (lon/lat
    /// boxes, longitudes continuous), when the layer knows: the ground paints only the tiles
    /// that reach into them again. Nothing: it may have changed anywhere.
    virtual std::optional<std::vector<globe::GeoExtent>> drapeChangedSince(uint64_t /*version*/) const { return std::nullopt; }
    /// How far past its edge a tile's painting reaches, as a fraction of its size (a stroke's
    /// width, an icon's size): a tile that near a changed box is painted again.
    virtual double drapeReach() const { return 0.5; }
};

/// One feature a click found: what the viewer's feature panel shows.
struct PickedAttributes {
    std::string layer;     ///< the scene layer and the source's layer ("Borders / countries")
    std::string feature;   ///< its id ("fid 12")
    std::vector<std::pair<std::string, std::string>> fields;   ///< name and value as text, in field order
};

/// A layer whose features can be clicked (vector data): the feature at a ground point, its
/// attributes, and the feature highlighted until the next pick. Main thread only.
class PickableContent {
public:
    virtual ~PickableContent() = default;
    /// The feature drawn at the ground point (lon, lat; `metresPerPixel` of ground there sizes
    /// line widths and markers), now highlighted; nothing, and no highlight, when none is there.
    virtual std::optional<PickedAttributes> pickAt(double lonDeg, double latDeg, double metresPerPixel) = 0;
    /// Ends the highlight.
    virtual void clearPick() = 0;
};

/// Figures for the viewer's stats panel and the benchmark's tables. Main thread only.
/// What a layer fed by a live stream (FMV over the network) tells the feeds panel.
struct FeedStatus {
    std::string url;
    std::string state;                     ///< "connecting", "live", "no signal"
    double bitsPerSecond = 0.0;            ///< over the last seconds
    std::optional<double> latencySeconds;  ///< a frame's send time (its time stamp) to its drape
    uint64_t framesShown = 0, framesLost = 0, damagedPackets = 0;
    double secondsSinceData = 0.0;
    int width = 0, height = 0;
    std::string lastError;                 ///< why the stream last stopped, or empty
    std::string recording;                 ///< the file the stream is recorded into, or empty
};

/// A layer fed by a live stream. Main thread only.
class LiveFeed {
public:
    virtual ~LiveFeed() = default;
    virtual FeedStatus feedStatus() const = 0;
    /// Starts recording the stream as received (a new file next to the scene, named after the
    /// layer and the time) or stops; returns the file, or an error naming it.
    virtual Result<std::string> setRecording(bool on) const = 0;
};

class LayerStats {
public:
    virtual ~LayerStats() = default;
    /// GPU memory the layer holds.
    virtual uint64_t gpuBytes() const { return 0; }
    /// CPU memory the layer holds in caches (tiles, chunks).
    virtual uint64_t cacheBytes() const { return 0; }
    /// Items drawn in the last frame (tiles, chunks, ...).
    virtual uint64_t itemsDrawn() const { return 0; }
};

}  // namespace orbis::scene
