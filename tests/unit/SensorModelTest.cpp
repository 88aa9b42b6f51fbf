// The FMV sensor camera (ST 0601 angles -> rays) against analytic cases: nadir and oblique
// views over the ellipsoid, the heading turning the footprint, a ridge in front of the target,
// sensors looking above the horizon, and the poles and the antimeridian.
#include "globe/Ellipsoid.h"
#include "layers/fmv/SensorModel.h"
#include "formats/fmv/St0601.h"
#include "formats/fmv/St0601Encode.h"
#include "layers/fmv/SyntheticFlight.h"

#include <gtest/gtest.h>

#include <cmath>

namespace orbis::fmv {
namespace {

const globe::Ellipsoid& wgs84() { return globe::Ellipsoid::wgs84(); }

// A point's east and north metres from (lon, lat) on the ground (local tangent plane).
glm::dvec2 eastNorth(const glm::dvec3& p, double lon, double lat) {
    const glm::dmat3 enu = wgs84().enuFrame(lon, lat);
    const glm::dvec3 d = p - wgs84().toEcef(lon, lat, 0.0);
    return {glm::dot(d, enu[0]), glm::dot(d, enu[1])};
}

SensorPose nadir(double heading = 0.0) {
    SensorPose p;
    p.lonDeg = 10.0;
    p.latDeg = 45.0;
    p.height = 1000.0;
    p.platformHeadingDeg = heading;
    p.sensorElevationDeg = -90.0;
    p.hfovDeg = 40.0;
    p.vfovDeg = 30.0;
    return p;
}

TEST(SensorModel, NadirFootprintIsTheFieldOfViewOnTheGround) {
    const SensorCamera camera(nadir());
    const Footprint f = footprint(camera, nullptr, 1.0);
    ASSERT_TRUE(f.centre.hit);
    const glm::dvec2 c = eastNorth(f.centre.ecef, 10.0, 45.0);
    EXPECT_NEAR(c.x, 0.0, 0.01);
    EXPECT_NEAR(c.y, 0.0, 0.01);
    EXPECT_NEAR(f.centre.distance, 1000.0, 0.01);
    // Looking straight down with the platform's nose north: the image's top is north, its
    // right east. Corners: upper left, upper right, lower right, lower left.
    const double e = 1000.0 * std::tan(glm::radians(20.0)), n = 1000.0 * std::tan(glm::radians(15.0));
    const glm::dvec2 expected[4] = {{-e, n}, {e, n}, {e, -n}, {-e, -n}};
    for (int i = 0; i < 4; ++i) {
        ASSERT_TRUE(f.corners[size_t(i)].hit);
        const glm::dvec2 got = eastNorth(f.corners[size_t(i)].ecef, 10.0, 45.0);
        EXPECT_NEAR(got.x, expected[i].x, 0.3) << "corner " << i + 1;   // the Earth's curvature: centimetres
        EXPECT_NEAR(got.y, expected[i].y, 0.3) << "corner " << i + 1;
    }
}

TEST(SensorModel, HeadingTurnsTheFootprintClockwise) {
    const Footprint f = footprint(SensorCamera(nadir(90.0)), nullptr, 1.0);
    // Nose east: the image's top is east, its right south; corner 1 (upper left) is north-east.
    const double e = 1000.0 * std::tan(glm::radians(20.0)), n = 1000.0 * std::tan(glm::radians(15.0));
    const glm::dvec2 expected[4] = {{n, e}, {n, -e}, {-n, -e}, {-n, e}};
    for (int i = 0; i < 4; ++i) {
        const glm::dvec2 got = eastNorth(f.corners[size_t(i)].ecef, 10.0, 45.0);
        EXPECT_NEAR(got.x, expected[i].x, 0.3) << "corner " << i + 1;
        EXPECT_NEAR(got.y, expected[i].y, 0.3) << "corner " << i + 1;
    }
}

TEST(SensorModel, ObliqueViewsFollowAzimuthElevationAndPlatformAngles) {
    // Sensor 45 degrees down, turned 90 degrees right of a north-flying platform: the centre is
    // 1000 m east.
    SensorPose p = nadir();
    p.sensorElevationDeg = -45.0;
    p.sensorAzimuthDeg = 90.0;
    GroundHit c = intersectGround(SensorCamera(p).position(), SensorCamera(p).ray(0, 0), nullptr, 1.0);
    ASSERT_TRUE(c.hit);
    glm::dvec2 en = eastNorth(c.ecef, 10.0, 45.0);
    EXPECT_NEAR(en.x, 1000.0, 0.5);
    EXPECT_NEAR(en.y, 0.0, 0.5);
    // The same look from the platform's own attitude: pitched 45 degrees nose down, heading
    // east, sensor straight ahead.
    SensorPose q = nadir(90.0);
    q.platformPitchDeg = -45.0;
    q.sensorElevationDeg = 0.0;
    const SensorCamera cq(q);
    c = intersectGround(cq.position(), cq.ray(0, 0), nullptr, 1.0);
    en = eastNorth(c.ecef, 10.0, 45.0);
    EXPECT_NEAR(en.x, 1000.0, 0.5);
    EXPECT_NEAR(en.y, 0.0, 0.5);
    // Rolling the platform 30 degrees right wing down with the sensor looking straight down
    // (relative to the platform) moves the centre to the left of the track: west for a
    // north-flying platform, by h tan 30.
    SensorPose r = nadir();
    r.platformRollDeg = 30.0;
    const SensorCamera cr(r);
    c = intersectGround(cr.position(), cr.ray(0, 0), nullptr, 1.0);
    en = eastNorth(c.ecef, 10.0, 45.0);
    EXPECT_NEAR(en.x, -1000.0 * std::tan(glm::radians(30.0)), 0.5);
    EXPECT_NEAR(en.y, 0.0, 0.5);
    // project() inverts ray().
    for (double u : {-1.0, -0.3, 0.0, 0.8})
        for (double v : {-1.0, 0.25, 1.0}) {
            const glm::dvec3 uvd = cr.project(cr.position() + 500.0 * cr.ray(u, v));
            EXPECT_NEAR(uvd.x, u, 1e-9);
            EXPECT_NEAR(uvd.y, v, 1e-9);
            EXPECT_GT(uvd.z, 0.0);
        }
}

TEST(SensorModel, ARidgeInFrontHidesTheTarget) {
    // Terrain: flat at 0 but a ridge 700 m high between 400 and 500 m north of the sensor.
    SensorPose p = nadir();
    p.sensorElevationDeg = -45.0;   // the centre ray would land 1000 m north
    const glm::dvec3 origin = wgs84().toEcef(10.0, 45.0, 0.0);
    const glm::dmat3 enu = wgs84().enuFrame(10.0, 45.0);
    TerrainHeights ridge;
    ridge.minHeight = 0.0;
    ridge.maxHeight = 700.0;
    ridge.at = [&](double lon, double lat) {
        const double north = glm::dot(wgs84().toEcef(lon, lat, 0.0) - origin, enu[1]);
        return north > 400.0 && north < 500.0 ? 700.0 : 0.0;
    };
    const SensorCamera camera(p);
    const GroundHit hit = intersectGround(camera.position(), camera.ray(0, 0), &ridge, 1.0);
    ASSERT_TRUE(hit.hit);
    const glm::dvec2 en = eastNorth(hit.ecef, 10.0, 45.0);
    // The ray at 45 degrees is 1000 - north metres up: 600 m at the ridge's near wall, below
    // its top, so the ray stops there and the ground behind the ridge is hidden.
    EXPECT_NEAR(en.y, 400.0, 1.5);
    EXPECT_LT(hit.distance, 1000.0 * std::sqrt(2.0));
}

TEST(SensorModel, RaysAboveTheHorizonClampToIt) {
    SensorPose p = nadir();
    p.sensorElevationDeg = 25.0;   // looking up, north: even the lower corners (about 10 degrees up)
    const SensorCamera camera(p);
    const Footprint f = footprint(camera, nullptr, 10.0);
    EXPECT_FALSE(f.centre.hit);
    const double horizon = std::sqrt(2.0 * 6371000.0 * 1000.0);   // about 113 km
    EXPECT_NEAR(f.centre.distance, horizon, 0.01 * horizon);
    const globe::Geodetic g = wgs84().toGeodetic(f.centre.ecef);
    EXPECT_NEAR(g.height, 0.0, 1e-3);
    EXPECT_NEAR(g.lonDeg, 10.0, 1e-3);   // due north
    EXPECT_GT(g.latDeg, 45.9);
    for (const GroundHit& c : f.corners) {
        EXPECT_FALSE(c.hit);
        EXPECT_TRUE(std::isfinite(c.ecef.x) && std::isfinite(c.ecef.y) && std::isfinite(c.ecef.z));
    }
    // Straight up, and a sensor below the ground: finite.
    p.sensorElevationDeg = 90.0;
    const GroundHit up = intersectGround(SensorCamera(p).position(), SensorCamera(p).ray(0, 0), nullptr);
    EXPECT_FALSE(up.hit);
    EXPECT_TRUE(std::isfinite(up.distance));
    EXPECT_LT(glm::length(horizonPoint(wgs84().toEcef(10, 45, -50), glm::dvec3(1, 0, 0)) - wgs84().toEcef(10, 45, 0)), 1e-6);
}

TEST(SensorModel, PolesAndTheAntimeridianStayFinite) {
    for (const glm::dvec2 lonLat : {glm::dvec2(179.9999, 0.0), glm::dvec2(-180.0, 30.0), glm::dvec2(0.0, 90.0),
                                    glm::dvec2(45.0, -89.99999)}) {
        SensorPose p = nadir(200.0);
        p.lonDeg = lonLat.x;
        p.latDeg = lonLat.y;
        p.sensorElevationDeg = -60.0;
        const Footprint f = footprint(SensorCamera(p), nullptr, 2.0);
        for (const GroundHit& h : {f.corners[0], f.corners[1], f.corners[2], f.corners[3], f.centre}) {
            ASSERT_TRUE(h.hit) << lonLat.x << " " << lonLat.y;
            const globe::Geodetic g = wgs84().toGeodetic(h.ecef);
            EXPECT_NEAR(g.height, 0.0, 1e-2);
            EXPECT_LT(glm::length(h.ecef - SensorCamera(p).position()), 10000.0);
        }
    }
}

TEST(SensorModel, PoseFromAPacket) {
    St0601Packet packet;
    EXPECT_NE(sensorPoseFromPacket(packet).message().find("sensor position"), std::string::npos);
    packet.sensorLatitudeDeg = 45.0;
    packet.sensorLongitudeDeg = 10.0;
    EXPECT_NE(sensorPoseFromPacket(packet).message().find("height"), std::string::npos);
    packet.sensorTrueAltitude = 1000.0;
    EXPECT_NE(sensorPoseFromPacket(packet).message().find("field of view"), std::string::npos);
    packet.horizontalFovDeg = 40.0;
    packet.verticalFovDeg = 0.0;
    EXPECT_NE(sensorPoseFromPacket(packet).message().find("field of view"), std::string::npos);
    packet.verticalFovDeg = 30.0;
    packet.platformHeadingDeg = 90.0;
    packet.platformPitchDeg = 5.0;
    packet.platformPitchFullDeg = 6.0;   // the full-range tag wins
    packet.sensorRelativeElevationDeg = -30.0;
    auto pose = sensorPoseFromPacket(packet, 47.5);   // geoid 47.5 m above the ellipsoid
    ASSERT_TRUE(pose.ok()) << pose.message();
    EXPECT_DOUBLE_EQ(pose->height, 1047.5);
    EXPECT_DOUBLE_EQ(pose->platformPitchDeg, 6.0);
    EXPECT_DOUBLE_EQ(pose->platformRollDeg, 0.0);
    EXPECT_DOUBLE_EQ(pose->sensorElevationDeg, -30.0);
    packet.sensorEllipsoidHeight = 1200.0;   // an ellipsoid height wins over the altitude
    EXPECT_DOUBLE_EQ(sensorPoseFromPacket(packet, 47.5)->height, 1200.0);
}

TEST(SyntheticFlight, ItsPacketsDecodeToPosesThatLandOnTheirCorners) {
    // The fixture's KLV (orbis-make-fmv): encoded with ST 0601's precision, decoded, turned
    // back into a sensor camera: its rays land where the packet's corners and centre say, within
    // the precision of the angles (tag 18 steps 0.0055 degrees: 0.3 m at 3 km).
    const TerrainHeights terrain = SyntheticFlight::terrain();
    double worst = 0.0;
    for (double t : {0.0, 7.3, 60.0, 150.0, 200.0}) {
        const St0601Packet written = SyntheticFlight::packet(t);
        auto read = decodeSt0601(encodeSt0601(written));
        ASSERT_TRUE(read.ok()) << read.message();
        EXPECT_EQ(read->checksum, ChecksumVerdict::Valid);
        auto pose = sensorPoseFromPacket(*read);
        ASSERT_TRUE(pose.ok()) << pose.message();
        const Footprint f = footprint(SensorCamera(*pose), &terrain, 2.0);
        for (int i = 0; i < 4; ++i) {
            ASSERT_TRUE(read->corner(i)) << "corner " << i + 1;
            const LatLonDeg c = *read->corner(i);
            const glm::dvec3 expected = wgs84().toEcef(c.lonDeg, c.latDeg, SyntheticFlight::height(c.lonDeg, c.latDeg));
            worst = std::max(worst, glm::length(f.corners[size_t(i)].ecef - expected));
            EXPECT_TRUE(f.corners[size_t(i)].hit);
        }
        // The sensor tracks the target (the ridge is not in the way at these times).
        const glm::dvec3 target = wgs84().toEcef(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat,
                                                 SyntheticFlight::height(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat));
        EXPECT_LT(glm::length(f.centre.ecef - target), 2.0) << "t = " << t;
        EXPECT_NEAR(*read->slantRange, f.centre.distance, 2.0);
    }
    EXPECT_LT(worst, 2.0);
    // The terrain: heights within the stated range everywhere on the fixture's area.
    for (double lon = SyntheticFlight::kWest; lon <= SyntheticFlight::kEast; lon += 0.002)
        for (double lat = SyntheticFlight::kSouth; lat <= SyntheticFlight::kNorth; lat += 0.002) {
            EXPECT_GE(SyntheticFlight::height(lon, lat), terrain.minHeight);
            EXPECT_LE(SyntheticFlight::height(lon, lat), terrain.maxHeight);
        }
}

}  // namespace
}  // namespace orbis::fmv
