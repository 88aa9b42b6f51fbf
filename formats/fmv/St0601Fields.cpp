#include "formats/fmv/St0601Fields.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::fmv::detail {
namespace {

using P = St0601Packet;

// ST 0601 maps a fixed-size integer linearly onto a range: unsigned ints onto [min, max] by
// 2^(8n) - 1 steps; signed ints onto [-max, max] by ±(2^(8n-1) - 1), which leaves INT_MIN
// (0x8000, 0x80000000) outside the range: ST 0601 names it "error"/"out of range"/"N/A
// (off-earth)" where it defines it, and it is "reserved" elsewhere, so it is never a number.
constexpr Field uns(uint32_t tag, const char* name, int bytes, double min, double max, Number m) {
    return Field{tag, name, Kind::Unsigned, bytes, min, max, m};
}
constexpr Field sig(uint32_t tag, const char* name, int bytes, double max, Number m) {
    return Field{tag, name, Kind::Signed, bytes, -max, max, m};
}
constexpr Field sigCorner(uint32_t tag, const char* name, int bytes, double max, Corners c, int i) {
    return Field{tag, name, Kind::Signed, bytes, -max, max, nullptr, c, i};
}
constexpr Field text(uint32_t tag, const char* name, Text t) {
    return Field{tag, name, Kind::Text, 0, 0.0, 0.0, nullptr, nullptr, 0, t};
}

// Ranges and sizes: MISB ST 0601.17, the tag's "Mapping" row.
constexpr Field kFields[] = {
    Field{2, "precisionTimeUs", Kind::Timestamp, 8},                           // uint64 µs since 1970
    text(3, "missionId", &P::missionId),
    text(4, "platformTailNumber", &P::platformTailNumber),
    uns(5, "platformHeadingDeg", 2, 0.0, 360.0, &P::platformHeadingDeg),     // uint16 → 0..360°
    sig(6, "platformPitchDeg", 2, 20.0, &P::platformPitchDeg),               // int16 → ±20°, 0x8000 out of range
    sig(7, "platformRollDeg", 2, 50.0, &P::platformRollDeg),                 // int16 → ±50°, 0x8000 out of range
    text(10, "platformDesignation", &P::platformDesignation),
    text(11, "imageSourceSensor", &P::imageSourceSensor),
    text(12, "imageCoordinateSystem", &P::imageCoordinateSystem),
    sig(13, "sensorLatitudeDeg", 4, 90.0, &P::sensorLatitudeDeg),            // int32 → ±90°, 0x80000000 error
    sig(14, "sensorLongitudeDeg", 4, 180.0, &P::sensorLongitudeDeg),         // int32 → ±180°, 0x80000000 error
    uns(15, "sensorTrueAltitude", 2, -900.0, 19000.0, &P::sensorTrueAltitude),   // uint16 → -900..19000 m
    uns(16, "horizontalFovDeg", 2, 0.0, 180.0, &P::horizontalFovDeg),        // uint16 → 0..180°
    uns(17, "verticalFovDeg", 2, 0.0, 180.0, &P::verticalFovDeg),            // uint16 → 0..180°
    uns(18, "sensorRelativeAzimuthDeg", 4, 0.0, 360.0, &P::sensorRelativeAzimuthDeg),   // uint32 → 0..360°
    sig(19, "sensorRelativeElevationDeg", 4, 180.0, &P::sensorRelativeElevationDeg),    // int32 → ±180°
    uns(20, "sensorRelativeRollDeg", 4, 0.0, 360.0, &P::sensorRelativeRollDeg),         // uint32 → 0..360°
    uns(21, "slantRange", 4, 0.0, 5.0e6, &P::slantRange),                    // uint32 → 0..5 000 000 m
    uns(22, "targetWidth", 2, 0.0, 10000.0, &P::targetWidth),                // uint16 → 0..10 000 m
    sig(23, "frameCenterLatitudeDeg", 4, 90.0, &P::frameCenterLatitudeDeg),  // int32 → ±90°, 0x80000000 N/A
    sig(24, "frameCenterLongitudeDeg", 4, 180.0, &P::frameCenterLongitudeDeg),
    uns(25, "frameCenterElevation", 2, -900.0, 19000.0, &P::frameCenterElevation),
    // int16 → ±0.075° from the frame centre, 0x8000 N/A (off-earth)
    sigCorner(26, "offsetCornerLatitudeDeg1", 2, 0.075, &P::offsetCornerLatitudeDeg, 0),
    sigCorner(27, "offsetCornerLongitudeDeg1", 2, 0.075, &P::offsetCornerLongitudeDeg, 0),
    sigCorner(28, "offsetCornerLatitudeDeg2", 2, 0.075, &P::offsetCornerLatitudeDeg, 1),
    sigCorner(29, "offsetCornerLongitudeDeg2", 2, 0.075, &P::offsetCornerLongitudeDeg, 1),
    sigCorner(30, "offsetCornerLatitudeDeg3", 2, 0.075, &P::offsetCornerLatitudeDeg, 2),
    sigCorner(31, "offsetCornerLongitudeDeg3", 2, 0.075, &P::offsetCornerLongitudeDeg, 2),
    sigCorner(32, "offsetCornerLatitudeDeg4", 2, 0.075, &P::offsetCornerLatitudeDeg, 3),
    sigCorner(33, "offsetCornerLongitudeDeg4", 2, 0.075, &P::offsetCornerLongitudeDeg, 3),
    Field{65, "uasLsVersion", Kind::Integer, 1},                               // uint8
    uns(75, "sensorEllipsoidHeight", 2, -900.0, 19000.0, &P::sensorEllipsoidHeight),
    // int32 → ±90° / ±180°, 0x80000000 N/A (off-earth)
    sigCorner(82, "cornerLatitudeDeg1", 4, 90.0, &P::cornerLatitudeDeg, 0),
    sigCorner(83, "cornerLongitudeDeg1", 4, 180.0, &P::cornerLongitudeDeg, 0),
    sigCorner(84, "cornerLatitudeDeg2", 4, 90.0, &P::cornerLatitudeDeg, 1),
    sigCorner(85, "cornerLongitudeDeg2", 4, 180.0, &P::cornerLongitudeDeg, 1),
    sigCorner(86, "cornerLatitudeDeg3", 4, 90.0, &P::cornerLatitudeDeg, 2),
    sigCorner(87, "cornerLongitudeDeg3", 4, 180.0, &P::cornerLongitudeDeg, 2),
    sigCorner(88, "cornerLatitudeDeg4", 4, 90.0, &P::cornerLatitudeDeg, 3),
    sigCorner(89, "cornerLongitudeDeg4", 4, 180.0, &P::cornerLongitudeDeg, 3),
    sig(90, "platformPitchFullDeg", 4, 90.0, &P::platformPitchFullDeg),      // int32 → ±90°, 0x80000000 out of range
    sig(91, "platformRollFullDeg", 4, 90.0, &P::platformRollFullDeg),        // int32 → ±90°, 0x80000000 out of range
    // IMAPB(-900, 40000), variable length (ST 0601 tag 104, ST 1201)
    Field{104, "sensorEllipsoidHeightExtended", Kind::Imapb, 8, -900.0, 40000.0, &P::sensorEllipsoidHeightExtended},
};

double twoPow(int e) { return std::ldexp(1.0, e); }

/// ST 1201 §8.1.2 parameters of IMAPB(a, b) in `n` bytes.
struct ImapbScale {
    int bPow = 0, dPow = 0;
    double sF = 0.0, sR = 0.0, zOffset = 0.0;
    ImapbScale(double a, double b, std::size_t n) {
        bPow = int(std::ceil(std::log2(b - a)));
        dPow = int(8 * n) - 1;
        sF = twoPow(dPow - bPow);
        sR = twoPow(bPow - dPow);
        // A range that straddles zero is shifted so that zero maps onto an integer exactly.
        if (a < 0.0 && b > 0.0) zOffset = sF * a - std::floor(sF * a);
    }
};

}  // namespace

std::span<const Field> st0601Fields() { return kFields; }

const Field* findField(uint32_t tag) {
    // Tags are < 256 here: a direct index built once (thread-safe static initialisation).
    static const auto index = [] {
        std::array<int16_t, 256> idx;
        idx.fill(-1);
        for (std::size_t i = 0; i < std::size(kFields); ++i) idx[kFields[i].tag] = int16_t(i);
        return idx;
    }();
    if (tag >= index.size() || index[tag] < 0) return nullptr;
    return &kFields[std::size_t(index[tag])];
}

double Field::lsb(std::size_t n) const {
    switch (kind) {
    case Kind::Unsigned: return (max - min) / (twoPow(int(8 * n)) - 1.0);
    case Kind::Signed: return max / (twoPow(int(8 * n) - 1) - 1.0);
    case Kind::Imapb: return ImapbScale(min, max, n).sR;
    default: return 0.0;
    }
}

Mapped imapbDecode(double a, double b, uint64_t y, std::size_t n) {
    if (n < 1 || n > 8) return {std::nullopt, true};
    // ST 1201: an integer with its top bit set is a special value (±infinity, NaN, below
    // minimum, user defined): never a number.
    if ((y >> (8 * n - 1)) & 1) return {std::nullopt, true};
    const ImapbScale s(a, b, n);
    const double x = s.sR * (double(y) - s.zOffset) + a;
    if (x > b + 0.5 * s.sR) return {std::nullopt, true};   // above the range's top: out of range
    return {std::min(x, b), false};
}

uint64_t imapbEncode(double a, double b, double x, std::size_t n) {
    n = std::clamp<std::size_t>(n, 1, 8);
    if (std::isnan(x)) return uint64_t(0b11010) << (8 * n - 5);   // ST 1201 quiet NaN pattern 11010
    const ImapbScale s(a, b, n);
    x = std::clamp(x, a, b);
    return uint64_t(std::floor(s.sF * (x - a) + s.zOffset));
}

Mapped decodeNumber(const Field& f, Bytes value) {
    const std::size_t n = value.size();
    const uint64_t y = bigEndian(value);
    switch (f.kind) {
    case Kind::Unsigned: return {f.min + double(y) * (f.max - f.min) / (twoPow(int(8 * n)) - 1.0), false};
    case Kind::Signed: {
        const uint64_t signBit = uint64_t(1) << (8 * n - 1);
        if (y == signBit) return {std::nullopt, true};   // INT_MIN: the error value
        const int64_t s = (y & signBit) ? int64_t(y) - int64_t(signBit) - int64_t(signBit) : int64_t(y);
        return {double(s) * f.max / (twoPow(int(8 * n) - 1) - 1.0), false};
    }
    case Kind::Imapb: return imapbDecode(f.min, f.max, y, n);
    default: return {double(y), false};
    }
}

void encodeNumber(const Field& f, std::optional<double> value, std::vector<uint8_t>& out, int imapbBytes) {
    const bool bad = !value || std::isnan(*value);
    switch (f.kind) {
    case Kind::Unsigned: {
        const double steps = twoPow(8 * f.bytes) - 1.0;
        const double x = bad ? f.min : std::clamp(*value, f.min, f.max);
        appendBigEndian(out, uint64_t(std::llround((x - f.min) / (f.max - f.min) * steps)), f.bytes);
        return;
    }
    case Kind::Signed: {
        const double steps = twoPow(8 * f.bytes - 1) - 1.0;
        const uint64_t signBit = uint64_t(1) << (8 * f.bytes - 1);
        // Out of range (beyond half a step past the end) is written as the error value.
        if (bad || std::abs(*value) > f.max * (1.0 + 0.5 / steps)) {
            appendBigEndian(out, signBit, f.bytes);
            return;
        }
        const int64_t s = std::clamp<int64_t>(std::llround(*value / f.max * steps), -int64_t(steps), int64_t(steps));
        appendBigEndian(out, uint64_t(s), f.bytes);   // two's complement: the low bytes
        return;
    }
    case Kind::Imapb: {
        const std::size_t n = std::size_t(std::clamp(imapbBytes, 1, 8));
        appendBigEndian(out, imapbEncode(f.min, f.max, bad ? std::numeric_limits<double>::quiet_NaN() : *value, n), int(n));
        return;
    }
    default: return;
    }
}

}  // namespace orbis::fmv::detail
