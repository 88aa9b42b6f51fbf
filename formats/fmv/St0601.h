#pragma once
// MISB ST 0601 UAS Datalink Local Set: one packet of drone video metadata decoded into the
// values the FMV layer needs (sensor position and attitude, field of view, frame centre and
// corners, time), CPU only.
//
// Decoding follows ST 0601's mappings (linear maps of fixed-size integers, and ST 1201 IMAPB for
// the "extended" tags). A value the standard marks as an error or out of range (0x8000 for the
// int16 tags, 0x80000000 for the int32 ones, ST 1201 special values for IMAPB) is left absent and
// its tag listed in `errorTags`: never a bogus number. The 16-bit running-sum checksum (tag 1) is
// verified and its verdict reported; a mismatch does not stop the decode (the caller decides).
// Tags not decoded here, nested local sets (48 security, 73 RVT, 74 VMTI, ...) included, are kept
// as raw bytes. Structurally broken packets (lengths past the end, malformed tags) are errors;
// anything else odd (duplicate tags, wrong value sizes, checksum not last) is a warning.

#include "base/Result.h"
#include "formats/fmv/Klv.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace orbis::fmv {

/// Largest ST 0601 packet accepted (value bytes). The standard sets no limit; real packets are
/// a few hundred bytes, a few kB with VMTI. A declared length above this is an "oversized
/// packet" error, so that a corrupt length never makes a reader swallow a whole stream.
inline constexpr std::size_t kMaxSt0601PacketBytes = 1 << 20;

enum class ChecksumVerdict { Valid, Mismatch, Missing };
const char* toString(ChecksumVerdict verdict);   ///< "valid", "mismatch", "missing"

/// A tag kept as it was: undecoded tags, nested sets, values of the wrong size.
struct RawTag {
    uint32_t tag = 0;
    std::vector<uint8_t> bytes;
};

/// A geographic point in degrees.
struct LatLonDeg {
    double latDeg = 0.0, lonDeg = 0.0;
};

/// One decoded packet. Units: degrees for angles, metres for lengths (the standard's units).
/// Heights: "true altitude" and "elevation" are above mean sea level (ST 0601), "ellipsoid
/// height" is above the WGS84 ellipsoid.
struct St0601Packet {
    std::optional<uint64_t> precisionTimeUs;           ///< tag 2: µs since 1970-01-01T00:00Z (no leap seconds)
    std::optional<std::string> missionId;              ///< tag 3
    std::optional<std::string> platformTailNumber;     ///< tag 4
    std::optional<double> platformHeadingDeg;          ///< tag 5: 0..360, clockwise from true north
    std::optional<double> platformPitchDeg;            ///< tag 6: ±20, positive nose up
    std::optional<double> platformRollDeg;             ///< tag 7: ±50, positive right wing down
    std::optional<std::string> platformDesignation;    ///< tag 10
    std::optional<std::string> imageSourceSensor;      ///< tag 11
    std::optional<std::string> imageCoordinateSystem;  ///< tag 12
    std::optional<double> sensorLatitudeDeg;           ///< tag 13: ±90
    std::optional<double> sensorLongitudeDeg;          ///< tag 14: ±180
    std::optional<double> sensorTrueAltitude;          ///< tag 15: -900..19000 m above MSL
    std::optional<double> horizontalFovDeg;            ///< tag 16: 0..180
    std::optional<double> verticalFovDeg;              ///< tag 17: 0..180
    std::optional<double> sensorRelativeAzimuthDeg;    ///< tag 18: 0..360, from the platform's nose, clockwise
    std::optional<double> sensorRelativeElevationDeg;  ///< tag 19: ±180, negative looking down
    std::optional<double> sensorRelativeRollDeg;       ///< tag 20: 0..360
    std::optional<double> slantRange;                  ///< tag 21: 0..5e6 m, sensor to frame centre
    std::optional<double> targetWidth;                 ///< tag 22: 0..10000 m
    std::optional<double> frameCenterLatitudeDeg;      ///< tag 23: ±90
    std::optional<double> frameCenterLongitudeDeg;     ///< tag 24: ±180
    std::optional<double> frameCenterElevation;        ///< tag 25: -900..19000 m above MSL
    /// Tags 26, 28, 30, 32 / 27, 29, 31, 33: corners 1..4 (upper left, upper right, lower right,
    /// lower left) as offsets (±0.075°) from the frame centre; see corner().
    std::array<std::optional<double>, 4> offsetCornerLatitudeDeg, offsetCornerLongitudeDeg;
    std::optional<int> uasLsVersion;                   ///< tag 65
    std::optional<double> sensorEllipsoidHeight;       ///< tag 75: -900..19000 m above the ellipsoid
    /// Tags 82, 84, 86, 88 / 83, 85, 87, 89: corners 1..4 at full precision (±90, ±180).
    std::array<std::optional<double>, 4> cornerLatitudeDeg, cornerLongitudeDeg;
    std::optional<double> platformPitchFullDeg;        ///< tag 90: ±90
    std::optional<double> platformRollFullDeg;         ///< tag 91: ±90
    std::optional<double> sensorEllipsoidHeightExtended;   ///< tag 104: IMAPB(-900, 40000) m above the ellipsoid

    std::vector<RawTag> otherTags;     ///< tags not decoded above, nested sets included, in packet order
    std::vector<uint32_t> errorTags;   ///< tags present whose value is an error sentinel, out of range or of the wrong size
    std::vector<std::string> warnings; ///< duplicate tags, wrong sizes, checksum not last, ...

    ChecksumVerdict checksum = ChecksumVerdict::Missing;
    uint16_t storedChecksum = 0;     ///< tag 1 as stored (0 when missing)
    uint16_t computedChecksum = 0;   ///< over the key .. tag 1's length byte (see st0601Checksum); 0 when missing
    std::size_t size = 0;            ///< bytes of the packet, key to end of value

    /// Platform pitch and roll: the full-range tags (90, 91) when present, else tags 6, 7.
    std::optional<double> pitchDeg() const { return platformPitchFullDeg ? platformPitchFullDeg : platformPitchDeg; }
    std::optional<double> rollDeg() const { return platformRollFullDeg ? platformRollFullDeg : platformRollDeg; }
    /// Sensor height above the ellipsoid: tag 104, else tag 75.
    std::optional<double> sensorHeightAboveEllipsoid() const {
        return sensorEllipsoidHeightExtended ? sensorEllipsoidHeightExtended : sensorEllipsoidHeight;
    }
    /// Corner `i` (0..3: upper left, upper right, lower right, lower left): the full-precision
    /// corner (82..89) when present, else frame centre + offset (23/24 + 26..33), else nothing.
    std::optional<LatLonDeg> corner(int i) const;
    bool hasError(uint32_t tag) const;
};

/// ST 0601 tag 1: the 16-bit running sum over `bytes` (from the first key byte through the
/// checksum item's tag and length bytes), each even-indexed byte added as the high byte of a
/// 16-bit word and each odd one as the low byte, modulo 2^16.
uint16_t st0601Checksum(Bytes bytes);

/// Decodes the packet that starts at `bytes[0]` (the ST 0601 key). Bytes after the packet are
/// ignored (`size` says where it ends). Errors: not the ST 0601 key, a bad BER length, a packet
/// that runs past `bytes` or over kMaxSt0601PacketBytes, a malformed item. Messages name byte
/// offsets relative to `bytes` plus `base` (the packet's offset in its file). Any thread.
Result<St0601Packet> decodeSt0601(Bytes bytes, std::size_t base = 0);

/// The name `orbis info` gives a tag ("sensorLatitudeDeg"), or "" for tags not decoded here.
const char* st0601TagName(uint32_t tag);

/// One JSON object on one line: `offset`, `checksum` (`verdict`, `stored`, `computed` as hex),
/// every decoded field by the name st0601TagName gives it (timestamps also as ISO 8601),
/// `errorTags`, `warnings`, and `otherTags` as {"tag": n, "hex": "..."}.
std::string st0601JsonLine(const St0601Packet& packet, uint64_t offset);

}  // namespace orbis::fmv
