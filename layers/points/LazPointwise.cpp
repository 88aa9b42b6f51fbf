// Point-wise LAZ chunks (compressors 1 and 2): item coders of versions 1 and 2 for point formats
// 0-5, all items sharing one arithmetic stream, point after point. The first point of a chunk is
// stored raw; each item predicts its next value from the previous point.

#include "layers/points/LazChunks.h"
#include "layers/points/LasBytes.h"
#include "layers/points/LazCoder.h"

#include <array>
#include <cstring>
#include <memory>
#include <optional>

namespace orbis::points::laz::detail {
namespace {

class ItemDecoder {
public:
    virtual ~ItemDecoder() = default;
    /// The chunk's first point (raw) starts the item's state.
    virtual void init(const uint8_t* first) = 0;
    virtual void read(ArithmeticDecoder& dec, uint8_t* item) = 0;
};

/// Models created on first use (LASzip's 256-entry tables of per-byte-value contexts).
class LazyModels {
public:
    SymbolModel& operator[](uint8_t i) {
        if (!models_[i]) models_[i] = std::make_unique<SymbolModel>(256);
        return *models_[i];
    }
    void reset() {
        for (auto& m : models_)
            if (m) m->reset();
    }

private:
    std::array<std::unique_ptr<SymbolModel>, 256> models_;
};

// Contexts of (number of returns n, return number r) for version 2: a map into 16 classes for
// the x/y medians and intensity, and the level of penetration (|n - r|, capped) for heights.
constexpr uint8_t kReturnMap[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8}, {14, 0, 1, 3, 6, 10, 10, 9},   {13, 1, 2, 4, 7, 11, 11, 10},
    {12, 3, 4, 5, 8, 12, 12, 11},   {11, 6, 7, 8, 9, 13, 13, 12},  {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15}};
constexpr uint8_t kReturnLevel[8][8] = {
    {0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 1, 2, 3, 4, 5, 6}, {2, 1, 0, 1, 2, 3, 4, 5}, {3, 2, 1, 0, 1, 2, 3, 4},
    {4, 3, 2, 1, 0, 1, 2, 3}, {5, 4, 3, 2, 1, 0, 1, 2}, {6, 5, 4, 3, 2, 1, 0, 1}, {7, 6, 5, 4, 3, 2, 1, 0}};

// POINT10 record: X, Y, Z int32 at 0/4/8, intensity u16 at 12, returns/flags byte at 14
// (return number bits 0-2, number of returns 3-5, scan direction 6, edge 7), classification
// byte at 15, scan angle rank at 16, user data at 17, point source u16 at 18.

class Point10v2 final : public ItemDecoder {
public:
    void init(const uint8_t* first) override {
        for (int i = 0; i < 16; ++i) {
            medianX_[i].reset();
            medianY_[i].reset();
            lastIntensity_[i] = 0;
        }
        lastHeight_.fill(0);
        changed_.reset();
        intensity_.reset();
        scanAngle_[0].reset();
        scanAngle_[1].reset();
        source_.reset();
        bitByte_.reset();
        classification_.reset();
        userData_.reset();
        dx_.reset();
        dy_.reset();
        z_.reset();
        std::memcpy(last_, first, 20);
        last_[12] = last_[13] = 0;   // the intensity prediction starts from 0
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        const uint32_t changed = dec.decodeSymbol(changed_);
        if (changed & 32) last_[14] = uint8_t(dec.decodeSymbol(bitByte_[last_[14]]));
        const uint32_t r = last_[14] & 7, n = (last_[14] >> 3) & 7;
        const uint32_t m = kReturnMap[n][r], l = kReturnLevel[n][r];
        if (changed) {
            if (changed & 16) {
                const auto intensity = uint16_t(intensity_.decompress(dec, lastIntensity_[m], m < 3 ? m : 3));
                lastIntensity_[m] = intensity;
                bytes::put<uint16_t>(last_ + 12, intensity);
            } else {
                bytes::put<uint16_t>(last_ + 12, lastIntensity_[m]);
            }
            if (changed & 8) last_[15] = uint8_t(dec.decodeSymbol(classification_[last_[15]]));
            if (changed & 4) {
                const uint32_t direction = (last_[14] >> 6) & 1;
                last_[16] = fold8(int32_t(dec.decodeSymbol(scanAngle_[direction])) + last_[16]);
            }
            if (changed & 2) last_[17] = uint8_t(dec.decodeSymbol(userData_[last_[17]]));
            if (changed & 1) bytes::put<uint16_t>(last_ + 18, uint16_t(source_.decompress(dec, bytes::get<uint16_t>(last_ + 18))));
        }
        const int32_t dx = dx_.decompress(dec, medianX_[m].get(), n == 1);
        bytes::put<int32_t>(last_, wrapAdd(bytes::get<int32_t>(last_), dx));
        medianX_[m].add(dx);
        uint32_t k = dx_.k();
        const int32_t dy = dy_.decompress(dec, medianY_[m].get(), (n == 1) + (k < 20 ? (k & ~1u) : 20));
        bytes::put<int32_t>(last_ + 4, wrapAdd(bytes::get<int32_t>(last_ + 4), dy));
        medianY_[m].add(dy);
        k = (dx_.k() + dy_.k()) / 2;
        const int32_t z = z_.decompress(dec, lastHeight_[l], (n == 1) + (k < 18 ? (k & ~1u) : 18));
        bytes::put<int32_t>(last_ + 8, z);
        lastHeight_[l] = z;
        std::memcpy(item, last_, 20);
    }

private:
    uint8_t last_[20] = {};
    uint16_t lastIntensity_[16] = {};
    Median5 medianX_[16], medianY_[16];
    std::array<int32_t, 8> lastHeight_{};
    SymbolModel changed_{64};
    IntegerCodec intensity_{16, 4};
    SymbolModel scanAngle_[2] = {SymbolModel(256), SymbolModel(256)};
    IntegerCodec source_{16};
    LazyModels bitByte_, classification_, userData_;
    IntegerCodec dx_{32, 2}, dy_{32, 22}, z_{32, 20};
};

class Point10v1 final : public ItemDecoder {
public:
    void init(const uint8_t* first) override {
        lastDx_.fill(0);
        lastDy_.fill(0);
        lastIncrement_ = 0;
        dx_.reset();
        dy_.reset();
        z_.reset();
        intensity_.reset();
        scanAngle_.reset();
        source_.reset();
        changed_.reset();
        bitByte_.reset();
        classification_.reset();
        userData_.reset();
        std::memcpy(last_, first, 20);
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        const int32_t dx = dx_.decompress(dec, median3(lastDx_));
        bytes::put<int32_t>(last_, wrapAdd(bytes::get<int32_t>(last_), dx));
        uint32_t k = dx_.k();
        const int32_t dy = dy_.decompress(dec, median3(lastDy_), k < 19 ? k : 19);
        bytes::put<int32_t>(last_ + 4, wrapAdd(bytes::get<int32_t>(last_ + 4), dy));
        k = (k + dy_.k()) / 2;
        bytes::put<int32_t>(last_ + 8, z_.decompress(dec, bytes::get<int32_t>(last_ + 8), k < 19 ? k : 19));
        const uint32_t changed = dec.decodeSymbol(changed_);
        if (changed) {
            if (changed & 32) bytes::put<uint16_t>(last_ + 12, uint16_t(intensity_.decompress(dec, bytes::get<uint16_t>(last_ + 12))));
            if (changed & 16) last_[14] = uint8_t(dec.decodeSymbol(bitByte_[last_[14]]));
            if (changed & 8) last_[15] = uint8_t(dec.decodeSymbol(classification_[last_[15]]));
            if (changed & 4) last_[16] = uint8_t(scanAngle_.decompress(dec, last_[16], k < 3));
            if (changed & 2) last_[17] = uint8_t(dec.decodeSymbol(userData_[last_[17]]));
            if (changed & 1) bytes::put<uint16_t>(last_ + 18, uint16_t(source_.decompress(dec, bytes::get<uint16_t>(last_ + 18))));
        }
        lastDx_[lastIncrement_] = dx;
        lastDy_[lastIncrement_] = dy;
        lastIncrement_ = (lastIncrement_ + 1) % 3;
        std::memcpy(item, last_, 20);
    }

private:
    static int32_t median3(const std::array<int32_t, 3>& v) {
        if (v[0] < v[1]) return v[1] < v[2] ? v[1] : (v[0] < v[2] ? v[2] : v[0]);
        return v[0] < v[2] ? v[0] : (v[1] < v[2] ? v[2] : v[1]);
    }
    uint8_t last_[20] = {};
    std::array<int32_t, 3> lastDx_{}, lastDy_{};
    int lastIncrement_ = 0;
    IntegerCodec dx_{32}, dy_{32, 20}, z_{32, 20}, intensity_{16}, scanAngle_{8, 2}, source_{16};
    SymbolModel changed_{64};
    LazyModels bitByte_, classification_, userData_;
};

// GPS time: an int64 view of the double, predicted as a multiple of the last difference. Version
// 2 keeps four sequences (interleaved flight lines) and switches between them.
constexpr int32_t kGpsMulti = 500, kGpsMultiMinus = -10;
constexpr uint32_t kGpsUnchanged = kGpsMulti - kGpsMultiMinus + 1;   // 511
constexpr uint32_t kGpsCodeFull = kGpsMulti - kGpsMultiMinus + 2;    // 512
constexpr uint32_t kGpsTotal = kGpsMulti - kGpsMultiMinus + 6;       // 516

class GpsTime11v2 final : public ItemDecoder {
public:
    void init(const uint8_t* first) override {
        last_ = next_ = 0;
        diff_.fill(0);
        extreme_.fill(0);
        multi_.reset();
        zeroDiff_.reset();
        ic_.reset();
        time_[0] = bytes::get<uint64_t>(first);
        time_[1] = time_[2] = time_[3] = 0;
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        // A switch to another sequence re-reads in that sequence: a loop, bounded by the model's
        // symbols (each switch consumes one symbol), in place of LASzip's recursion.
        for (int guard = 0; guard < 8; ++guard)
            if (step(dec)) break;
        bytes::put<uint64_t>(item, time_[last_]);
    }

private:
    /// One symbol; false when it only switched the sequence.
    bool step(ArithmeticDecoder& dec) {
        if (diff_[last_] == 0) {
            const uint32_t multi = dec.decodeSymbol(zeroDiff_);
            if (multi == 1) {
                diff_[last_] = ic_.decompress(dec, 0, 0);
                time_[last_] += uint64_t(int64_t(diff_[last_]));
                extreme_[last_] = 0;
            } else if (multi == 2) {
                fullTime(dec);
            } else if (multi > 2) {
                last_ = (last_ + multi - 2) & 3;
                return false;
            }
            return true;
        }
        const uint32_t multi = dec.decodeSymbol(multi_);
        if (multi == 1) {
            time_[last_] += uint64_t(int64_t(ic_.decompress(dec, diff_[last_], 1)));
            extreme_[last_] = 0;
        } else if (multi < kGpsUnchanged) {
            int32_t diff;
            if (multi == 0) {
                diff = ic_.decompress(dec, 0, 7);
                adoptExtreme(diff);
            } else if (multi < uint32_t(kGpsMulti)) {
                diff = ic_.decompress(dec, wrapMul(int32_t(multi), diff_[last_]), multi < 10 ? 2 : 3);
            } else if (multi == uint32_t(kGpsMulti)) {
                diff = ic_.decompress(dec, wrapMul(kGpsMulti, diff_[last_]), 4);
                adoptExtreme(diff);
            } else {
                const int32_t m = kGpsMulti - int32_t(multi);
                if (m > kGpsMultiMinus) {
                    diff = ic_.decompress(dec, wrapMul(m, diff_[last_]), 5);
                } else {
                    diff = ic_.decompress(dec, wrapMul(kGpsMultiMinus, diff_[last_]), 6);
                    adoptExtreme(diff);
                }
            }
            time_[last_] += uint64_t(int64_t(diff));
        } else if (multi == kGpsCodeFull) {
            fullTime(dec);
        } else if (multi > kGpsCodeFull) {
            last_ = (last_ + multi - kGpsCodeFull) & 3;
            return false;
        }
        return true;
    }
    void adoptExtreme(int32_t diff) {
        if (++extreme_[last_] > 3) {
            diff_[last_] = diff;
            extreme_[last_] = 0;
        }
    }
    /// A time far from the last: a new sequence, its high 32 bits predicted, its low ones raw.
    void fullTime(ArithmeticDecoder& dec) {
        next_ = (next_ + 1) & 3;
        const uint32_t high = uint32_t(ic_.decompress(dec, int32_t(uint32_t(time_[last_] >> 32)), 8));
        time_[next_] = (uint64_t(high) << 32) | dec.readInt();
        last_ = next_;
        diff_[last_] = 0;
        extreme_[last_] = 0;
    }
    uint32_t last_ = 0, next_ = 0;
    std::array<uint64_t, 4> time_{};
    std::array<int32_t, 4> diff_{}, extreme_{};
    SymbolModel multi_{kGpsTotal}, zeroDiff_{6};
    IntegerCodec ic_{32, 9};
};

class GpsTime11v1 final : public ItemDecoder {
public:
    void init(const uint8_t* first) override {
        diff_ = 0;
        extreme_ = 0;
        multi_.reset();
        zeroDiff_.reset();
        ic_.reset();
        time_ = bytes::get<uint64_t>(first);
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        constexpr uint32_t kMultiMax = 512;
        if (diff_ == 0) {
            const uint32_t multi = dec.decodeSymbol(zeroDiff_);
            if (multi == 1) {
                diff_ = ic_.decompress(dec, 0, 0);
                time_ += uint64_t(int64_t(diff_));
            } else if (multi == 2) {
                time_ = dec.readInt64();
            }
        } else {
            const uint32_t multi = dec.decodeSymbol(multi_);
            if (multi < kMultiMax - 2) {
                int32_t diff;
                if (multi == 1) {
                    diff = ic_.decompress(dec, diff_, 1);
                    diff_ = diff;
                    extreme_ = 0;
                } else if (multi == 0) {
                    diff = ic_.decompress(dec, diff_ / 4, 2);
                    if (++extreme_ > 3) {
                        diff_ = diff;
                        extreme_ = 0;
                    }
                } else if (multi < 10) {
                    diff = ic_.decompress(dec, wrapMul(int32_t(multi), diff_), 3);
                } else if (multi < 50) {
                    diff = ic_.decompress(dec, wrapMul(int32_t(multi), diff_), 4);
                } else {
                    diff = ic_.decompress(dec, wrapMul(int32_t(multi), diff_), 5);
                    if (multi == kMultiMax - 3 && ++extreme_ > 3) {
                        diff_ = diff;
                        extreme_ = 0;
                    }
                }
                time_ += uint64_t(int64_t(diff));
            } else if (multi < kMultiMax - 1) {
                time_ = dec.readInt64();
            }
        }
        bytes::put<uint64_t>(item, time_);
    }

private:
    uint64_t time_ = 0;
    int32_t diff_ = 0, extreme_ = 0;
    SymbolModel multi_{512}, zeroDiff_{3};
    IntegerCodec ic_{32, 6};
};

// RGB: three 16-bit channels as six bytes; a symbol says which bytes changed. Version 2 predicts
// green and blue from red's change.
class Rgb12v2 final : public ItemDecoder {
public:
    void init(const uint8_t* first) override {
        used_.reset();
        for (SymbolModel& m : diff_) m.reset();
        for (int i = 0; i < 3; ++i) last_[i] = bytes::get<uint16_t>(first + 2 * i);
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        const uint32_t sym = dec.decodeSymbol(used_);
        uint16_t c[3];
        const auto lo = [](uint16_t v) { return int32_t(v & 0xFF); };
        const auto hi = [](uint16_t v) { return int32_t(v >> 8); };
        c[0] = (sym & 1) ? fold8(int32_t(dec.decodeSymbol(diff_[0])) + lo(last_[0])) : uint16_t(lo(last_[0]));
        c[0] |= (sym & 2) ? uint16_t(fold8(int32_t(dec.decodeSymbol(diff_[1])) + hi(last_[0])) << 8) : uint16_t(last_[0] & 0xFF00);
        if (sym & 64) {
            int32_t d = lo(c[0]) - lo(last_[0]);
            c[1] = (sym & 4) ? fold8(int32_t(dec.decodeSymbol(diff_[2])) + clamp8(d + lo(last_[1]))) : uint16_t(lo(last_[1]));
            if (sym & 16) {
                d = (d + (lo(c[1]) - lo(last_[1]))) / 2;
                c[2] = fold8(int32_t(dec.decodeSymbol(diff_[4])) + clamp8(d + lo(last_[2])));
            } else {
                c[2] = uint16_t(lo(last_[2]));
            }
            d = hi(c[0]) - hi(last_[0]);
            c[1] |= (sym & 8) ? uint16_t(fold8(int32_t(dec.decodeSymbol(diff_[3])) + clamp8(d + hi(last_[1]))) << 8) : uint16_t(last_[1] & 0xFF00);
            if (sym & 32) {
                d = (d + (hi(c[1]) - hi(last_[1]))) / 2;
                c[2] |= uint16_t(fold8(int32_t(dec.decodeSymbol(diff_[5])) + clamp8(d + hi(last_[2]))) << 8);
            } else {
                c[2] |= uint16_t(last_[2] & 0xFF00);
            }
        } else {
            c[1] = c[2] = c[0];   // grey
        }
        for (int i = 0; i < 3; ++i) {
            last_[i] = c[i];
            bytes::put<uint16_t>(item + 2 * i, c[i]);
        }
    }

private:
    uint16_t last_[3] = {};
    SymbolModel used_{128};
    SymbolModel diff_[6] = {SymbolModel(256), SymbolModel(256), SymbolModel(256), SymbolModel(256), SymbolModel(256), SymbolModel(256)};
};

class Rgb12v1 final : public ItemDecoder {
public:
    void init(const uint8_t* first) override {
        used_.reset();
        ic_.reset();
        for (int i = 0; i < 3; ++i) last_[i] = bytes::get<uint16_t>(first + 2 * i);
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        const uint32_t sym = dec.decodeSymbol(used_);
        for (uint32_t i = 0; i < 3; ++i) {
            const uint32_t lowBit = 1u << (2 * i), highBit = 2u << (2 * i);
            uint16_t v = (sym & lowBit) ? uint16_t(uint8_t(ic_.decompress(dec, last_[i] & 0xFF, 2 * i))) : uint16_t(last_[i] & 0xFF);
            v |= (sym & highBit) ? uint16_t(uint8_t(ic_.decompress(dec, last_[i] >> 8, 2 * i + 1)) << 8) : uint16_t(last_[i] & 0xFF00);
            last_[i] = v;
            bytes::put<uint16_t>(item + 2 * i, v);
        }
    }

private:
    uint16_t last_[3] = {};
    SymbolModel used_{64};
    IntegerCodec ic_{8, 6};
};

// Extra bytes: each byte predicted by the same byte of the last point.
class BytesV2 final : public ItemDecoder {
public:
    explicit BytesV2(uint16_t n) : last_(n, 0) {
        models_.reserve(n);
        for (uint16_t i = 0; i < n; ++i) models_.emplace_back(256);
    }
    void init(const uint8_t* first) override {
        for (SymbolModel& m : models_) m.reset();
        std::memcpy(last_.data(), first, last_.size());
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        for (size_t i = 0; i < last_.size(); ++i) item[i] = last_[i] = fold8(int32_t(last_[i]) + int32_t(dec.decodeSymbol(models_[i])));
    }

private:
    std::vector<uint8_t> last_;
    std::vector<SymbolModel> models_;
};

class BytesV1 final : public ItemDecoder {
public:
    explicit BytesV1(uint16_t n) : last_(n, 0), ic_(8, n) {}
    void init(const uint8_t* first) override {
        ic_.reset();
        std::memcpy(last_.data(), first, last_.size());
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        for (size_t i = 0; i < last_.size(); ++i) item[i] = last_[i] = uint8_t(ic_.decompress(dec, last_[i], uint32_t(i)));
    }

private:
    std::vector<uint8_t> last_;
    IntegerCodec ic_;
};

// Waveform packet descriptors (formats 4 and 5): index byte, offset u64, size u32, return point
// f32, x/y/z f32 (29 bytes). The same coder serves versions 1 and 2.
class WavePacket13 final : public ItemDecoder {
public:
    void init(const uint8_t* first) override {
        lastDiff32_ = 0;
        lastOffsetSymbol_ = 0;
        index_.reset();
        for (SymbolModel& m : offsetDiff_) m.reset();
        offset_.reset();
        size_.reset();
        returnPoint_.reset();
        xyz_.reset();
        std::memcpy(last_, first, 29);
    }
    void read(ArithmeticDecoder& dec, uint8_t* item) override {
        item[0] = uint8_t(dec.decodeSymbol(index_));
        const uint8_t* l = last_ + 1;
        uint8_t* p = item + 1;
        lastOffsetSymbol_ = dec.decodeSymbol(offsetDiff_[lastOffsetSymbol_]);
        const uint64_t lastOffset = bytes::get<uint64_t>(l);
        const uint32_t lastSize = bytes::get<uint32_t>(l + 8);
        uint64_t offset;
        if (lastOffsetSymbol_ == 0) offset = lastOffset;
        else if (lastOffsetSymbol_ == 1) offset = lastOffset + lastSize;
        else if (lastOffsetSymbol_ == 2) {
            lastDiff32_ = offset_.decompress(dec, lastDiff32_);
            offset = lastOffset + uint64_t(int64_t(lastDiff32_));
        } else offset = dec.readInt64();
        bytes::put<uint64_t>(p, offset);
        bytes::put<int32_t>(p + 8, size_.decompress(dec, int32_t(lastSize)));
        bytes::put<int32_t>(p + 12, returnPoint_.decompress(dec, bytes::get<int32_t>(l + 12)));
        for (uint32_t a = 0; a < 3; ++a) bytes::put<int32_t>(p + 16 + 4 * a, xyz_.decompress(dec, bytes::get<int32_t>(l + 16 + 4 * a), a));
        std::memcpy(last_, item, 29);
    }

private:
    uint8_t last_[29] = {};
    int32_t lastDiff32_ = 0;
    uint32_t lastOffsetSymbol_ = 0;
    SymbolModel index_{256};
    SymbolModel offsetDiff_[4] = {SymbolModel(4), SymbolModel(4), SymbolModel(4), SymbolModel(4)};
    IntegerCodec offset_{32}, size_{32}, returnPoint_{32}, xyz_{32, 3};
};

std::unique_ptr<ItemDecoder> makeDecoder(const Item& item) {
    const bool v2 = item.version >= 2;
    switch (item.type) {
    case ItemType::Point10: return v2 ? std::unique_ptr<ItemDecoder>(new Point10v2) : std::unique_ptr<ItemDecoder>(new Point10v1);
    case ItemType::GpsTime11: return v2 ? std::unique_ptr<ItemDecoder>(new GpsTime11v2) : std::unique_ptr<ItemDecoder>(new GpsTime11v1);
    case ItemType::Rgb12: return v2 ? std::unique_ptr<ItemDecoder>(new Rgb12v2) : std::unique_ptr<ItemDecoder>(new Rgb12v1);
    case ItemType::Byte: return v2 ? std::unique_ptr<ItemDecoder>(new BytesV2(item.size)) : std::unique_ptr<ItemDecoder>(new BytesV1(item.size));
    case ItemType::WavePacket13: return std::make_unique<WavePacket13>();
    default: return nullptr;
    }
}

}  // namespace

Result<void> decodePointwiseChunk(const LaszipVlr& vlr, std::span<const uint8_t> data, uint64_t count, uint8_t* out) {
    const size_t record = vlr.recordLength();
    if (data.size() < record)
        return makeError(std::string("the chunk is ").append(std::to_string(data.size())).append(" bytes, shorter than its first (raw) point"));
    std::vector<std::unique_ptr<ItemDecoder>> decoders;
    std::vector<size_t> at;
    size_t offset = 0;
    for (const Item& item : vlr.items) {
        auto d = makeDecoder(item);
        if (!d) return makeError(std::string("LAZ item type ").append(std::to_string(int(item.type))).append(" is not a point-wise item"));
        decoders.push_back(std::move(d));
        at.push_back(offset);
        offset += item.size;
    }
    std::memcpy(out, data.data(), record);
    for (size_t i = 0; i < decoders.size(); ++i) decoders[i]->init(out + at[i]);
    if (count == 1) return {};
    ArithmeticDecoder dec;
    dec.init(data.data() + record, data.size() - record);
    for (uint64_t p = 1; p < count; ++p) {
        uint8_t* r = out + p * record;
        for (size_t i = 0; i < decoders.size(); ++i) decoders[i]->read(dec, r + at[i]);
        // A cut stream decodes zeros into plausible garbage: stop at the first sign of it.
        if (dec.overrun() > 4)
            return makeError(std::string("the chunk's data ends at point ").append(std::to_string(p)).append(" of ").append(std::to_string(count))
                                 .append(" (truncated or corrupt)"));
    }
    return {};
}

}  // namespace orbis::points::laz::detail
