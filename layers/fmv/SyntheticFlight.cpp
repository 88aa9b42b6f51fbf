#include "layers/fmv/SyntheticFlight.h"

#include "globe/Ellipsoid.h"

#include <cmath>

namespace orbis::fmv {
namespace {

const globe::Ellipsoid& wgs84() { return globe::Ellipsoid::wgs84(); }

// Metres east and north of the target on its tangent plane, and back.
glm::dvec2 local(double lonDeg, double latDeg) {
    const glm::dmat3 enu = wgs84().enuFrame(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat);
    const glm::dvec3 d = wgs84().toEcef(lonDeg, latDeg, 0.0) - wgs84().toEcef(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat, 0.0);
    return {glm::dot(d, enu[0]), glm::dot(d, enu[1])};
}

globe::Geodetic fromLocal(double east, double north, double height) {
    const glm::dmat3 enu = wgs84().enuFrame(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat);
    const glm::dvec3 p = wgs84().toEcef(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat, 0.0) + east * enu[0] + north * enu[1];
    globe::Geodetic g = wgs84().toGeodetic(p);
    g.height = height;
    return g;
}

}  // namespace

double SyntheticFlight::height(double lonDeg, double latDeg) {
    const glm::dvec2 xy = local(lonDeg, latDeg);
    const double ridge = 500.0 * std::exp(-0.5 * std::pow((xy.x - 900.0) / 80.0, 2.0));
    return 600.0 + 80.0 * std::sin(xy.x / 400.0) * std::cos(xy.y / 300.0) + ridge;
}

TerrainHeights SyntheticFlight::terrain() {
    TerrainHeights t;
    t.at = &SyntheticFlight::height;
    t.minHeight = 600.0 - 80.0;
    t.maxHeight = 600.0 + 80.0 + 500.0;
    return t;
}

SensorPose SyntheticFlight::pose(double seconds) {
    const double phi = M_PI + 2.0 * M_PI * seconds / kLapSeconds;   // from due west, counter-clockwise
    const double east = kRadius * std::cos(phi), north = kRadius * std::sin(phi);
    const globe::Geodetic g = fromLocal(east, north, kHeight);
    SensorPose p;
    p.lonDeg = g.lonDeg;
    p.latDeg = g.latDeg;
    p.height = kHeight;
    // Heading along the circle's tangent (-sin, cos), clockwise from north.
    p.platformHeadingDeg = std::fmod(glm::degrees(std::atan2(-std::sin(phi), std::cos(phi))) + 360.0, 360.0);
    p.platformPitchDeg = 2.0;
    p.platformRollDeg = 0.0;
    p.hfovDeg = kHfov;
    p.vfovDeg = kVfov;
    // The sensor looks at the target on the ground: its direction in the platform's frame.
    SensorPose level = p;   // the platform alone: the sensor along its nose
    const SensorCamera platform(level);
    const glm::dvec3 target = wgs84().toEcef(kTargetLon, kTargetLat, height(kTargetLon, kTargetLat));
    const glm::dvec3 d = glm::transpose(platform.axes()) * glm::normalize(target - platform.position());
    p.sensorAzimuthDeg = std::fmod(glm::degrees(std::atan2(d.y, d.x)) + 360.0, 360.0);
    p.sensorElevationDeg = glm::degrees(std::atan2(-d.z, std::hypot(d.x, d.y)));
    p.sensorRollDeg = 0.0;
    return p;
}

St0601Packet SyntheticFlight::packet(double seconds) {
    const SensorPose p = pose(seconds);
    St0601Packet k;
    k.precisionTimeUs = kStartUs + uint64_t(std::llround(seconds * 1e6));
    k.missionId = "ORBIS SYNTHETIC";
    k.platformDesignation = "orbis-make-fmv";
    k.platformHeadingDeg = p.platformHeadingDeg;
    k.platformPitchDeg = p.platformPitchDeg;
    k.platformRollDeg = p.platformRollDeg;
    k.sensorLatitudeDeg = p.latDeg;
    k.sensorLongitudeDeg = p.lonDeg;
    k.sensorTrueAltitude = p.height;
    k.sensorEllipsoidHeight = p.height;
    k.horizontalFovDeg = p.hfovDeg;
    k.verticalFovDeg = p.vfovDeg;
    k.sensorRelativeAzimuthDeg = p.sensorAzimuthDeg;
    k.sensorRelativeElevationDeg = p.sensorElevationDeg;
    k.sensorRelativeRollDeg = p.sensorRollDeg;
    const SensorCamera camera(p);
    const TerrainHeights t = terrain();
    const Footprint f = footprint(camera, &t, 2.0);
    const globe::Geodetic c = wgs84().toGeodetic(f.centre.ecef);
    k.slantRange = f.centre.distance;
    k.frameCenterLatitudeDeg = c.latDeg;
    k.frameCenterLongitudeDeg = c.lonDeg;
    k.frameCenterElevation = c.height;
    for (int i = 0; i < 4; ++i) {
        const globe::Geodetic g = wgs84().toGeodetic(f.corners[size_t(i)].ecef);
        k.cornerLatitudeDeg[size_t(i)] = g.latDeg;
        k.cornerLongitudeDeg[size_t(i)] = g.lonDeg;
    }
    k.uasLsVersion = 17;
    return k;
}

}  // namespace orbis::fmv
