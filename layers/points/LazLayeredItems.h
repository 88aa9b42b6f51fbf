#pragma once
// Inside the layered LAZ codec (LazLayered.cpp, LazPoint14.cpp): the streams of one chunk (a
// decoder or encoder per layer), the item coders' interface, and the POINT14 coders' layers.

#include "layers/points/LazChunks.h"
#include "layers/points/LazCoder.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace orbis::points::laz::detail {

/// Models are made when first used: most of the 64 classification or user data contexts never are.
inline SymbolModel& lazyModel(std::unique_ptr<SymbolModel>& m, uint32_t symbols) {
    if (!m) m = std::make_unique<SymbolModel>(symbols);
    return *m;
}

// ---------------------------------------------------------------------------------------------
// The streams of one chunk.

struct InLayer {
    ArithmeticDecoder dec;
    const uint8_t* bytes = nullptr;
    uint32_t size = 0;
    bool active = false;   // asked for and not empty: decoded
};

struct OutLayer {
    std::vector<uint8_t> bytes;
    ArithmeticEncoder enc{bytes};
    bool changed = false;   // the field changed somewhere in the chunk: the layer is written
};

class ItemDecoder {
public:
    virtual ~ItemDecoder() = default;
    /// Starts from the chunk's first record; POINT14 sets the channel, the others follow it (see
    /// ChannelContexts for what POINT14 hands down on later points).
    virtual void init(const uint8_t* first, uint32_t& channel) = 0;
    virtual void decode(uint8_t* item, uint32_t& channel) = 0;
};

class ItemEncoder {
public:
    virtual ~ItemEncoder() = default;
    virtual void init(const uint8_t* first, uint32_t& channel) = 0;
    virtual void encode(const uint8_t* item, uint32_t& channel) = 0;
};


/// The layers of POINT14, in the chunk's order.
enum Point14Layer { kXY, kZ, kClassification, kFlags, kIntensity, kScanAngle, kUserData, kPointSource, kGpsTime, kPoint14Layers };
inline constexpr const char* kPoint14LayerNames[kPoint14Layers] = {"channel_returns_XY", "Z", "classification", "flags", "intensity",
                                                             "scan_angle", "user_data", "point_source", "gps_time"};

/// The POINT14 coders (LazPoint14.cpp): `layers` are the chunk's kPoint14Layers streams.
std::unique_ptr<ItemDecoder> makePoint14Decoder(InLayer* layers);
std::unique_ptr<ItemEncoder> makePoint14Encoder(OutLayer* layers);

}  // namespace orbis::points::laz::detail
