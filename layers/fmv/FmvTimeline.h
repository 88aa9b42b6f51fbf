#pragma once
// The sensor's poses over a video's time, from its KLV packets (or a pose CSV), and the mapping
// of the video's clock onto UTC (the scene's virtual time). CPU only: no Vulkan, no FFmpeg.
//
// Each packet becomes a pose at its time on the video's clock; packets with a wrong checksum
// or without a usable pose (no position, height or field of view) are left out and counted.
// poseAt() interpolates between the two packets around a time: position linearly (longitude
// across the antimeridian the short way), angles the short way round, field of view linearly;
// before the first packet and after the last it holds the end pose.
//
// UTC of the video's frame 0: given (a scene's "start"), else from the packets' precision time
// stamps (tag 2): the median over packets of (time stamp - time on the video's clock), robust
// to a few packets whose stamp is off. A pose CSV has only UTC: its rows are placed on the
// video's clock by that same offset, which the caller gives (or the first row's time when the
// video has no other clock: row 1 at video time 0).

#include "base/Result.h"
#include "layers/fmv/SensorModel.h"
#include "formats/fmv/St0601.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace orbis::fmv {

struct TimedKlv;

/// How well the sensor model (SensorModel.h's rotation order) agrees with the corner
/// coordinates the packets carry: the angle, seen from the sensor, between each corner ray of
/// the model and the direction to the packet's corner (placed at the frame centre's elevation:
/// the packets do not say the corners' own heights). Relief puts a degree or two between them;
/// a wrong rotation order or sign puts tens of degrees.
struct CornerCheck {
    size_t corners = 0;   ///< corners compared (packets without corners have none)
    double medianDegrees = 0.0, maxDegrees = 0.0;
    double medianFovDegrees = 0.0;   ///< for scale: the horizontal field of view
};

struct TimedPose {
    double time = 0.0;   ///< seconds on the video's clock
    std::optional<double> utc;   ///< the packet's precision time stamp, seconds since 1970
    SensorPose pose;
};

/// The geoid's height above the ellipsoid at a place (for ST 0601's MSL altitudes), or none.
using GeoidHeight = std::function<double(double lonDeg, double latDeg)>;

class FmvTimeline {
public:
    /// From a video's KLV data packets (each may hold several ST 0601 sets). `name` starts every
    /// message. Errors: no packet with a usable pose (the message says why the packets failed).
    static Result<FmvTimeline> fromKlv(const std::vector<TimedKlv>& packets, const std::string& name,
                                       const GeoidHeight& geoid = {});
    /// From decoded packets at given video times (a pose CSV placed on the video's clock).
    static Result<FmvTimeline> fromPackets(const std::vector<std::pair<double, St0601Packet>>& packets,
                                           const std::string& name, const GeoidHeight& geoid = {});

    const std::vector<TimedPose>& poses() const { return poses_; }
    double firstTime() const { return poses_.front().time; }
    double lastTime() const { return poses_.back().time; }
    /// UTC (seconds since 1970) of the video's time 0, from the time stamps; none without them.
    std::optional<double> videoStartUtc() const { return videoStartUtc_; }
    /// The pose at `videoTime` (interpolated; held at the ends).
    SensorPose poseAt(double videoTime) const;

    const CornerCheck& cornerCheck() const { return cornerCheck_; }
    size_t checksumRejected() const { return checksumRejected_; }
    size_t incompleteRejected() const { return incompleteRejected_; }
    size_t undecodable() const { return undecodable_; }

private:
    std::vector<TimedPose> poses_;
    std::optional<double> videoStartUtc_;
    CornerCheck cornerCheck_;
    size_t checksumRejected_ = 0, incompleteRejected_ = 0, undecodable_ = 0;
};

/// Interpolates two poses: `f` = 0 gives `a`, 1 gives `b`.
SensorPose interpolate(const SensorPose& a, const SensorPose& b, double f);

}  // namespace orbis::fmv
