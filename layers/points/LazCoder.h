#pragma once
// The entropy coding of LASzip (LAZ): an adaptive arithmetic decoder with its bit and symbol
// models, and the integer decompressor that codes a value as its difference from a prediction
// (the magnitude class k as a symbol, then the bits inside the class). Written from the LAZ
// format's description (Isenburg, "LASzip: lossless compression of LiDAR data", 2013, and the
// format as LASzip 3.4 writes it); checked against files written by LASzip, laz-perf and libLAS.
//
// Every read is bounded by the buffer it was given: a truncated or corrupt stream reads zeros past
// its end and says so (`overrun()`), never outside the buffer. CPU only, no allocation while
// decoding once the models exist.

#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace orbis::points::laz {

/// An adaptive binary model (probability of a 0 bit).
class BitModel {
public:
    BitModel() { reset(); }
    void reset();

private:
    friend class ArithmeticDecoder;
    friend class ArithmeticEncoder;
    void update();
    uint32_t bit0Count_ = 1, bitCount_ = 2, bit0Prob_ = 0, bitsUntilUpdate_ = 4, updateCycle_ = 4;
};

/// An adaptive model of `symbols` symbols (2..2048), with a lookup table for large alphabets.
class SymbolModel {
public:
    explicit SymbolModel(uint32_t symbols);
    void reset();
    uint32_t symbols() const { return symbols_; }

private:
    friend class ArithmeticDecoder;
    friend class ArithmeticEncoder;
    void update();
    uint32_t symbols_, lastSymbol_;
    uint32_t tableSize_ = 0, tableShift_ = 0;
    uint32_t totalCount_ = 0, updateCycle_ = 0, symbolsUntilUpdate_ = 0;
    std::vector<uint32_t> distribution_, symbolCount_, decoderTable_;
};

class ArithmeticDecoder {
public:
    /// Starts decoding `size` bytes at `data` (reads the first four). The buffer must outlive
    /// the decoding.
    void init(const uint8_t* data, size_t size);
    uint32_t decodeBit(BitModel& m);
    uint32_t decodeSymbol(SymbolModel& m);
    uint32_t readBits(uint32_t bits);   ///< 1..32 raw bits
    uint32_t readShort();
    uint32_t readInt();
    uint64_t readInt64();
    /// Bytes requested past the end of the buffer (read as zeros): a truncated or corrupt stream
    /// when more than the few the encoder's flush allows.
    size_t overrun() const { return overrun_; }
    size_t consumed() const { return size_t(at_ - begin_); }

private:
    uint8_t nextByte() {
        if (at_ < end_) return *at_++;
        ++overrun_;
        return 0;
    }
    void renormalise() {
        do value_ = (value_ << 8) | nextByte();
        while ((length_ <<= 8) < kMinLength);
    }
    static constexpr uint32_t kMinLength = 0x01000000u;
    const uint8_t* begin_ = nullptr;
    const uint8_t* at_ = nullptr;
    const uint8_t* end_ = nullptr;
    uint32_t value_ = 0, length_ = 0;
    size_t overrun_ = 0;
};

/// The mirror of ArithmeticDecoder (the COPC writer and the tests' encoders).
class ArithmeticEncoder {
public:
    explicit ArithmeticEncoder(std::vector<uint8_t>& out) : out_(out) {}
    void encodeBit(BitModel& m, uint32_t bit);
    void encodeSymbol(SymbolModel& m, uint32_t symbol);
    void writeBits(uint32_t bits, uint32_t value);
    void writeShort(uint32_t value) { writeBits(16, value & 0xFFFFu); }
    void writeInt(uint32_t value);
    void writeInt64(uint64_t value);
    /// Flushes the coder's state so a decoder reads every symbol back; appends to `out`.
    void done();

private:
    void carry();
    void renormalise();
    std::vector<uint8_t>& out_;
    size_t start_ = out_.size();
    uint32_t base_ = 0, length_ = 0xFFFFFFFFu;
};

/// A value coded as a correction to a prediction, in one of `contexts` contexts (LASzip's
/// IntegerCompressor). `bits` is the value's width (32: full int32 range, wrapping).
class IntegerCodec {
public:
    explicit IntegerCodec(uint32_t bits = 16, uint32_t contexts = 1, uint32_t bitsHigh = 8);
    /// Resets every model (the start of a chunk).
    void reset();
    int32_t decompress(ArithmeticDecoder& dec, int32_t prediction, uint32_t context = 0);
    void compress(ArithmeticEncoder& enc, int32_t prediction, int32_t real, uint32_t context = 0);
    /// The magnitude class of the last corrector (LASzip's getK()).
    uint32_t k() const { return k_; }

private:
    int32_t readCorrector(ArithmeticDecoder& dec, SymbolModel& bitsModel);
    void writeCorrector(ArithmeticEncoder& enc, int32_t c, SymbolModel& bitsModel);
    uint32_t bits_, contexts_, bitsHigh_;
    uint32_t corrBits_, corrRange_;
    int32_t corrMin_, corrMax_;
    uint32_t k_ = 0;
    std::vector<SymbolModel> bitsModels_;   // one per context: the class k
    BitModel corrector0_;                   // k = 0: the corrector is 0 or 1
    std::vector<SymbolModel> correctors_;   // k = 1..corrBits
};

/// LASzip's running median of the last five values (the predictor of x/y differences).
struct Median5 {
    int32_t v[5] = {0, 0, 0, 0, 0};
    bool high = true;
    void reset() { *this = Median5{}; }
    int32_t get() const { return v[2]; }
    void add(int32_t x);
};

/// Wraps an int into 0..255 (LASzip's U8_FOLD) and clamps one (U8_CLAMP).
inline uint8_t fold8(int32_t n) { return uint8_t(n < 0 ? n + 256 : (n > 255 ? n - 256 : n)); }
inline int32_t clamp8(int32_t n) { return n < 0 ? 0 : (n > 255 ? 255 : n); }

/// Wrapping int32 arithmetic (the coders rely on two's complement wrap-around).
inline int32_t wrapAdd(int32_t a, int32_t b) { return int32_t(uint32_t(a) + uint32_t(b)); }
inline int32_t wrapMul(int32_t a, int32_t b) { return int32_t(uint32_t(a) * uint32_t(b)); }

}  // namespace orbis::points::laz
