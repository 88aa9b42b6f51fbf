// Layered LAZ, item POINT14 (version 3): the point record of LAS 1.4 formats 6-10 in nine layers
// (returns and XY, Z, classification, flags, intensity, scan angle, user data, point source, GPS
// time), each point predicted from the last point of its scanner channel. See LazLayered.cpp.

#include "layers/points/LasBytes.h"
#include "layers/points/LazLayeredItems.h"

#include <array>
#include <cstring>
#include <memory>

namespace orbis::points::laz::detail {
namespace {

// ---------------------------------------------------------------------------------------------
// POINT14

// The context of the x difference's median, [number of returns][return number]: the common
// combinations (1 <= r <= n) fold into 6 classes, and the invalid ones (r or n of 0, r > n) are
// spread over the same classes so that files which fill the fields oddly still compress.
// A format constant (LASzip's number_return_map_6ctx): it must not change.
constexpr uint8_t kReturnMap[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5},
    {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3},
    {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5},
};

/// The context of the last z, by how deep the return lies in its pulse: |n - r|, capped at 7
/// (LASzip's number_return_level_8ctx is exactly this table).
constexpr uint32_t returnLevel(uint32_t n, uint32_t r) {
    const uint32_t d = n > r ? n - r : r - n;
    return d < 7 ? d : 7;
}

// GPS time multipliers: a difference is coded as a multiple (-10..500) of the sequence's last
// difference; the symbols past the multipliers start a new sequence or switch to another one.
constexpr int32_t kGpsMulti = 500, kGpsMultiMinus = -10;
constexpr uint32_t kGpsCodeFull = uint32_t(kGpsMulti - kGpsMultiMinus + 1);   // 511: a new sequence
constexpr uint32_t kGpsMultiSymbols = kGpsCodeFull + 4;                      // and 3 switches

/// A POINT14 record's fields as the coder predicts them.
struct Point14 {
    int32_t x = 0, y = 0, z = 0;
    uint16_t intensity = 0;
    uint8_t returnNumber = 0, returnCount = 0;
    uint8_t flags = 0;   // edge of flight line << 5 | scan direction << 4 | classification flags
    uint8_t channel = 0;
    uint8_t classification = 0, userData = 0;
    int16_t scanAngle = 0;
    uint16_t pointSource = 0;
    uint64_t gpsTime = 0;          // the double's bits: compared and differenced as an integer
    bool gpsTimeChanged = false;   // whether this point's time differed from its predecessor's
};

Point14 unpackPoint14(const uint8_t* p) {
    Point14 q;
    q.x = bytes::get<int32_t>(p);
    q.y = bytes::get<int32_t>(p + 4);
    q.z = bytes::get<int32_t>(p + 8);
    q.intensity = bytes::get<uint16_t>(p + 12);
    q.returnNumber = p[14] & 15;
    q.returnCount = p[14] >> 4;
    q.flags = uint8_t((p[15] & 15) | ((p[15] >> 2) & 0x30));
    q.channel = (p[15] >> 4) & 3;
    q.classification = p[16];
    q.userData = p[17];
    q.scanAngle = bytes::get<int16_t>(p + 18);
    q.pointSource = bytes::get<uint16_t>(p + 20);
    q.gpsTime = bytes::get<uint64_t>(p + 22);
    return q;
}

void packPoint14(const Point14& q, uint8_t* p) {
    bytes::put(p, q.x);
    bytes::put(p + 4, q.y);
    bytes::put(p + 8, q.z);
    bytes::put(p + 12, q.intensity);
    p[14] = uint8_t(q.returnNumber | (q.returnCount << 4));
    p[15] = uint8_t((q.flags & 15) | (q.channel << 4) | ((q.flags & 0x30) << 2));
    p[16] = q.classification;
    p[17] = q.userData;
    bytes::put(p + 18, q.scanAngle);
    bytes::put(p + 20, q.pointSource);
    bytes::put(p + 22, q.gpsTime);
}

/// The per-channel state of POINT14: the last point, the predictors and every model.
struct Point14Context {
    Point14 last;
    std::array<uint16_t, 8> lastIntensity{};   // by return kind and GPS time change
    std::array<int32_t, 8> lastZ{};            // by return level
    std::array<Median5, 12> dxMedian, dyMedian;

    // channel_returns_XY layer
    std::vector<SymbolModel> changes = std::vector<SymbolModel>(8, SymbolModel(128));
    SymbolModel channelStep{3};
    std::array<std::unique_ptr<SymbolModel>, 16> returnCounts, returnNumbers;
    SymbolModel returnStepSameTime{13};
    IntegerCodec dx{32, 2}, dy{32, 22};
    // the attribute layers
    IntegerCodec z{32, 20};
    std::array<std::unique_ptr<SymbolModel>, 64> classifications, flags, userData;
    IntegerCodec intensity{16, 4}, scanAngle{16, 2}, pointSource{16, 1};
    SymbolModel gpsMulti{kGpsMultiSymbols}, gpsZeroDiff{5};
    IntegerCodec gps{32, 9};
    // GPS time: up to four interleaved sequences, each with its last time and difference
    uint32_t gpsLast = 0, gpsNext = 0;
    std::array<uint64_t, 4> gpsTimes{};
    std::array<int32_t, 4> gpsDiffs{}, gpsExtremes{};

    explicit Point14Context(const Point14& from) : last(from) {
        last.gpsTimeChanged = false;
        lastIntensity.fill(from.intensity);
        lastZ.fill(from.z);
        gpsTimes[0] = from.gpsTime;
    }

    /// The context of the change mask: the last point first (1) and/or last (2) of its pulse (the
    /// reverse of returnKind's numbering, as LASzip has it), + 4 if its GPS time changed.
    uint32_t lastReturnKind() const {
        return (last.returnNumber == 1 ? 1u : 0u) + (last.returnNumber >= last.returnCount ? 2u : 0u) + (last.gpsTimeChanged ? 4u : 0u);
    }
    /// A difference stayed extreme for four points in a row: it becomes the new reference.
    void countExtreme(int32_t diff) {
        if (++gpsExtremes[gpsLast] > 3) {
            gpsDiffs[gpsLast] = diff;
            gpsExtremes[gpsLast] = 0;
        }
    }
};


/// Return kind of a point: first (2) and/or last (1) of its pulse.
inline uint32_t returnKind(uint32_t r, uint32_t n) { return (r == 1 ? 2u : 0u) + (r >= n ? 1u : 0u); }
inline uint32_t xyContext(uint32_t k) { return k < 20 ? (k & ~1u) : 20; }
inline uint32_t zContext(uint32_t k) { return k < 18 ? (k & ~1u) : 18; }


// ---------------------------------------------------------------------------------------------
// POINT14 decoding and encoding

class Point14Decoder final : public ItemDecoder {
public:
    explicit Point14Decoder(InLayer* layers) : layers_(layers) {}

    void init(const uint8_t* first, uint32_t& channel) override {
        const Point14 p = unpackPoint14(first);
        current_ = p.channel;
        contexts_[current_] = std::make_unique<Point14Context>(p);
        channel = current_;
    }

    void decode(uint8_t* item, uint32_t& channel) override;

private:
    void readGpsTime(Point14Context& c, ArithmeticDecoder& dec);
    static void startSequence(Point14Context& c, ArithmeticDecoder& dec) {
        c.gpsNext = (c.gpsNext + 1) & 3;
        const uint32_t high = uint32_t(c.gps.decompress(dec, int32_t(c.gpsTimes[c.gpsLast] >> 32), 8));
        c.gpsTimes[c.gpsNext] = (uint64_t(high) << 32) | dec.readInt();
        c.gpsLast = c.gpsNext;
        c.gpsDiffs[c.gpsLast] = 0;
        c.gpsExtremes[c.gpsLast] = 0;
    }

    InLayer* layers_;
    std::array<std::unique_ptr<Point14Context>, 4> contexts_;
    uint32_t current_ = 0;
};

void Point14Decoder::decode(uint8_t* item, uint32_t& channel) {
    ArithmeticDecoder& xy = layers_[kXY].dec;
    Point14Context* c = contexts_[current_].get();
    // What changed, in the context of the previous point (whatever its channel).
    const uint32_t changes = xy.decodeSymbol(c->changes[c->lastReturnKind()]);
    if (changes & 64) {
        const uint32_t next = (current_ + xy.decodeSymbol(c->channelStep) + 1) & 3;
        if (!contexts_[next]) contexts_[next] = std::make_unique<Point14Context>(c->last);
        current_ = next;
        c = contexts_[next].get();
        c->last.channel = uint8_t(next);
        channel = next;
    }
    Point14& p = c->last;
    const uint32_t gpsChanged = (changes >> 4) & 1;

    if (changes & 4) p.returnCount = uint8_t(xy.decodeSymbol(lazyModel(c->returnCounts[p.returnCount], 16)));
    switch (changes & 3) {
    case 0: break;
    case 1: p.returnNumber = (p.returnNumber + 1) & 15; break;
    case 2: p.returnNumber = (p.returnNumber + 15) & 15; break;
    default:
        if (gpsChanged) p.returnNumber = uint8_t(xy.decodeSymbol(lazyModel(c->returnNumbers[p.returnNumber], 16)));
        else p.returnNumber = uint8_t((p.returnNumber + xy.decodeSymbol(c->returnStepSameTime) + 2) & 15);
        break;
    }
    const uint32_t n = p.returnCount, r = p.returnNumber;
    const uint32_t single = n == 1 ? 1 : 0, kind = returnKind(r, n);
    const uint32_t median = (uint32_t(kReturnMap[n][r]) << 1) | gpsChanged;

    const int32_t dx = c->dx.decompress(xy, c->dxMedian[median].get(), single);
    p.x = wrapAdd(p.x, dx);
    c->dxMedian[median].add(dx);
    const int32_t dy = c->dy.decompress(xy, c->dyMedian[median].get(), single + xyContext(c->dx.k()));
    p.y = wrapAdd(p.y, dy);
    c->dyMedian[median].add(dy);

    if (layers_[kZ].active) {
        const uint32_t level = returnLevel(n, r);
        p.z = c->z.decompress(layers_[kZ].dec, c->lastZ[level], single + zContext((c->dx.k() + c->dy.k()) / 2));
        c->lastZ[level] = p.z;
    }
    if (layers_[kClassification].active) {
        const uint32_t ctx = ((p.classification & 0x1Fu) << 1) + (kind == 3 ? 1 : 0);
        p.classification = uint8_t(layers_[kClassification].dec.decodeSymbol(lazyModel(c->classifications[ctx], 256)));
    }
    if (layers_[kFlags].active) p.flags = uint8_t(layers_[kFlags].dec.decodeSymbol(lazyModel(c->flags[p.flags], 64)));
    if (layers_[kIntensity].active) {
        const uint32_t slot = (kind << 1) | gpsChanged;
        p.intensity = uint16_t(c->intensity.decompress(layers_[kIntensity].dec, c->lastIntensity[slot], kind));
        c->lastIntensity[slot] = p.intensity;
    }
    if (layers_[kScanAngle].active && (changes & 8)) p.scanAngle = int16_t(c->scanAngle.decompress(layers_[kScanAngle].dec, p.scanAngle, gpsChanged));
    if (layers_[kUserData].active) p.userData = uint8_t(layers_[kUserData].dec.decodeSymbol(lazyModel(c->userData[p.userData >> 2], 256)));
    if (layers_[kPointSource].active && (changes & 32)) p.pointSource = uint16_t(c->pointSource.decompress(layers_[kPointSource].dec, p.pointSource));
    if (layers_[kGpsTime].active && gpsChanged) {
        readGpsTime(*c, layers_[kGpsTime].dec);
        p.gpsTime = c->gpsTimes[c->gpsLast];
    }
    packPoint14(p, item);
    p.gpsTimeChanged = gpsChanged != 0;
}

void Point14Decoder::readGpsTime(Point14Context& c, ArithmeticDecoder& dec) {
    // A valid stream switches sequence at most once per point; the cap only stops a corrupt one.
    for (int hop = 0; hop < 4; ++hop) {
        const uint32_t s = c.gpsLast;
        if (c.gpsDiffs[s] == 0) {   // no reference difference yet
            const uint32_t sym = dec.decodeSymbol(c.gpsZeroDiff);
            if (sym == 0) {
                const int32_t diff = c.gps.decompress(dec, 0, 0);
                c.gpsDiffs[s] = diff;
                c.gpsTimes[s] += uint64_t(int64_t(diff));
                c.gpsExtremes[s] = 0;
            } else if (sym == 1) {
                startSequence(c, dec);
            } else {
                c.gpsLast = (s + sym - 1) & 3;
                continue;
            }
            return;
        }
        const uint32_t multi = dec.decodeSymbol(c.gpsMulti);
        const int32_t ref = c.gpsDiffs[s];
        if (multi < kGpsCodeFull) {
            int32_t diff;
            if (multi == 1) {
                diff = c.gps.decompress(dec, ref, 1);
                c.gpsExtremes[s] = 0;
            } else if (multi == 0) {
                diff = c.gps.decompress(dec, 0, 7);
                c.countExtreme(diff);
            } else if (multi < uint32_t(kGpsMulti)) {
                diff = c.gps.decompress(dec, wrapMul(int32_t(multi), ref), multi < 10 ? 2 : 3);
            } else if (multi == uint32_t(kGpsMulti)) {
                diff = c.gps.decompress(dec, wrapMul(kGpsMulti, ref), 4);
                c.countExtreme(diff);
            } else {
                const int32_t negative = kGpsMulti - int32_t(multi);
                if (negative > kGpsMultiMinus) {
                    diff = c.gps.decompress(dec, wrapMul(negative, ref), 5);
                } else {
                    diff = c.gps.decompress(dec, wrapMul(kGpsMultiMinus, ref), 6);
                    c.countExtreme(diff);
                }
            }
            c.gpsTimes[s] += uint64_t(int64_t(diff));
            return;
        }
        if (multi == kGpsCodeFull) {
            startSequence(c, dec);
            return;
        }
        c.gpsLast = (s + multi - kGpsCodeFull) & 3;
    }
}

class Point14Encoder final : public ItemEncoder {
public:
    explicit Point14Encoder(OutLayer* layers) : layers_(layers) {}

    void init(const uint8_t* first, uint32_t& channel) override {
        const Point14 p = unpackPoint14(first);
        current_ = p.channel;
        contexts_[current_] = std::make_unique<Point14Context>(p);
        channel = current_;
    }

    void encode(const uint8_t* item, uint32_t& channel) override;

private:
    void writeGpsTime(Point14Context& c, ArithmeticEncoder& enc, uint64_t time);
    static void startSequence(Point14Context& c, ArithmeticEncoder& enc, uint64_t time) {
        c.gps.compress(enc, int32_t(c.gpsTimes[c.gpsLast] >> 32), int32_t(time >> 32), 8);
        enc.writeInt(uint32_t(time));
        c.gpsNext = (c.gpsNext + 1) & 3;
        c.gpsLast = c.gpsNext;
        c.gpsDiffs[c.gpsLast] = 0;
        c.gpsExtremes[c.gpsLast] = 0;
    }
    /// The other sequence (1..3 steps on) whose last time is within 32 bits of `time`, or 0.
    static uint32_t nearSequence(const Point14Context& c, uint64_t time) {
        for (uint32_t i = 1; i < 4; ++i) {
            const int64_t d = int64_t(time - c.gpsTimes[(c.gpsLast + i) & 3]);
            if (d == int64_t(int32_t(d))) return i;
        }
        return 0;
    }

    OutLayer* layers_;
    std::array<std::unique_ptr<Point14Context>, 4> contexts_;
    uint32_t current_ = 0;
};

void Point14Encoder::encode(const uint8_t* item, uint32_t& channel) {
    const Point14 p = unpackPoint14(item);
    ArithmeticEncoder& xy = layers_[kXY].enc;
    Point14Context* c = contexts_[current_].get();
    const uint32_t lastKind = c->lastReturnKind();
    // The point is compared with the last point of its own channel; a channel not seen yet starts
    // from the previous point.
    const Point14* ref = &c->last;
    if (p.channel != current_ && contexts_[p.channel]) ref = &contexts_[p.channel]->last;
    const bool sourceChanged = p.pointSource != ref->pointSource;
    // Bitwise: LASzip compares the doubles, which drops a -0.0 after a 0.0 (and codes a repeated NaN
    // as a change); this differs from it only there, and any decoder reads both.
    const bool gpsChanged = p.gpsTime != ref->gpsTime;
    const bool angleChanged = p.scanAngle != ref->scanAngle;
    const uint32_t lastN = ref->returnCount, lastR = ref->returnNumber;
    const uint32_t n = p.returnCount, r = p.returnNumber;
    uint32_t changes = (p.channel != current_ ? 64u : 0u) | (sourceChanged ? 32u : 0u) | (gpsChanged ? 16u : 0u) | (angleChanged ? 8u : 0u) |
                       (n != lastN ? 4u : 0u);
    if (r != lastR) changes |= r == ((lastR + 1) & 15) ? 1u : (r == ((lastR + 15) & 15) ? 2u : 3u);
    xy.encodeSymbol(c->changes[lastKind], changes);
    if (changes & 64) {
        xy.encodeSymbol(c->channelStep, (p.channel - current_ + 3) & 3);
        if (!contexts_[p.channel]) contexts_[p.channel] = std::make_unique<Point14Context>(c->last);
        current_ = p.channel;
        c = contexts_[current_].get();
        channel = current_;
    }
    Point14& last = c->last;

    if (changes & 4) xy.encodeSymbol(lazyModel(c->returnCounts[lastN], 16), n);
    if ((changes & 3) == 3) {
        if (gpsChanged) xy.encodeSymbol(lazyModel(c->returnNumbers[lastR], 16), r);
        else xy.encodeSymbol(c->returnStepSameTime, (r - lastR + 14) & 15);
    }
    const uint32_t single = n == 1 ? 1 : 0, kind = returnKind(r, n);
    const uint32_t median = (uint32_t(kReturnMap[n][r]) << 1) | (gpsChanged ? 1u : 0u);

    const int32_t dx = int32_t(uint32_t(p.x) - uint32_t(last.x));
    c->dx.compress(xy, c->dxMedian[median].get(), dx, single);
    c->dxMedian[median].add(dx);
    const int32_t dy = int32_t(uint32_t(p.y) - uint32_t(last.y));
    c->dy.compress(xy, c->dyMedian[median].get(), dy, single + xyContext(c->dx.k()));
    c->dyMedian[median].add(dy);

    const uint32_t level = returnLevel(n, r);
    c->z.compress(layers_[kZ].enc, c->lastZ[level], p.z, single + zContext((c->dx.k() + c->dy.k()) / 2));
    c->lastZ[level] = p.z;

    const uint32_t classContext = ((last.classification & 0x1Fu) << 1) + (kind == 3 ? 1 : 0);
    layers_[kClassification].enc.encodeSymbol(lazyModel(c->classifications[classContext], 256), p.classification);
    layers_[kClassification].changed |= p.classification != last.classification;

    layers_[kFlags].enc.encodeSymbol(lazyModel(c->flags[last.flags], 64), p.flags);
    layers_[kFlags].changed |= p.flags != last.flags;

    const uint32_t slot = (kind << 1) | (gpsChanged ? 1u : 0u);
    c->intensity.compress(layers_[kIntensity].enc, c->lastIntensity[slot], p.intensity, kind);
    c->lastIntensity[slot] = p.intensity;
    layers_[kIntensity].changed |= p.intensity != last.intensity;

    if (angleChanged) {
        c->scanAngle.compress(layers_[kScanAngle].enc, last.scanAngle, p.scanAngle, gpsChanged ? 1 : 0);
        layers_[kScanAngle].changed = true;
    }

    layers_[kUserData].enc.encodeSymbol(lazyModel(c->userData[last.userData >> 2], 256), p.userData);
    layers_[kUserData].changed |= p.userData != last.userData;

    if (sourceChanged) {
        c->pointSource.compress(layers_[kPointSource].enc, last.pointSource, p.pointSource);
        layers_[kPointSource].changed = true;
    }
    if (gpsChanged) {
        writeGpsTime(*c, layers_[kGpsTime].enc, p.gpsTime);
        layers_[kGpsTime].changed = true;
    }
    last = p;
    last.gpsTimeChanged = gpsChanged;
}

void Point14Encoder::writeGpsTime(Point14Context& c, ArithmeticEncoder& enc, uint64_t time) {
    for (;;) {
        const uint32_t s = c.gpsLast;
        const int64_t diff64 = int64_t(time - c.gpsTimes[s]);
        const int32_t diff = int32_t(diff64);
        const bool fits = diff64 == int64_t(diff);
        const int32_t ref = c.gpsDiffs[s];
        if (!fits) {
            // Maybe the time continues another sequence (interleaved flight lines).
            if (const uint32_t i = nearSequence(c, time)) {
                enc.encodeSymbol(ref == 0 ? c.gpsZeroDiff : c.gpsMulti, ref == 0 ? i + 1 : kGpsCodeFull + i);
                c.gpsLast = (s + i) & 3;
                continue;
            }
            enc.encodeSymbol(ref == 0 ? c.gpsZeroDiff : c.gpsMulti, ref == 0 ? 1 : kGpsCodeFull);
            startSequence(c, enc, time);
        } else if (ref == 0) {
            enc.encodeSymbol(c.gpsZeroDiff, 0);
            c.gps.compress(enc, 0, diff, 0);
            c.gpsDiffs[s] = diff;
            c.gpsExtremes[s] = 0;
        } else {
            // The multiplier as LASzip rounds it (in float; out of int32's range reads as INT32_MIN
            // as x86 converts it).
            const float q = float(diff) / float(ref);
            const float rounded = q >= 0 ? q + 0.5f : q - 0.5f;
            const int32_t multi = (rounded >= 2147483648.0f || rounded < -2147483648.0f) ? INT32_MIN : int32_t(rounded);
            if (multi == 1) {
                enc.encodeSymbol(c.gpsMulti, 1);
                c.gps.compress(enc, ref, diff, 1);
                c.gpsExtremes[s] = 0;
            } else if (multi > 0 && multi < kGpsMulti) {
                enc.encodeSymbol(c.gpsMulti, uint32_t(multi));
                c.gps.compress(enc, wrapMul(multi, ref), diff, multi < 10 ? 2 : 3);
            } else if (multi >= kGpsMulti) {
                enc.encodeSymbol(c.gpsMulti, uint32_t(kGpsMulti));
                c.gps.compress(enc, wrapMul(kGpsMulti, ref), diff, 4);
                c.countExtreme(diff);
            } else if (multi < 0 && multi > kGpsMultiMinus) {
                enc.encodeSymbol(c.gpsMulti, uint32_t(kGpsMulti - multi));
                c.gps.compress(enc, wrapMul(multi, ref), diff, 5);
            } else if (multi < 0) {
                enc.encodeSymbol(c.gpsMulti, uint32_t(kGpsMulti - kGpsMultiMinus));
                c.gps.compress(enc, wrapMul(kGpsMultiMinus, ref), diff, 6);
                c.countExtreme(diff);
            } else {
                enc.encodeSymbol(c.gpsMulti, 0);
                c.gps.compress(enc, 0, diff, 7);
                c.countExtreme(diff);
            }
        }
        c.gpsTimes[c.gpsLast] = time;
        return;
    }
}


}  // namespace

std::unique_ptr<ItemDecoder> makePoint14Decoder(InLayer* layers) { return std::make_unique<Point14Decoder>(layers); }
std::unique_ptr<ItemEncoder> makePoint14Encoder(OutLayer* layers) { return std::make_unique<Point14Encoder>(layers); }

}  // namespace orbis::points::laz::detail
