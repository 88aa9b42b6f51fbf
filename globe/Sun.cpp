#include "globe/Sun.h"

#include <cmath>

namespace orbis::globe {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;

/// Angle reduced to [0, 360).
double wrap360(double deg) {
    const double r = std::fmod(deg, 360.0);
    return r < 0.0 ? r + 360.0 : r;
}

/// Angle reduced to [-180, 180).
double wrap180(double deg) { return wrap360(deg + 180.0) - 180.0; }

/// The Sun in the true-of-date equatorial frame, as a unit vector and a distance.
struct Equatorial {
    glm::dvec3 direction;
    double distanceAu;
};

Equatorial equatorial(TimeNs t) {
    // The Astronomical Almanac, section C, "Low precision formulas for the Sun" (identical since
    // the 1980s editions; also in Michalsky 1988, Solar Energy 40(3)). n is days from J2000.0.
    // The Almanac uses TT; using UTC instead shifts the Sun by (TT - UTC = 69 s) * 0.041"/s =
    // 3 arcseconds, well inside the formula's 0.01 degree accuracy.
    const double n = daysSinceJ2000(t);
    // Mean longitude, corrected for aberration, and mean anomaly, degrees.
    const double meanLongitude = wrap360(280.460 + 0.9856474 * n);
    const double meanAnomaly = wrap360(357.528 + 0.9856003 * n) * kDegToRad;
    // Ecliptic longitude (equation of centre to second order); ecliptic latitude is < 1.2" and
    // taken as 0.
    const double lambda =
        (meanLongitude + 1.915 * std::sin(meanAnomaly) + 0.020 * std::sin(2.0 * meanAnomaly)) * kDegToRad;
    // Obliquity of the ecliptic, degrees.
    const double epsilon = (23.439 - 0.0000004 * n) * kDegToRad;
    // Distance in AU.
    const double distance = 1.00014 - 0.01671 * std::cos(meanAnomaly) - 0.00014 * std::cos(2.0 * meanAnomaly);

    // Ecliptic (cos lambda, sin lambda, 0) rotated about x by the obliquity.
    const glm::dvec3 direction(std::cos(lambda), std::cos(epsilon) * std::sin(lambda),
                               std::sin(epsilon) * std::sin(lambda));
    return {direction, distance};
}

}  // namespace

SunEquatorial sunEquatorial(TimeNs t) {
    const Equatorial e = equatorial(t);
    SunEquatorial s;
    s.rightAscensionDeg = wrap360(std::atan2(e.direction.y, e.direction.x) * kRadToDeg);
    s.declinationDeg = std::asin(glm::clamp(e.direction.z, -1.0, 1.0)) * kRadToDeg;
    s.distanceAu = e.distanceAu;
    return s;
}

double greenwichMeanSiderealTimeDeg(TimeNs t) {
    // IAU 1982 GMST (Aoki et al. 1982, A&A 105, 359), written in degrees of the full date as in
    // Meeus, Astronomical Algorithms (2nd ed.), eq. 12.4:
    //   GMST = 280.46061837 + 360.98564736629 d + 0.000387933 T^2 - T^3 / 38710000
    // with d = days from J2000.0 (UT1) and T = d / 36525. The 360.98... d term is split into
    // whole days (each exactly 360 degrees, dropped) plus the fraction, so that present-day
    // values keep their precision instead of losing it in a 3.6e6-degree product.
    const double d = daysSinceJ2000(t);
    const double whole = std::floor(d);
    const double fraction = d - whole;
    const double T = d / 36525.0;
    const double deg = 280.46061837 + 360.0 * fraction + 0.98564736629 * d + 0.000387933 * T * T -
                       T * T * T / 38710000.0;
    return wrap360(deg);
}

glm::dvec3 sunDirectionEcef(TimeNs t) {
    // The Earth-fixed frame is the equatorial frame of date turned by the sidereal angle about
    // z. Using mean rather than apparent sidereal time (the equation of the equinoxes, at most
    // 1.2 s = 0.005 degrees) and ignoring polar motion (< 0.5") both stay inside the 0.01 degree
    // budget of the solar coordinates.
    const glm::dvec3 q = equatorial(t).direction;
    const double theta = greenwichMeanSiderealTimeDeg(t) * kDegToRad;
    const double c = std::cos(theta), s = std::sin(theta);
    // R_z(-theta): x_ecef = cos(theta) x + sin(theta) y, y_ecef = -sin(theta) x + cos(theta) y.
    return glm::normalize(glm::dvec3(c * q.x + s * q.y, -s * q.x + c * q.y, q.z));
}

glm::dvec2 subsolarPointDeg(TimeNs t) {
    const glm::dvec3 d = sunDirectionEcef(t);
    const double lonDeg = wrap180(std::atan2(d.y, d.x) * kRadToDeg);
    const double latDeg = std::asin(glm::clamp(d.z, -1.0, 1.0)) * kRadToDeg;
    return {lonDeg, latDeg};
}

}  // namespace orbis::globe
