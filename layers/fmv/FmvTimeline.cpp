#include "layers/fmv/FmvTimeline.h"

#include "globe/Ellipsoid.h"
#include "formats/fmv/KlvFile.h"
#include "layers/fmv/VideoFile.h"

#include <algorithm>
#include <cmath>

namespace orbis::fmv {
namespace {

// a + f (b - a) the short way round a circle of `period` degrees, in [0, period) for 360.
double lerpAngle(double a, double b, double f, double period = 360.0) {
    double d = std::fmod(b - a, period);
    if (d > period / 2) d -= period;
    if (d < -period / 2) d += period;
    return a + f * d;
}

double wrap360(double a) {
    a = std::fmod(a, 360.0);
    return a < 0.0 ? a + 360.0 : a;
}

double wrap180(double a) {
    a = std::fmod(a + 180.0, 360.0);
    return (a < 0.0 ? a + 360.0 : a) - 180.0;
}

}  // namespace

SensorPose interpolate(const SensorPose& a, const SensorPose& b, double f) {
    f = std::clamp(f, 0.0, 1.0);
    SensorPose p;
    p.lonDeg = wrap180(lerpAngle(a.lonDeg, b.lonDeg, f));
    p.latDeg = a.latDeg + f * (b.latDeg - a.latDeg);
    p.height = a.height + f * (b.height - a.height);
    p.platformHeadingDeg = wrap360(lerpAngle(a.platformHeadingDeg, b.platformHeadingDeg, f));
    p.platformPitchDeg = lerpAngle(a.platformPitchDeg, b.platformPitchDeg, f);
    p.platformRollDeg = lerpAngle(a.platformRollDeg, b.platformRollDeg, f);
    p.sensorAzimuthDeg = wrap360(lerpAngle(a.sensorAzimuthDeg, b.sensorAzimuthDeg, f));
    p.sensorElevationDeg = lerpAngle(a.sensorElevationDeg, b.sensorElevationDeg, f);
    p.sensorRollDeg = wrap360(lerpAngle(a.sensorRollDeg, b.sensorRollDeg, f));
    p.hfovDeg = a.hfovDeg + f * (b.hfovDeg - a.hfovDeg);
    p.vfovDeg = a.vfovDeg + f * (b.vfovDeg - a.vfovDeg);
    return p;
}

Result<FmvTimeline> FmvTimeline::fromKlv(const std::vector<TimedKlv>& packets, const std::string& name, const GeoidHeight& geoid) {
    std::vector<std::pair<double, St0601Packet>> decoded;
    FmvTimeline t;
    std::string firstProblem;
    for (const TimedKlv& k : packets) {
        const KlvStream stream = decodeKlvStream(k.bytes);
        for (const KlvRecord& r : stream.records) {
            if (!r.packet) {
                ++t.undecodable_;
                if (firstProblem.empty()) firstProblem = r.error;
                continue;
            }
            if (r.packet->checksum == ChecksumVerdict::Mismatch) {
                ++t.checksumRejected_;
                if (firstProblem.empty()) firstProblem = "a packet's checksum is wrong";
                continue;
            }
            decoded.emplace_back(k.time, *r.packet);
        }
    }
    auto built = fromPackets(decoded, name, geoid);
    if (!built) {
        if (decoded.empty())
            return makeError(name + ": no usable KLV packet (" + std::to_string(packets.size()) + " data packets" +
                             (firstProblem.empty() ? std::string(")") : std::string("; first problem: ").append(firstProblem).append(")")));
        return built;
    }
    built->checksumRejected_ = t.checksumRejected_;
    built->undecodable_ = t.undecodable_;
    return built;
}

Result<FmvTimeline> FmvTimeline::fromPackets(const std::vector<std::pair<double, St0601Packet>>& packets, const std::string& name,
                                             const GeoidHeight& geoid) {
    FmvTimeline t;
    std::string firstProblem;
    std::vector<double> offsets, cornerAngles, fovs;
    const globe::Ellipsoid& wgs84 = globe::Ellipsoid::wgs84();
    for (const auto& [time, packet] : packets) {
        if (!std::isfinite(time)) continue;
        double undulation = 0.0;
        if (geoid && packet.sensorLatitudeDeg && packet.sensorLongitudeDeg && !packet.sensorHeightAboveEllipsoid())
            undulation = geoid(*packet.sensorLongitudeDeg, *packet.sensorLatitudeDeg);
        auto pose = sensorPoseFromPacket(packet, undulation);
        if (!pose) {
            ++t.incompleteRejected_;
            if (firstProblem.empty()) firstProblem = pose.message();
            continue;
        }
        TimedPose p;
        p.time = time;
        p.pose = *pose;
        if (packet.precisionTimeUs) {
            p.utc = double(*packet.precisionTimeUs) * 1e-6;
            offsets.push_back(*p.utc - time);
        }
        // The model's corner rays against the directions to the packet's corners.
        if (packet.corner(0) && packet.corner(1) && packet.corner(2) && packet.corner(3)) {
            double h = 0.0;
            if (packet.frameCenterElevation) {
                h = *packet.frameCenterElevation;
                if (geoid && packet.frameCenterLatitudeDeg && packet.frameCenterLongitudeDeg)
                    h += geoid(*packet.frameCenterLongitudeDeg, *packet.frameCenterLatitudeDeg);
            }
            const SensorCamera camera(*pose);
            for (int i = 0; i < 4; ++i) {
                const LatLonDeg c = *packet.corner(i);
                const glm::dvec3 towards = wgs84.toEcef(c.lonDeg, c.latDeg, h) - camera.position();
                if (glm::length(towards) < 1e-3) continue;
                const double cosine = std::clamp(glm::dot(glm::normalize(towards), camera.cornerRay(i)), -1.0, 1.0);
                cornerAngles.push_back(glm::degrees(std::acos(cosine)));
            }
            fovs.push_back(pose->hfovDeg);
        }
        t.poses_.push_back(p);
    }
    if (t.poses_.empty())
        return makeError(name + ": no packet gives a sensor pose" +
                         (firstProblem.empty() ? std::string() : std::string(" (").append(firstProblem).append(")")));
    std::stable_sort(t.poses_.begin(), t.poses_.end(), [](const TimedPose& a, const TimedPose& b) { return a.time < b.time; });
    const auto median = [](std::vector<double>& v) {
        std::nth_element(v.begin(), v.begin() + ptrdiff_t(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    if (!offsets.empty()) t.videoStartUtc_ = median(offsets);
    if (!cornerAngles.empty()) {
        t.cornerCheck_.corners = cornerAngles.size();
        t.cornerCheck_.maxDegrees = *std::max_element(cornerAngles.begin(), cornerAngles.end());
        t.cornerCheck_.medianDegrees = median(cornerAngles);
        t.cornerCheck_.medianFovDegrees = median(fovs);
    }
    return t;
}

SensorPose FmvTimeline::poseAt(double videoTime) const {
    if (videoTime <= poses_.front().time) return poses_.front().pose;
    if (videoTime >= poses_.back().time) return poses_.back().pose;
    const auto after = std::upper_bound(poses_.begin(), poses_.end(), videoTime,
                                        [](double t, const TimedPose& p) { return t < p.time; });
    const TimedPose& b = *after;
    const TimedPose& a = *(after - 1);
    const double span = b.time - a.time;
    return span > 0.0 ? interpolate(a.pose, b.pose, (videoTime - a.time) / span) : b.pose;
}

}  // namespace orbis::fmv
