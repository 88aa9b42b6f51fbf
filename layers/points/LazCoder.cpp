#include "layers/points/LazCoder.h"

#include <algorithm>
#include <cassert>

namespace orbis::points::laz {
namespace {

constexpr uint32_t kMinLength = 0x01000000u;
constexpr uint32_t kBitLengthShift = 13, kBitMaxCount = 1u << kBitLengthShift;
constexpr uint32_t kSymbolLengthShift = 15, kSymbolMaxCount = 1u << kSymbolLengthShift;

}  // namespace

// ---------------------------------------------------------------------------------------------
// Models. Both adapt by counting: the counts are rescaled into probabilities every "update
// cycle", a cycle that grows by 5/4 each time up to a cap, and the counts are halved when their
// total passes the maximum.

void BitModel::reset() {
    bit0Count_ = 1;
    bitCount_ = 2;
    bit0Prob_ = 1u << (kBitLengthShift - 1);
    updateCycle_ = bitsUntilUpdate_ = 4;
}

void BitModel::update() {
    if ((bitCount_ += updateCycle_) > kBitMaxCount) {
        bitCount_ = (bitCount_ + 1) >> 1;
        bit0Count_ = (bit0Count_ + 1) >> 1;
        if (bit0Count_ == bitCount_) ++bitCount_;
    }
    const uint32_t scale = 0x80000000u / bitCount_;
    bit0Prob_ = (bit0Count_ * scale) >> (31 - kBitLengthShift);
    updateCycle_ = (5 * updateCycle_) >> 2;
    if (updateCycle_ > 64) updateCycle_ = 64;
    bitsUntilUpdate_ = updateCycle_;
}

SymbolModel::SymbolModel(uint32_t symbols) : symbols_(symbols < 2 ? 2 : (symbols > 2048 ? 2048 : symbols)), lastSymbol_(symbols_ - 1) {
    if (symbols_ > 16) {
        uint32_t tableBits = 3;
        while (symbols_ > (1u << (tableBits + 2))) ++tableBits;
        tableSize_ = 1u << tableBits;
        tableShift_ = kSymbolLengthShift - tableBits;
        decoderTable_.assign(tableSize_ + 2, 0);
    }
    distribution_.assign(symbols_, 0);
    symbolCount_.assign(symbols_, 0);
    reset();
}

void SymbolModel::reset() {
    totalCount_ = 0;
    updateCycle_ = symbols_;
    for (uint32_t& c : symbolCount_) c = 1;
    update();
    symbolsUntilUpdate_ = updateCycle_ = (symbols_ + 6) >> 1;
}

void SymbolModel::update() {
    if ((totalCount_ += updateCycle_) > kSymbolMaxCount) {
        totalCount_ = 0;
        for (uint32_t& c : symbolCount_) totalCount_ += (c = (c + 1) >> 1);
    }
    uint32_t sum = 0, s = 0;
    const uint32_t scale = 0x80000000u / totalCount_;
    if (tableSize_ == 0) {
        for (uint32_t k = 0; k < symbols_; ++k) {
            distribution_[k] = (scale * sum) >> (31 - kSymbolLengthShift);
            sum += symbolCount_[k];
        }
    } else {
        for (uint32_t k = 0; k < symbols_; ++k) {
            distribution_[k] = (scale * sum) >> (31 - kSymbolLengthShift);
            sum += symbolCount_[k];
            const uint32_t w = distribution_[k] >> tableShift_;
            while (s < w) decoderTable_[++s] = k - 1;
        }
        decoderTable_[0] = 0;
        while (s <= tableSize_) decoderTable_[++s] = symbols_ - 1;
    }
    updateCycle_ = (5 * updateCycle_) >> 2;
    const uint32_t maxCycle = (symbols_ + 6) << 3;
    if (updateCycle_ > maxCycle) updateCycle_ = maxCycle;
    symbolsUntilUpdate_ = updateCycle_;
}

// ---------------------------------------------------------------------------------------------
// Decoder: the interval [0, length) scaled to 32 bits, `value` the code's position in it.

void ArithmeticDecoder::init(const uint8_t* data, size_t size) {
    begin_ = at_ = data;
    end_ = data + size;
    overrun_ = 0;
    length_ = 0xFFFFFFFFu;
    value_ = uint32_t(nextByte()) << 24;
    value_ |= uint32_t(nextByte()) << 16;
    value_ |= uint32_t(nextByte()) << 8;
    value_ |= uint32_t(nextByte());
}

uint32_t ArithmeticDecoder::decodeBit(BitModel& m) {
    const uint32_t x = m.bit0Prob_ * (length_ >> kBitLengthShift);
    const uint32_t bit = value_ >= x;
    if (bit == 0) {
        length_ = x;
        ++m.bit0Count_;
    } else {
        value_ -= x;
        length_ -= x;
    }
    if (length_ < kMinLength) renormalise();
    if (--m.bitsUntilUpdate_ == 0) m.update();
    return bit;
}

uint32_t ArithmeticDecoder::decodeSymbol(SymbolModel& m) {
    uint32_t symbol, x, y = length_;
    if (!m.decoderTable_.empty()) {
        const uint32_t dv = value_ / (length_ >>= kSymbolLengthShift);
        // A corrupt stream can leave value_ past length_: keep the lookup inside the table.
        const uint32_t t = std::min(dv >> m.tableShift_, m.tableSize_);
        symbol = m.decoderTable_[t];
        uint32_t n = m.decoderTable_[t + 1] + 1;
        while (n > symbol + 1) {   // bisection inside the table's bracket
            const uint32_t k = (symbol + n) >> 1;
            if (m.distribution_[k] > dv) n = k;
            else symbol = k;
        }
        x = m.distribution_[symbol] * length_;
        if (symbol != m.lastSymbol_) y = m.distribution_[symbol + 1] * length_;
    } else {
        x = symbol = 0;
        length_ >>= kSymbolLengthShift;
        uint32_t n = m.symbols_, k = n >> 1;
        do {
            const uint32_t z = length_ * m.distribution_[k];
            if (z > value_) {
                n = k;
                y = z;
            } else {
                symbol = k;
                x = z;
            }
        } while ((k = (symbol + n) >> 1) != symbol);
    }
    value_ -= x;
    length_ = y - x;
    if (length_ < kMinLength) renormalise();
    ++m.symbolCount_[symbol];
    if (--m.symbolsUntilUpdate_ == 0) m.update();
    // A corrupt stream can land past the last symbol only through a broken model; clamp so the
    // callers' table lookups stay in range.
    return symbol < m.symbols_ ? symbol : m.lastSymbol_;
}

uint32_t ArithmeticDecoder::readBits(uint32_t bits) {
    if (bits > 19) {
        const uint32_t low = readShort();
        const uint32_t high = readBits(bits - 16);
        return (high << 16) | low;
    }
    const uint32_t symbol = value_ / (length_ >>= bits);
    value_ -= length_ * symbol;
    if (length_ < kMinLength) renormalise();
    return symbol;
}

uint32_t ArithmeticDecoder::readShort() {
    const uint32_t symbol = value_ / (length_ >>= 16);
    value_ -= length_ * symbol;
    if (length_ < kMinLength) renormalise();
    return symbol & 0xFFFFu;
}

uint32_t ArithmeticDecoder::readInt() {
    const uint32_t low = readShort();
    return (readShort() << 16) | low;
}

uint64_t ArithmeticDecoder::readInt64() {
    const uint64_t low = readInt();
    return (uint64_t(readInt()) << 32) | low;
}

// ---------------------------------------------------------------------------------------------
// Encoder: the mirror; a carry ripples back through the bytes already written.

void ArithmeticEncoder::carry() {
    size_t i = out_.size();
    while (i > start_ && out_[i - 1] == 0xFF) out_[--i] = 0;
    if (i > start_) ++out_[i - 1];
}

void ArithmeticEncoder::renormalise() {
    do {
        out_.push_back(uint8_t(base_ >> 24));
        base_ <<= 8;
    } while ((length_ <<= 8) < kMinLength);
}

void ArithmeticEncoder::encodeBit(BitModel& m, uint32_t bit) {
    const uint32_t x = m.bit0Prob_ * (length_ >> kBitLengthShift);
    if (bit == 0) {
        length_ = x;
        ++m.bit0Count_;
    } else {
        const uint32_t before = base_;
        base_ += x;
        length_ -= x;
        if (before > base_) carry();
    }
    if (length_ < kMinLength) renormalise();
    if (--m.bitsUntilUpdate_ == 0) m.update();
}

void ArithmeticEncoder::encodeSymbol(SymbolModel& m, uint32_t symbol) {
    const uint32_t before = base_;
    if (symbol == m.lastSymbol_) {
        const uint32_t x = m.distribution_[symbol] * (length_ >> kSymbolLengthShift);
        base_ += x;
        length_ -= x;
    } else {
        const uint32_t x = m.distribution_[symbol] * (length_ >>= kSymbolLengthShift);
        base_ += x;
        length_ = m.distribution_[symbol + 1] * length_ - x;
    }
    if (before > base_) carry();
    if (length_ < kMinLength) renormalise();
    ++m.symbolCount_[symbol];
    if (--m.symbolsUntilUpdate_ == 0) m.update();
}

void ArithmeticEncoder::writeBits(uint32_t bits, uint32_t value) {
    if (bits > 19) {
        writeShort(value & 0xFFFFu);
        value >>= 16;
        bits -= 16;
    }
    const uint32_t before = base_;
    base_ += value * (length_ >>= bits);
    if (before > base_) carry();
    if (length_ < kMinLength) renormalise();
}

void ArithmeticEncoder::writeInt(uint32_t value) {
    writeShort(value & 0xFFFFu);
    writeShort(value >> 16);
}

void ArithmeticEncoder::writeInt64(uint64_t value) {
    writeInt(uint32_t(value));
    writeInt(uint32_t(value >> 32));
}

void ArithmeticEncoder::done() {
    const uint32_t before = base_;
    bool anotherByte = true;
    if (length_ > 2 * kMinLength) {
        base_ += kMinLength;
        length_ = kMinLength >> 1;
    } else {
        base_ += kMinLength >> 1;
        length_ = kMinLength >> 9;
        anotherByte = false;
    }
    if (before > base_) carry();
    renormalise();
    // Padding, so the decoder's look-ahead stays inside the stream.
    out_.push_back(0);
    out_.push_back(0);
    if (anotherByte) out_.push_back(0);
}

// ---------------------------------------------------------------------------------------------
// Integer codec: the corrector c = real - prediction, folded into the value's range, is coded as
// its class k (the smallest k with -(2^k - 1) <= c <= 2^k) and then its place inside the class:
// a symbol for small k, the top `bitsHigh` bits as a symbol and the rest raw for large k.

IntegerCodec::IntegerCodec(uint32_t bits, uint32_t contexts, uint32_t bitsHigh)
    : bits_(bits), contexts_(contexts == 0 ? 1 : contexts), bitsHigh_(bitsHigh) {
    if (bits_ > 0 && bits_ < 32) {
        corrBits_ = bits_;
        corrRange_ = 1u << bits_;
        corrMin_ = -int32_t(corrRange_ / 2);
        corrMax_ = int32_t(uint32_t(corrMin_) + corrRange_ - 1);
    } else {
        corrBits_ = 32;
        corrRange_ = 0;
        corrMin_ = INT32_MIN;
        corrMax_ = INT32_MAX;
    }
    bitsModels_.reserve(contexts_);
    for (uint32_t i = 0; i < contexts_; ++i) bitsModels_.emplace_back(corrBits_ + 1);
    correctors_.reserve(corrBits_);
    for (uint32_t i = 1; i <= corrBits_; ++i) correctors_.emplace_back(i <= bitsHigh_ ? (1u << i) : (1u << bitsHigh_));
}

void IntegerCodec::reset() {
    for (SymbolModel& m : bitsModels_) m.reset();
    corrector0_.reset();
    for (SymbolModel& m : correctors_) m.reset();
    k_ = 0;
}

int32_t IntegerCodec::readCorrector(ArithmeticDecoder& dec, SymbolModel& bitsModel) {
    k_ = dec.decodeSymbol(bitsModel);
    if (k_ == 0) return int32_t(dec.decodeBit(corrector0_));
    if (k_ >= 32) return corrMin_;
    int64_t c;
    if (k_ <= bitsHigh_) {
        c = dec.decodeSymbol(correctors_[k_ - 1]);
    } else {
        const uint32_t k1 = k_ - bitsHigh_;
        c = dec.decodeSymbol(correctors_[k_ - 1]);
        c = (c << k1) | dec.readBits(k1);
    }
    // Back from [0, 2^k - 1] to [-(2^k - 1), -(2^(k-1))] or [2^(k-1) + 1, 2^k].
    if (c >= (int64_t(1) << (k_ - 1))) c += 1;
    else c -= (int64_t(1) << k_) - 1;
    return int32_t(c);
}

int32_t IntegerCodec::decompress(ArithmeticDecoder& dec, int32_t prediction, uint32_t context) {
    if (context >= contexts_) context = contexts_ - 1;
    int32_t real = wrapAdd(prediction, readCorrector(dec, bitsModels_[context]));
    if (corrRange_ != 0) {
        if (real < 0) real = int32_t(uint32_t(real) + corrRange_);
        else if (uint32_t(real) >= corrRange_) real = int32_t(uint32_t(real) - corrRange_);
    }
    return real;
}

void IntegerCodec::writeCorrector(ArithmeticEncoder& enc, int32_t c, SymbolModel& bitsModel) {
    uint32_t c1 = c <= 0 ? uint32_t(0) - uint32_t(c) : uint32_t(c) - 1;
    k_ = 0;
    while (c1) {
        c1 >>= 1;
        ++k_;
    }
    enc.encodeSymbol(bitsModel, k_);
    if (k_ == 0) {
        enc.encodeBit(corrector0_, uint32_t(c));
        return;
    }
    if (k_ >= 32) return;
    int64_t v = c;
    if (v < 0) v += (int64_t(1) << k_) - 1;
    else v -= 1;
    if (k_ <= bitsHigh_) {
        enc.encodeSymbol(correctors_[k_ - 1], uint32_t(v));
    } else {
        const uint32_t k1 = k_ - bitsHigh_;
        const uint32_t low = uint32_t(v) & ((1u << k1) - 1);
        enc.encodeSymbol(correctors_[k_ - 1], uint32_t(v >> k1));
        enc.writeBits(k1, low);
    }
}

void IntegerCodec::compress(ArithmeticEncoder& enc, int32_t prediction, int32_t real, uint32_t context) {
    if (context >= contexts_) context = contexts_ - 1;
    int32_t corr = int32_t(uint32_t(real) - uint32_t(prediction));
    if (corrRange_ != 0) {
        if (corr < corrMin_) corr = int32_t(uint32_t(corr) + corrRange_);
        else if (corr > corrMax_) corr = int32_t(uint32_t(corr) - corrRange_);
    }
    writeCorrector(enc, corr, bitsModels_[context]);
}

// ---------------------------------------------------------------------------------------------

void Median5::add(int32_t x) {
    if (high) {
        if (x < v[2]) {
            v[4] = v[3];
            v[3] = v[2];
            if (x < v[0]) {
                v[2] = v[1];
                v[1] = v[0];
                v[0] = x;
            } else if (x < v[1]) {
                v[2] = v[1];
                v[1] = x;
            } else {
                v[2] = x;
            }
        } else {
            if (x < v[3]) {
                v[4] = v[3];
                v[3] = x;
            } else {
                v[4] = x;
            }
            high = false;
        }
    } else {
        if (v[2] < x) {
            v[0] = v[1];
            v[1] = v[2];
            if (v[4] < x) {
                v[2] = v[3];
                v[3] = v[4];
                v[4] = x;
            } else if (v[3] < x) {
                v[2] = v[3];
                v[3] = x;
            } else {
                v[2] = x;
            }
        } else {
            if (v[1] < x) {
                v[0] = v[1];
                v[1] = x;
            } else {
                v[0] = x;
            }
            high = true;
        }
    }
}

}  // namespace orbis::points::laz
