#pragma once
// Helpers shared by the motion tests: analytic paths sampled into TrajectorySamples, the local
// frame, temp files unique to this test process.
#include "globe/Ellipsoid.h"
#include "formats/motion/Trajectory.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace orbis::motion::test {

inline constexpr TimeNs kT0 = 1'700'000'000 * kNsPerSecond;   // 2023-11-14T22:13:20Z

inline TimeNs atSeconds(double s) { return kT0 + TimeNs(std::llround(s * 1e9)); }

/// A sample at an ECEF point (heights above the ellipsoid), no attitude.
inline TrajectorySample sampleAt(TimeNs t, const glm::dvec3& ecef) {
    const globe::Geodetic g = globe::Ellipsoid::wgs84().toGeodetic(ecef);
    TrajectorySample s;
    s.t = t;
    s.lonDeg = g.lonDeg;
    s.latDeg = g.latDeg;
    s.alt = g.height;
    s.altRef = AltitudeRef::Ellipsoid;
    return s;
}

/// A circle about the Earth's centre in the plane of unit vectors u, v (u ⟂ v), radius r,
/// travelled at `speed` m/s: the point at time `seconds`.
struct Circle {
    glm::dvec3 u, v;
    double radius, speed;
    double angleAt(double seconds) const { return speed * seconds / radius; }
    glm::dvec3 at(double seconds) const {
        const double a = angleAt(seconds);
        return radius * (std::cos(a) * u + std::sin(a) * v);
    }
    glm::dvec3 velocityAt(double seconds) const {
        const double a = angleAt(seconds);
        return speed * (-std::sin(a) * u + std::cos(a) * v);
    }
    std::vector<TrajectorySample> samples(double from, double to, double step) const {
        std::vector<TrajectorySample> out;
        for (double s = from; s <= to + 1e-9; s += step) out.push_back(sampleAt(atSeconds(s), at(s)));
        return out;
    }
};

/// The equator (radius a: exactly the ellipsoid's equator at height 0), eastward.
inline Circle equator(double speed = 250.0) {
    return {{1, 0, 0}, {0, 1, 0}, globe::Ellipsoid::wgs84().equatorialRadius(), speed};
}

/// A circle in the plane of the meridians 0 and 180, radius 6 400 km, northward at lon 0: it
/// passes exactly over the north pole at angle 90 degrees.
inline Circle meridianOverPole(double speed = 250.0) { return {{1, 0, 0}, {0, 0, 1}, 6'400'000.0, speed}; }

inline glm::dmat3 enu(double lonDeg, double latDeg) { return globe::Ellipsoid::wgs84().enuFrame(lonDeg, latDeg); }

/// Degrees between two unit vectors.
inline double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
    return glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
}

/// Difference of two headings, in (-180, 180].
inline double headingDiff(double a, double b) {
    double d = std::fmod(a - b, 360.0);
    if (d > 180.0) d -= 360.0;
    if (d <= -180.0) d += 360.0;
    return d;
}

/// A folder for this test process's files (ctest runs test processes in parallel).
inline std::filesystem::path tempDir() {
    const auto dir = std::filesystem::temp_directory_path() / ("orbis-motion-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
}

/// Removes this process's temp folder when the tests are done (one instance for all files).
class TempDirCleanup : public ::testing::Environment {
public:
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(std::filesystem::temp_directory_path() / ("orbis-motion-" + std::to_string(::getpid())), ec);
    }
};
inline ::testing::Environment* const kTempDirCleanup = ::testing::AddGlobalTestEnvironment(new TempDirCleanup);

inline std::string writeText(const std::string& name, const std::string& text) {
    const auto p = tempDir() / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

inline std::filesystem::path sharedData(const char* relative) {
    return std::filesystem::path(ORBIS_SHARED_DATA_DIR) / relative;
}

}  // namespace orbis::motion::test
