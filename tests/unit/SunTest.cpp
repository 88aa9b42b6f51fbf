#include "globe/Sun.h"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

using namespace orbis;

namespace {

constexpr double kPi = 3.14159265358979323846;

TimeNs at(const char* iso) {
    auto t = parseIso8601(iso);
    EXPECT_TRUE(t.ok()) << iso;
    return t.ok() ? *t : 0;
}

// Signed difference of two longitudes, in (-180, 180].
double lonDiff(double a, double b) {
    double d = std::fmod(a - b, 360.0);
    if (d > 180.0) d -= 360.0;
    if (d <= -180.0) d += 360.0;
    return d;
}

}  // namespace

// Declination tolerance: the Almanac formulas are good to 0.01 degrees, and the event times
// below are quoted to the minute (the Sun's declination changes by at most 0.0003 degrees in a
// minute). 0.05 degrees leaves margin for both without hiding a wrong sign or frame.

TEST(Sun, MarchEquinox2026HasZeroDeclination) {
    const glm::dvec2 p = globe::subsolarPointDeg(at("2026-03-20T14:46Z"));
    EXPECT_NEAR(p.y, 0.0, 0.05);
    EXPECT_NEAR(globe::sunEquatorial(at("2026-03-20T14:46Z")).rightAscensionDeg, 0.0, 0.05);
}

TEST(Sun, JuneSolstice2026DeclinationIsTheObliquity) {
    // Obliquity of the ecliptic in 2026: 23.4362 degrees (IAU 2006; nutation adds ~0.002).
    EXPECT_NEAR(globe::subsolarPointDeg(at("2026-06-21T08:24Z")).y, 23.436, 0.05);
}

TEST(Sun, DecemberSolstice2026DeclinationIsMinusTheObliquity) {
    EXPECT_NEAR(globe::subsolarPointDeg(at("2026-12-21T20:50Z")).y, -23.436, 0.05);
}

TEST(Sun, SubsolarLongitudeAtNoonUtcStaysWithinTheEquationOfTime) {
    // The equation of time never exceeds 16.5 minutes, i.e. 4.125 degrees of longitude; 4.15
    // adds the formulas' 0.01 degree error and rounding.
    double largest = 0.0;
    for (int day = 0; day < 365; day += 2) {
        const TimeNs noon = at("2026-01-01T12:00Z") + day * kNsPerDay;
        const double lon = globe::subsolarPointDeg(noon).x;
        EXPECT_LE(std::fabs(lon), 4.15) << formatIso8601(noon);
        largest = std::max(largest, std::fabs(lon));
    }
    // And it does reach ~4 degrees (early November): the Sun is not simply locked to noon UTC.
    EXPECT_GT(largest, 4.0);
}

TEST(Sun, AgreesWithNoaaSolarCalculator) {
    // Reference values from NOAA's solar calculator equations (Meeus-based, independent of the
    // Almanac formulas used here). Both are accurate to about 0.01 degrees, so 0.02 is the
    // tolerance for their difference.
    struct Case {
        const char* time;
        double declinationDeg, subsolarLonDeg;
    };
    const Case cases[] = {
        {"2026-03-20T14:46:00Z", 0.0023, -39.6503},   {"2026-06-21T08:24:00Z", 23.4381, 54.4479},
        {"2026-12-21T20:50:00Z", -23.4378, -132.9351}, {"2026-11-03T12:00:00Z", -15.1514, -4.1231},
        {"2026-02-11T12:00:00Z", -13.9252, 3.5565},   {"2026-07-26T12:00:00Z", 19.3634, 1.6407},
        {"2026-01-03T00:00:00Z", -22.8407, -178.9337},
    };
    for (const Case& c : cases) {
        const glm::dvec2 p = globe::subsolarPointDeg(at(c.time));
        EXPECT_NEAR(p.y, c.declinationDeg, 0.02) << c.time;
        EXPECT_NEAR(lonDiff(p.x, c.subsolarLonDeg), 0.0, 0.02) << c.time;
    }
}

TEST(Sun, DirectionIsUnitLength) {
    // normalize() leaves an error of a few ulps; 1e-12 is far above that and far below any
    // visible effect.
    for (int hour = 0; hour < 24 * 400; hour += 37) {
        const TimeNs t = at("2026-01-01T00:00Z") + hour * 3600 * kNsPerSecond;
        EXPECT_NEAR(glm::length(globe::sunDirectionEcef(t)), 1.0, 1e-12);
    }
}

TEST(Sun, DirectionPointsAtTheSubsolarPoint) {
    // Both come from the same vector; 1e-12 allows for the atan2/asin/cos round trip.
    const TimeNs t = at("2026-08-15T17:30Z");
    const glm::dvec3 d = globe::sunDirectionEcef(t);
    const glm::dvec2 p = globe::subsolarPointDeg(t) * (kPi / 180.0);
    EXPECT_NEAR(d.x, std::cos(p.y) * std::cos(p.x), 1e-12);
    EXPECT_NEAR(d.y, std::cos(p.y) * std::sin(p.x), 1e-12);
    EXPECT_NEAR(d.z, std::sin(p.y), 1e-12);
}

TEST(Sun, SubsolarLongitudeMovesWestFifteenDegreesPerHour) {
    // The Earth turns 15 degrees per hour relative to the mean Sun; the true Sun differs by the
    // change in the equation of time, at most 30 s per day = 0.005 degrees per hour. 0.01 covers it.
    const TimeNs start = at("2026-05-05T00:00Z");
    for (int hour = 0; hour < 48; ++hour) {
        const TimeNs t = start + hour * 3600 * kNsPerSecond;
        const double a = globe::subsolarPointDeg(t).x;
        const double b = globe::subsolarPointDeg(t + 3600 * kNsPerSecond).x;
        EXPECT_NEAR(lonDiff(b, a), -15.0, 0.01) << formatIso8601(t);
    }
}

TEST(Sun, SubsolarLongitudeIsInHalfOpenRange) {
    for (int minute = 0; minute < 24 * 60; minute += 7) {
        const double lon = globe::subsolarPointDeg(at("2026-09-01T00:00Z") + minute * 60 * kNsPerSecond).x;
        EXPECT_GE(lon, -180.0);
        EXPECT_LT(lon, 180.0);
    }
}

TEST(Sun, GmstMatchesMeeusExample) {
    // Meeus, Astronomical Algorithms, example 12.a: 1987-04-10 0h UT, GMST = 13h10m46.3668s.
    // 1e-6 degrees = 0.24 ms of time: the example's own rounding is 0.1 ms.
    const double expected = (13.0 + 10.0 / 60.0 + 46.3668 / 3600.0) * 15.0;
    EXPECT_NEAR(globe::greenwichMeanSiderealTimeDeg(at("1987-04-10T00:00Z")), expected, 1e-6);
}

TEST(Sun, GmstAtJ2000IsTheFormulaConstant) {
    // At J2000.0 every time-dependent term is zero; the tolerance is double rounding.
    EXPECT_NEAR(globe::greenwichMeanSiderealTimeDeg(at("2000-01-01T12:00Z")), 280.46061837, 1e-9);
}

TEST(Sun, DistanceIsShortestInJanuaryAndLongestInJuly) {
    // Perihelion ~0.98329 AU (early January), aphelion ~1.01671 AU (early July). The Almanac's
    // distance series is good to about 0.0003 AU.
    EXPECT_NEAR(globe::sunEquatorial(at("2026-01-03T17:00Z")).distanceAu, 0.98329, 0.0003);
    EXPECT_NEAR(globe::sunEquatorial(at("2026-07-06T17:00Z")).distanceAu, 1.01671, 0.0003);
}
