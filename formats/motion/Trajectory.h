#pragma once
// A vehicle's trajectory: time-stamped samples (TrajectorySample.h) turned once into ECEF
// positions and body-to-ECEF quaternions, and the pose at any time between them. CPU only, no
// Vulkan; double precision throughout.
//
// Position. Interpolated in ECEF, never in lon/lat, so the antimeridian and the poles are no
// special case (lon 179.9 -> -179.9 goes the short way by construction).
//   Linear      straight chords between samples; velocity is the chord's, constant per segment
//               (at a sample, that of the segment starting there).
//               On a curved path the chord cuts inside: by the sagitta R(1 - cos(a/2)) at mid
//               segment (0.12 m for 2.5 km segments on the Earth's radius).
//   CatmullRom  a cubic Hermite spline in time (C1 at the samples: position and velocity are
//               continuous) whose tangent at each sample is the derivative of the parabola
//               through it and its two neighbours at their real times (the non-uniform
//               Catmull-Rom tangent: exact for constant acceleration, whatever the spacing); at
//               the ends the parabola through the first (last) three samples. A tangent is
//               limited to twice the speed of the slower chord beside it: a long gap or a stop
//               (two samples at one place) cannot make the curve overshoot, a vehicle that stands
//               still between two samples stays put, and a steady path (where tangent and chord
//               speeds agree to O(a^2)) is untouched.
//
// Attitude. Each sample's heading/pitch/roll (Attitude.h: ST 0601's convention) is turned once
// into the body-to-ECEF quaternion R_ned(sample) * Rz Ry Rx; between samples the quaternions are
// slerped, the short way round (each segment takes the sign of its second quaternion that is on
// the first's side, so heading 359 -> 1 turns 2 degrees through 0). Why the body-to-ECEF quaternion and not the
// angles relative to each sample's local frame: the local frame turns along the path, and near a
// pole it turns by up to 180 degrees between two samples (a straight flight over the pole goes
// from heading 0 to heading 180 without turning), where interpolating local angles would spin
// the vehicle. The body-to-ECEF quaternion is indifferent to the frame: over the pole the
// vehicle does not turn. Along an east-west path the local frame turns about the Earth's axis,
// exactly as slerp between the two samples' quaternions does, so a constant heading stays
// constant (to O(a^3) of the segment's angle a from the chord's longitude, ~1e-9 degrees for
// 2.5 km segments). In general the difference from interpolating local angles is of second
// order (the segment's angle times the attitude change), negligible for any real sampling.
// Across a huge gap (tens of degrees of arc) the chord itself leaves the surface and the
// attitude, which follows the samples, is not level at mid-gap: resample such data.
//
// Missing attitude. Each absent angle is derived at load from the motion at that sample (the
// spline's tangent, whatever the interpolation): heading = course over ground, pitch = climb
// angle, roll = 0. At a sample where the vehicle does not move (< 1 cm/s) the direction of the
// nearest moving sample is used (before it, else after); with no motion at all, heading 0 and
// pitch 0. The angles given are kept: a CSV with only a heading column gets pitch from the climb.
//
// Altitude. Ellipsoid: as is. MeanSeaLevel: plus the geoid's height from
// TrajectoryOptions::geoid, looked up once at load; without one the altitude is taken as above
// the ellipsoid (off by the geoid undulation, up to about +-100 m) and a warning is logged and
// kept in warnings(). Ground: the height above the terrain; pose() adds the terrain's height
// from the GroundFn it is given at the interpolated place (a blend weight follows the samples,
// so a path that leaves the ground rises smoothly). Without a GroundFn, or where it knows no
// height, the terrain counts as the ellipsoid (height 0) and the pose says so (groundUnknown).
// The velocity and the derived pitch do not see the terrain's slope.
//
// Extrapolation, separately before the first sample and after the last:
//   Hold    the end pose (position and attitude), velocity 0.
//   Linear  the end position moved on with the end velocity (the last chord's for Linear
//           interpolation, the end tangent for CatmullRom): a straight line in ECEF, which leaves
//           the Earth's surface on long extrapolations; attitude held at the end's.
//   Hide    no pose: pose() returns nothing.
// A trajectory of one sample has velocity 0: every time gives that pose (unless Hide).
//
// Time. TimeNs (int64 ns since 1970); differences are taken in int64 with an overflow check and
// only then turned into double seconds, so times at the int64 extremes work.
//
// Sample order. Times must increase strictly: a time before the previous one is an error naming
// both lines; an equal time is an error too unless DuplicateTimes::KeepFirst (then the later
// samples at that time are dropped and counted). Non-finite positions, latitudes outside
// [-90, 90] and longitudes outside [-360, 360] are errors naming the line; a non-finite angle is
// taken as absent.
//
// Appending (live feeds). append() adds a sample after the last in amortised O(1): only the
// last three knots' tangents and attitudes and the last two segments change, exactly as create()
// over all the samples would make them (create() is the same appends one by one), so poses are
// the same whether a trajectory was read at once or grew fix by fix. One exception is kept lazy
// to stay O(1): while no sample but the last moves, the derived attitude of the still samples
// before it (which create() takes from the first moving sample after them) is computed when a
// pose needs it, and samples() shows it only from the first move on. keepLast() bounds the
// history (an O(n) rebuild, so call it once per many appends). The bounds grow with appends and
// may be a little larger than create()'s (a conservative sphere); keepLast() makes them exact.
//
// Thread rule: the const functions may be called from any thread at once (the GroundFn they are
// given must allow that too); append() and keepLast() not concurrently with anything.

#include "base/Result.h"
#include "base/TimeFormat.h"
#include "formats/motion/TrajectorySample.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace orbis::motion {

/// Poses at most this high above the ground (metres) count as on it (Pose::onGround).
inline constexpr double kOnGroundAglMetres = 1.0;

enum class Interpolation { Linear, CatmullRom };
enum class Extrapolation { Hold, Linear, Hide };
enum class DuplicateTimes { Error, KeepFirst };

/// The terrain's height above the ellipsoid (metres) at a place, or nothing where unknown.
using GroundFn = std::function<std::optional<double>(double lonDeg, double latDeg)>;
/// The geoid's height above the ellipsoid (metres) at a place; same type as fmv::GeoidHeight.
using GeoidHeight = std::function<double(double lonDeg, double latDeg)>;

struct TrajectoryOptions {
    Interpolation interpolation = Interpolation::CatmullRom;
    Extrapolation before = Extrapolation::Hold;   ///< before the first sample
    Extrapolation after = Extrapolation::Hold;    ///< after the last sample
    GeoidHeight geoid;                            ///< for MeanSeaLevel altitudes; empty: taken as ellipsoid heights
    bool clampToGround = false;                   ///< every sample on the terrain (Ground, altitude 0)
    DuplicateTimes duplicateTimes = DuplicateTimes::Error;
};

/// Where and how the vehicle is at one time.
struct Pose {
    TimeNs t = 0;
    glm::dvec3 ecef{0.0};   ///< metres
    double lonDeg = 0.0, latDeg = 0.0;
    double height = 0.0;    ///< above the ellipsoid, terrain included for Ground samples
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};   ///< body (x forward, y right, z down) to ECEF
    double headingDeg = 0.0, pitchDeg = 0.0, rollDeg = 0.0;   ///< in the NED frame at `ecef`
    glm::dvec3 velocity{0.0};   ///< ECEF, m/s
    bool extrapolated = false;  ///< `t` is outside timeRange()
    bool groundUnknown = false; ///< Ground altitude without a terrain height here: taken as 0
    /// Entirely Ground altitude, at most kOnGroundAglMetres above the terrain (which is known
    /// here): a vehicle on the ground, whose pitch and roll may follow it (GroundAttitude.h).
    bool onGround = false;

    glm::dmat3 rotation() const { return glm::mat3_cast(orientation); }   ///< columns: body x, y, z in ECEF
    glm::dvec3 forward() const;   ///< body +x in ECEF (unit)
    glm::dvec3 right() const;     ///< body +y in ECEF (unit)
    glm::dvec3 up() const;        ///< body -z in ECEF (unit)
};

struct TimeRange {
    TimeNs begin = 0, end = 0;   ///< first and last sample's times (equal for one sample)
};

/// The region a trajectory's samples cover, for framing a camera.
struct TrajectoryBounds {
    /// Longitudes: the smallest interval that holds every sample, from west to east; when it
    /// crosses the antimeridian eastDeg < westDeg. A path around a pole (or over it) has
    /// west -180, east 180.
    double westDeg = 0.0, eastDeg = 0.0;
    double southDeg = 0.0, northDeg = 0.0;   ///< including a pole the path passes over
    double minHeight = 0.0, maxHeight = 0.0; ///< above the ellipsoid; Ground samples without their terrain
    glm::dvec3 centerEcef{0.0};              ///< a sphere holding every sample
    double radius = 0.0;
    bool crossesAntimeridian() const { return eastDeg < westDeg; }
};

class Trajectory {
public:
    /// Builds the trajectory; `name` (the file) starts every message. Errors: no samples, a
    /// non-finite or out-of-range position, times not increasing (see the header's notes).
    static Result<Trajectory> create(std::vector<TrajectorySample> samples, const TrajectoryOptions& options = {},
                                     const std::string& name = "trajectory");

    /// The pose at `t`; nothing outside the time range when that end's extrapolation is Hide.
    /// O(log n) (a binary search), no allocation. `ground` is asked once, at the pose's place,
    /// and only for Ground samples.
    std::optional<Pose> pose(TimeNs t, const GroundFn* ground = nullptr) const;

    /// Adds a sample after the last (see the header's "Appending"): an error naming the sample
    /// for the same problems as create() (a time not after the last one's, unless duplicates are
    /// kept-first: then it is dropped and counted).
    Result<void> append(TrajectorySample sample);
    /// Keeps the last `count` samples (at least 1): the trajectory create() would make of them.
    /// O(n).
    void keepLast(std::size_t count);

    TimeRange timeRange() const { return {times_.front(), times_.back()}; }
    std::size_t sampleCount() const { return times_.size(); }
    /// The samples as kept (duplicates dropped, clampToGround applied, derived angles filled).
    const std::vector<TrajectorySample>& samples() const { return samples_; }

    /// Points of the path between `from` and `to` (clamped to timeRange(); empty when they do not
    /// meet it or from > to), for drawing it as a line: the poses at `from` and `to`, the samples
    /// between, and for CatmullRom points on the curve between samples where it bends away from
    /// the chord by more than 5 cm. At most max(maxPoints, 2) points: when the samples alone
    /// are more, every k-th is kept. ECEF, metres, in time order.
    std::vector<glm::dvec3> pathEcef(TimeNs from, TimeNs to, std::size_t maxPoints, const GroundFn* ground = nullptr) const;

    const TrajectoryBounds& bounds() const { return bounds_; }
    Interpolation interpolation() const { return interpolation_; }
    const std::string& name() const { return name_; }
    /// What the load noticed and let pass (MSL without a geoid, dropped duplicates, ...).
    const std::vector<std::string>& warnings() const { return warnings_; }
    std::size_t droppedDuplicates() const { return droppedDuplicates_; }
    std::size_t derivedAttitudes() const { return derivedAttitudes_; }   ///< samples with an angle derived

private:
    struct Knot {
        glm::dvec3 p{0.0};        ///< ECEF position; Ground samples: the altitude above the ellipsoid
        glm::dvec3 m{0.0};        ///< velocity (spline tangent), m/s
        glm::dquat q{1.0, 0.0, 0.0, 0.0};   ///< body to ECEF, in the hemisphere of the previous knot's
        double groundWeight = 0.0;          ///< 1 for Ground samples, else 0
        // The segment from this knot to the next (unused on the last knot):
        double seconds = 0.0;               ///< its duration
        glm::dvec3 chordVelocity{0.0};      ///< (next.p - p) / seconds
        double angle = 0.0;                 ///< between q and sign x next.q in 4-D (half the rotation)
        double invSinAngle = 0.0;
        double sign = 1.0;                  ///< next.q's sign on q's side of the 4-D sphere
        // The motion at this knot (from m), for derived attitudes:
        bool moving = false;
        double motionHeadingDeg = 0.0, motionPitchDeg = 0.0;
    };

    Trajectory() = default;
    /// Checks a sample (position, angles), in time after the last kept one; `index`: its place
    /// in the caller's input, for messages. Sets `drop` for a repeated time that is dropped.
    Result<void> check(TrajectorySample& s, std::size_t index, bool& drop);
    /// Adds a checked sample: its knot, the tangents and attitudes that change (TrajectoryBuild.cpp).
    void appendChecked(const TrajectorySample& s);
    glm::dvec3 tangentAt(std::size_t i) const;
    void setMotion(std::size_t i);                         ///< moving and motion angles from m
    /// Sample i's attitude with its missing angles from (heading, pitch), roll 0: the knot's q
    /// and the sample's filled angles.
    void setAttitude(std::size_t i, double headingDeg, double pitchDeg);
    glm::dquat attitudeQ(std::size_t i, double headingDeg, double pitchDeg) const;
    void linkRotation(std::size_t i);                      ///< segment i's angle and sign
    /// Every attitude from scratch (small trajectories, keepLast()).
    void recomputeAttitudes();
    /// Knot i's attitude: stored, or for a lazy still start computed now.
    glm::dquat knotQ(std::size_t i) const { return i < lazyEnd_ ? attitudeQ(i, lazyHeadingDeg_, lazyPitchDeg_) : knots_[i].q; }
    void updateEndVelocities();
    void computeBounds();
    void extendBounds(std::size_t i);                      ///< after an append: grow the bounds by knot i
    /// Position, velocity, attitude and ground weight on segment `i` at fraction `s` in [0, 1].
    void interpolate(std::size_t i, double s, glm::dvec3& p, glm::dvec3& v, glm::dquat& q, double& w) const;
    /// Fills the geodetic position, terrain and angles of `out` from an ECEF point.
    void finish(Pose& out, const glm::dvec3& p, double groundWeight, const GroundFn* ground) const;
    /// The position only (terrain included) on segment `i` at `s`; for the path line.
    glm::dvec3 pointOn(std::size_t i, double s, const GroundFn* ground) const;
    /// The segment holding `t` (inside the time range) and the fraction along it.
    std::size_t segmentOf(TimeNs t, double& s) const;

    std::string name_;
    TrajectoryOptions options_;
    Interpolation interpolation_ = Interpolation::CatmullRom;
    Extrapolation before_ = Extrapolation::Hold, after_ = Extrapolation::Hold;
    std::vector<TimeNs> times_;   ///< apart from knots_: the binary search walks a dense array
    std::vector<Knot> knots_;
    std::vector<TrajectorySample> samples_;
    std::vector<uint8_t> derived_;          ///< per sample: bit 0 heading, 1 pitch, 2 roll were absent
    std::vector<std::ptrdiff_t> lastMoving_;   ///< per knot: the last moving knot at or before it, or -1
    std::ptrdiff_t firstMoving_ = -1;       ///< the first moving knot that is not the last one, or -1
    /// Knots before this one are a still start waiting for the first move: their attitude takes
    /// its missing angles from (lazyHeadingDeg_, lazyPitchDeg_) when asked (knotQ()).
    std::size_t lazyEnd_ = 0;
    double lazyHeadingDeg_ = 0.0, lazyPitchDeg_ = 0.0;
    glm::dvec3 startVelocity_{0.0}, endVelocity_{0.0};
    std::size_t lastIndex_ = 0;             ///< the input index of the last sample kept (messages)
    bool warnedGeoid_ = false;
    TrajectoryBounds bounds_;
    glm::dvec3 boxLo_{0.0}, boxHi_{0.0};    ///< ECEF box of the knots (bounds_ is its sphere)
    bool aroundPole_ = false;
    std::vector<std::string> warnings_;
    std::size_t droppedDuplicates_ = 0, derivedAttitudes_ = 0;
};

/// Seconds from `b` to `a` (a - b), computed in int64 when that does not overflow.
double secondsBetween(TimeNs a, TimeNs b);

const char* toString(Interpolation interpolation);   ///< "linear", "catmull-rom"
const char* toString(Extrapolation extrapolation);   ///< "hold", "linear", "hide"

}  // namespace orbis::motion
