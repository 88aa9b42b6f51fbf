// Layered LAZ chunks (compressor 3, item version 3): the LAS 1.4 point formats 6-10.
//
// A chunk is the first record raw, the chunk's point count, the byte size of every layer, then
// the layers. Each layer is an arithmetic stream of its own, so a field group nobody asked for
// is stepped over without decoding, and an empty layer means the field never changes in the
// chunk. Every item keeps up to four contexts, one per scanner channel: a point is predicted from
// the last point of its own channel, and a channel seen for the first time starts from the point
// before it (the other items follow LASzip's quirks there: see ChannelContexts). Written from the
// format's description; the contexts, the models and their order decide every bit, so they follow
// LASzip 3.4 exactly. Checked against COPC files (re-encoding gives their chunks byte for byte) and
// against laz-perf's decoder on chunks with channel switches, RGB, NIR and extra bytes.

#include "layers/points/LasBytes.h"
#include "layers/points/LazLayeredItems.h"

#include <array>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>

namespace orbis::points::laz::detail {
namespace {

[[gnu::format(printf, 1, 2)]] Error fail(const char* format, ...) {
    char text[256];
    va_list args;
    va_start(args, format);
    std::vsnprintf(text, sizeof text, format, args);
    va_end(args);
    return makeError(text);
}

// ---------------------------------------------------------------------------------------------
// RGB (RGB14, and the colour of RGBNIR14) and NIR: byte-wise differences, the green and blue ones
// predicted from red's.

// The contexts below copy as a new context does: the last value, with fresh models.

struct RgbContext {
    std::array<uint16_t, 3> last{};
    SymbolModel used{128};
    std::vector<SymbolModel> diffs = std::vector<SymbolModel>(6, SymbolModel(256));

    explicit RgbContext(const uint8_t* first) {
        for (int i = 0; i < 3; ++i) last[i] = bytes::get<uint16_t>(first + 2 * i);
    }
    RgbContext(const RgbContext& from) : last(from.last) {}
};

struct NirContext {
    uint16_t last = 0;
    SymbolModel used{4};
    SymbolModel low{256}, high{256};

    explicit NirContext(uint16_t first) : last(first) {}
    NirContext(const NirContext& from) : last(from.last) {}
};

/// The per-channel contexts of an item other than POINT14, switched as LASzip 3 switches them,
/// quirks included (they are the format now; laz-perf does the same). The channel POINT14 hands
/// down is its new channel on a point where the channel changed and 0 on every other point. On a
/// switch to a context used before, only the models switch: the point is still predicted from, and
/// written to, the previous context's last value. A context used for the first time starts from a
/// copy of the previous one's last value.
template <typename Context>
class ChannelContexts {
public:
    struct Pick {
        Context& models;
        Context& last;
    };

    void init(uint32_t channel, const Context& first) {
        current_ = channel;
        contexts_[channel] = std::make_unique<Context>(first);
    }

    Pick select(uint32_t channel) {
        Context* last = contexts_[current_].get();
        if (channel != current_) {
            current_ = channel;
            if (!contexts_[channel]) {
                contexts_[channel] = std::make_unique<Context>(*last);
                last = contexts_[channel].get();
            }
        }
        return {*contexts_[current_], *last};
    }

private:
    std::array<std::unique_ptr<Context>, 4> contexts_;
    uint32_t current_ = 0;
};

void decodeRgb(ArithmeticDecoder& dec, ChannelContexts<RgbContext>::Pick pick, uint8_t* item) {
    RgbContext& c = pick.models;
    std::array<uint16_t, 3>& lastRgb = pick.last.last;
    const uint16_t* last = lastRgb.data();
    const uint32_t sym = dec.decodeSymbol(c.used);
    uint16_t rgb[3];
    auto byte = [&](uint32_t bit, uint32_t model, int32_t predicted, int32_t lastByte) {
        return (sym & (1u << bit)) ? int32_t(fold8(int32_t(dec.decodeSymbol(c.diffs[model])) + predicted)) : lastByte;
    };
    const int32_t rLow = byte(0, 0, last[0] & 255, last[0] & 255);
    const int32_t rHigh = byte(1, 1, last[0] >> 8, last[0] >> 8);
    rgb[0] = uint16_t(rLow | (rHigh << 8));
    if (sym & 64) {
        int32_t diff = rLow - (last[0] & 255);
        const int32_t gLow = byte(2, 2, clamp8(diff + (last[1] & 255)), last[1] & 255);
        diff = (diff + gLow - (last[1] & 255)) / 2;
        const int32_t bLow = byte(4, 4, clamp8(diff + (last[2] & 255)), last[2] & 255);
        diff = rHigh - (last[0] >> 8);
        const int32_t gHigh = byte(3, 3, clamp8(diff + (last[1] >> 8)), last[1] >> 8);
        diff = (diff + gHigh - (last[1] >> 8)) / 2;
        const int32_t bHigh = byte(5, 5, clamp8(diff + (last[2] >> 8)), last[2] >> 8);
        rgb[1] = uint16_t(gLow | (gHigh << 8));
        rgb[2] = uint16_t(bLow | (bHigh << 8));
    } else {
        rgb[1] = rgb[2] = rgb[0];   // grey
    }
    for (int i = 0; i < 3; ++i) {
        lastRgb[i] = rgb[i];
        bytes::put(item + 2 * i, rgb[i]);
    }
}

/// Returns whether the colour differs from the context's last.
bool encodeRgb(ArithmeticEncoder& enc, ChannelContexts<RgbContext>::Pick pick, const uint8_t* item) {
    RgbContext& c = pick.models;
    std::array<uint16_t, 3>& lastRgb = pick.last.last;
    const uint16_t* last = lastRgb.data();
    uint16_t rgb[3];
    for (int i = 0; i < 3; ++i) rgb[i] = bytes::get<uint16_t>(item + 2 * i);
    uint32_t sym = 0;
    for (int i = 0; i < 3; ++i) {
        if ((last[i] & 0x00FF) != (rgb[i] & 0x00FF)) sym |= 1u << (2 * i);
        if ((last[i] & 0xFF00) != (rgb[i] & 0xFF00)) sym |= 1u << (2 * i + 1);
    }
    if (rgb[0] != rgb[1] || rgb[0] != rgb[2]) sym |= 64;
    enc.encodeSymbol(c.used, sym);
    int32_t diffLow = 0, diffHigh = 0;
    if (sym & 1) {
        diffLow = (rgb[0] & 255) - (last[0] & 255);
        enc.encodeSymbol(c.diffs[0], fold8(diffLow));
    }
    if (sym & 2) {
        diffHigh = (rgb[0] >> 8) - (last[0] >> 8);
        enc.encodeSymbol(c.diffs[1], fold8(diffHigh));
    }
    if (sym & 64) {
        if (sym & 4) enc.encodeSymbol(c.diffs[2], fold8((rgb[1] & 255) - clamp8(diffLow + (last[1] & 255))));
        if (sym & 16) {
            diffLow = (diffLow + (rgb[1] & 255) - (last[1] & 255)) / 2;
            enc.encodeSymbol(c.diffs[4], fold8((rgb[2] & 255) - clamp8(diffLow + (last[2] & 255))));
        }
        if (sym & 8) enc.encodeSymbol(c.diffs[3], fold8((rgb[1] >> 8) - clamp8(diffHigh + (last[1] >> 8))));
        if (sym & 32) {
            diffHigh = (diffHigh + (rgb[1] >> 8) - (last[1] >> 8)) / 2;
            enc.encodeSymbol(c.diffs[5], fold8((rgb[2] >> 8) - clamp8(diffHigh + (last[2] >> 8))));
        }
    }
    for (int i = 0; i < 3; ++i) lastRgb[i] = rgb[i];
    return sym != 0;
}

void decodeNir(ArithmeticDecoder& dec, ChannelContexts<NirContext>::Pick pick, uint8_t* item) {
    NirContext& c = pick.models;
    uint16_t& last = pick.last.last;
    const uint32_t sym = dec.decodeSymbol(c.used);
    int32_t low = last & 255, high = last >> 8;
    if (sym & 1) low = fold8(int32_t(dec.decodeSymbol(c.low)) + low);
    if (sym & 2) high = fold8(int32_t(dec.decodeSymbol(c.high)) + high);
    last = uint16_t(low | (high << 8));
    bytes::put(item, last);
}

bool encodeNir(ArithmeticEncoder& enc, ChannelContexts<NirContext>::Pick pick, const uint8_t* item) {
    NirContext& c = pick.models;
    uint16_t& last = pick.last.last;
    const uint16_t nir = bytes::get<uint16_t>(item);
    const uint32_t sym = ((last & 0x00FF) != (nir & 0x00FF) ? 1u : 0u) | ((last & 0xFF00) != (nir & 0xFF00) ? 2u : 0u);
    enc.encodeSymbol(c.used, sym);
    if (sym & 1) enc.encodeSymbol(c.low, fold8((nir & 255) - (last & 255)));
    if (sym & 2) enc.encodeSymbol(c.high, fold8((nir >> 8) - (last >> 8)));
    last = nir;
    return sym != 0;
}

/// RGB14 (one layer) and RGBNIR14 (two: colour, then NIR).
class ColourDecoder final : public ItemDecoder {
public:
    ColourDecoder(InLayer* layers, bool nir) : layers_(layers), nir_(nir) {}

    void init(const uint8_t* first, uint32_t& channel) override {
        std::memcpy(first_, first, nir_ ? 8 : 6);
        rgb_.init(channel, RgbContext(first));
        if (nir_) nirContexts_.init(channel, NirContext(bytes::get<uint16_t>(first + 6)));
    }

    void decode(uint8_t* item, uint32_t& channel) override {
        // A skipped or constant layer keeps the first point's value: every context holds it.
        if (layers_[0].active) decodeRgb(layers_[0].dec, rgb_.select(channel), item);
        else std::memcpy(item, first_, 6);
        if (!nir_) return;
        if (layers_[1].active) decodeNir(layers_[1].dec, nirContexts_.select(channel), item + 6);
        else std::memcpy(item + 6, first_ + 6, 2);
    }

private:
    InLayer* layers_;
    bool nir_;
    uint8_t first_[8] = {};
    ChannelContexts<RgbContext> rgb_;
    ChannelContexts<NirContext> nirContexts_;
};

class ColourEncoder final : public ItemEncoder {
public:
    ColourEncoder(OutLayer* layers, bool nir) : layers_(layers), nir_(nir) {}

    void init(const uint8_t* first, uint32_t& channel) override {
        rgb_.init(channel, RgbContext(first));
        if (nir_) nirContexts_.init(channel, NirContext(bytes::get<uint16_t>(first + 6)));
    }

    void encode(const uint8_t* item, uint32_t& channel) override {
        layers_[0].changed |= encodeRgb(layers_[0].enc, rgb_.select(channel), item);
        if (nir_) layers_[1].changed |= encodeNir(layers_[1].enc, nirContexts_.select(channel), item + 6);
    }

private:
    OutLayer* layers_;
    bool nir_;
    ChannelContexts<RgbContext> rgb_;
    ChannelContexts<NirContext> nirContexts_;
};

// ---------------------------------------------------------------------------------------------
// BYTE14: every extra byte its own layer, coded as its difference from the last.

struct BytesContext {
    std::vector<uint8_t> last;
    std::vector<std::unique_ptr<SymbolModel>> models;   // made when first used: a skipped byte needs none
    BytesContext(const uint8_t* first, size_t n) : last(first, first + n), models(n) {}
    BytesContext(const BytesContext& from) : last(from.last), models(from.last.size()) {}
};

class BytesDecoder final : public ItemDecoder {
public:
    BytesDecoder(InLayer* layers, size_t n) : layers_(layers), n_(n) {}

    void init(const uint8_t* first, uint32_t& channel) override {
        first_.assign(first, first + n_);
        for (size_t i = 0; i < n_; ++i) any_ |= layers_[i].active;
        if (any_) contexts_.init(channel, BytesContext(first, n_));
    }

    void decode(uint8_t* item, uint32_t& channel) override {
        if (!any_) {
            std::memcpy(item, first_.data(), n_);
            return;
        }
        const auto [c, owner] = contexts_.select(channel);
        std::vector<uint8_t>& last = owner.last;
        for (size_t i = 0; i < n_; ++i) {
            if (layers_[i].active) last[i] = fold8(last[i] + int32_t(layers_[i].dec.decodeSymbol(lazyModel(c.models[i], 256))));
            item[i] = last[i];
        }
    }

private:
    InLayer* layers_;
    size_t n_;
    bool any_ = false;
    std::vector<uint8_t> first_;
    ChannelContexts<BytesContext> contexts_;
};

class BytesEncoder final : public ItemEncoder {
public:
    BytesEncoder(OutLayer* layers, size_t n) : layers_(layers), n_(n) {}

    void init(const uint8_t* first, uint32_t& channel) override { contexts_.init(channel, BytesContext(first, n_)); }

    void encode(const uint8_t* item, uint32_t& channel) override {
        const auto [c, owner] = contexts_.select(channel);
        std::vector<uint8_t>& last = owner.last;
        for (size_t i = 0; i < n_; ++i) {
            const int32_t diff = int32_t(item[i]) - int32_t(last[i]);
            layers_[i].enc.encodeSymbol(lazyModel(c.models[i], 256), fold8(diff));
            if (diff != 0) {
                layers_[i].changed = true;
                last[i] = item[i];
            }
        }
    }

private:
    OutLayer* layers_;
    size_t n_;
    ChannelContexts<BytesContext> contexts_;
};

// ---------------------------------------------------------------------------------------------
// WAVEPACKET14: descriptor index (byte 0), offset u64 (1), packet size u32 (9), return point and
// x, y, z (float bits, 13..28).

struct WaveContext {
    uint8_t last[29] = {};
    int32_t lastOffsetDiff = 0;
    uint32_t lastOffsetKind = 0;   // 0 same offset, 1 right after the last packet, 2 a 32-bit difference, 3 raw
    SymbolModel index{256};
    std::vector<SymbolModel> offsetKinds = std::vector<SymbolModel>(4, SymbolModel(4));
    IntegerCodec offsetDiff{32}, packetSize{32}, returnPoint{32}, xyz{32, 3};

    explicit WaveContext(const uint8_t* first) { std::memcpy(last, first, 29); }
    WaveContext(const WaveContext& from) { std::memcpy(last, from.last, 29); }
};

class WaveDecoder final : public ItemDecoder {
public:
    explicit WaveDecoder(InLayer* layer) : layer_(layer) {}

    void init(const uint8_t* first, uint32_t& channel) override {
        std::memcpy(first_, first, 29);
        if (layer_->active) contexts_.init(channel, WaveContext(first));
    }

    void decode(uint8_t* item, uint32_t& channel) override {
        if (!layer_->active) {
            std::memcpy(item, first_, 29);
            return;
        }
        ArithmeticDecoder& dec = layer_->dec;
        const auto [c, owner] = contexts_.select(channel);
        uint8_t* last = owner.last;
        item[0] = uint8_t(dec.decodeSymbol(c.index));
        const uint64_t lastOffset = bytes::get<uint64_t>(last + 1);
        const uint32_t lastSize = bytes::get<uint32_t>(last + 9);
        c.lastOffsetKind = dec.decodeSymbol(c.offsetKinds[c.lastOffsetKind]);
        uint64_t offset;
        switch (c.lastOffsetKind) {
        case 0: offset = lastOffset; break;
        case 1: offset = lastOffset + lastSize; break;
        case 2:
            c.lastOffsetDiff = c.offsetDiff.decompress(dec, c.lastOffsetDiff);
            offset = lastOffset + uint64_t(int64_t(c.lastOffsetDiff));
            break;
        default: offset = dec.readInt64(); break;
        }
        bytes::put(item + 1, offset);
        bytes::put(item + 9, c.packetSize.decompress(dec, int32_t(lastSize)));
        bytes::put(item + 13, c.returnPoint.decompress(dec, bytes::get<int32_t>(last + 13)));
        for (uint32_t i = 0; i < 3; ++i) bytes::put(item + 17 + 4 * i, c.xyz.decompress(dec, bytes::get<int32_t>(last + 17 + 4 * i), i));
        std::memcpy(last, item, 29);
    }

private:
    InLayer* layer_;
    uint8_t first_[29] = {};
    ChannelContexts<WaveContext> contexts_;
};

class WaveEncoder final : public ItemEncoder {
public:
    explicit WaveEncoder(OutLayer* layer) : layer_(layer) {}

    void init(const uint8_t* first, uint32_t& channel) override { contexts_.init(channel, WaveContext(first)); }

    void encode(const uint8_t* item, uint32_t& channel) override {
        ArithmeticEncoder& enc = layer_->enc;
        const auto [c, owner] = contexts_.select(channel);
        uint8_t* last = owner.last;
        layer_->changed |= std::memcmp(item, last, 29) != 0;
        enc.encodeSymbol(c.index, item[0]);
        const int64_t diff64 = int64_t(bytes::get<uint64_t>(item + 1) - bytes::get<uint64_t>(last + 1));
        const int32_t diff = int32_t(diff64);
        const uint32_t lastSize = bytes::get<uint32_t>(last + 9);
        uint32_t kind = 3;
        if (diff64 == int64_t(diff)) kind = diff == 0 ? 0 : (diff == int32_t(lastSize) ? 1 : 2);
        enc.encodeSymbol(c.offsetKinds[c.lastOffsetKind], kind);
        c.lastOffsetKind = kind;
        if (kind == 2) {
            c.offsetDiff.compress(enc, c.lastOffsetDiff, diff);
            c.lastOffsetDiff = diff;
        } else if (kind == 3) {
            enc.writeInt64(bytes::get<uint64_t>(item + 1));
        }
        c.packetSize.compress(enc, int32_t(lastSize), bytes::get<int32_t>(item + 9));
        c.returnPoint.compress(enc, bytes::get<int32_t>(last + 13), bytes::get<int32_t>(item + 13));
        for (uint32_t i = 0; i < 3; ++i) c.xyz.compress(enc, bytes::get<int32_t>(last + 17 + 4 * i), bytes::get<int32_t>(item + 17 + 4 * i), i);
        std::memcpy(last, item, 29);
    }

private:
    OutLayer* layer_;
    ChannelContexts<WaveContext> contexts_;
};

// ---------------------------------------------------------------------------------------------
// The chunk

struct ItemPlan {
    ItemType type;
    const char* name;
    uint32_t offset;       // in the record
    uint32_t size;
    uint32_t firstLayer;   // index of its first layer among the chunk's
    uint32_t layers;
};

const char* itemName(ItemType t) {
    switch (t) {
    case ItemType::Point14: return "POINT14";
    case ItemType::Rgb14: return "RGB14";
    case ItemType::RgbNir14: return "RGBNIR14";
    case ItemType::WavePacket14: return "WAVEPACKET14";
    case ItemType::Byte14: return "BYTE14";
    default: return "?";
    }
}

/// Checks the items for a layered chunk and lays out their layers.
Result<std::vector<ItemPlan>> planItems(const LaszipVlr& vlr) {
    std::vector<ItemPlan> plan;
    uint32_t offset = 0, layers = 0;
    for (size_t i = 0; i < vlr.items.size(); ++i) {
        const Item& item = vlr.items[i];
        ItemPlan p{item.type, itemName(item.type), offset, item.size, layers, 0};
        uint32_t size = 0;
        switch (item.type) {
        case ItemType::Point14: p.layers = kPoint14Layers, size = 30; break;
        case ItemType::Rgb14: p.layers = 1, size = 6; break;
        case ItemType::RgbNir14: p.layers = 2, size = 8; break;
        case ItemType::WavePacket14: p.layers = 1, size = 29; break;
        case ItemType::Byte14: p.layers = item.size, size = item.size; break;
        default: return fail("item %zu (type %u) cannot be in a layered chunk", i + 1, unsigned(item.type));
        }
        if (item.version != 3) return fail("item %s has version %u, layered chunks need version 3", p.name, unsigned(item.version));
        if (item.size != size || size == 0) return fail("item %s has %u bytes, not %u", p.name, unsigned(item.size), size);
        if ((item.type == ItemType::Point14) != (i == 0)) return fail("a layered chunk's first item, and only it, must be POINT14");
        plan.push_back(p);
        offset += size;
        layers += p.layers;
    }
    if (plan.empty()) return fail("a layered chunk needs items");
    return plan;
}

void layerName(const ItemPlan& item, uint32_t layer, char* text, size_t size) {
    if (item.type == ItemType::Point14) std::snprintf(text, size, "%s", kPoint14LayerNames[layer]);
    else if (item.type == ItemType::RgbNir14) std::snprintf(text, size, "%s", layer == 0 ? "RGB" : "NIR");
    else if (item.type == ItemType::Byte14) std::snprintf(text, size, "byte %u", layer);
    else std::snprintf(text, size, "%s", item.type == ItemType::Rgb14 ? "RGB" : "wavepacket");
}

/// Whether `fields` asks for the layer (positions are always decoded).
bool wanted(const ItemPlan& item, uint32_t layer, uint32_t fields) {
    switch (item.type) {
    case ItemType::Point14: return layer == kXY || layer == kZ || (fields & kFieldAttributes);
    case ItemType::Rgb14: return fields & kFieldRgb;
    case ItemType::RgbNir14: return fields & (layer == 0 ? kFieldRgb : kFieldNir);
    case ItemType::Byte14: return fields & kFieldExtraBytes;
    default: return fields & kFieldWaveform;
    }
}

}  // namespace

Result<void> decodeLayeredChunk(const LaszipVlr& vlr, std::span<const uint8_t> data, uint64_t count, uint32_t fields, uint8_t* out) {
    if (count == 0) return {};
    auto planned = planItems(vlr);
    if (!planned) return planned.error();
    const std::vector<ItemPlan>& items = *planned;
    const size_t recordLength = items.back().offset + items.back().size;

    if (data.size() < recordLength) return fail("the chunk ends inside its first point (%zu of %zu bytes)", data.size(), recordLength);
    std::memcpy(out, data.data(), recordLength);
    size_t at = recordLength;
    // A one-point chunk needs nothing past its first point (LASzip writes the rest all the same).
    if (count == 1 && at == data.size()) return {};
    if (data.size() - at < 4) return fail("the chunk ends before its point count");
    const uint32_t own = bytes::get<uint32_t>(data.data() + at);
    at += 4;
    if (own != count) return fail("the chunk says it holds %u points, the chunk table %llu", own, static_cast<unsigned long long>(count));

    const uint32_t totalLayers = items.back().firstLayer + items.back().layers;
    if ((data.size() - at) / 4 < totalLayers) return fail("the chunk ends inside its table of %u layer sizes", totalLayers);
    std::vector<InLayer> layers(totalLayers);
    for (InLayer& layer : layers) {
        layer.size = bytes::get<uint32_t>(data.data() + at);
        at += 4;
    }
    for (const ItemPlan& item : items) {
        for (uint32_t l = 0; l < item.layers; ++l) {
            InLayer& layer = layers[item.firstLayer + l];
            if (layer.size > data.size() - at) {
                char name[32];
                layerName(item, l, name, sizeof name);
                return fail("layer '%s' of item %s (%u bytes) runs past the chunk's end (%zu bytes left)", name, item.name, layer.size, data.size() - at);
            }
            layer.bytes = data.data() + at;
            at += layer.size;
            layer.active = layer.size > 0 && wanted(item, l, fields);
            if (layer.active) layer.dec.init(layer.bytes, layer.size);
        }
    }

    // Every point has its channel_returns_XY symbols; no stream to read them from is corrupt (and
    // would leave the decoder uninitialised).
    if (count > 1 && layers[kXY].size == 0) return fail("layer 'channel_returns_XY' of item POINT14 is empty");

    std::vector<std::unique_ptr<ItemDecoder>> decoders;
    for (const ItemPlan& item : items) {
        InLayer* first = layers.data() + item.firstLayer;
        switch (item.type) {
        case ItemType::Point14: decoders.push_back(makePoint14Decoder(first)); break;
        case ItemType::Rgb14: decoders.push_back(std::make_unique<ColourDecoder>(first, false)); break;
        case ItemType::RgbNir14: decoders.push_back(std::make_unique<ColourDecoder>(first, true)); break;
        case ItemType::Byte14: decoders.push_back(std::make_unique<BytesDecoder>(first, item.size)); break;
        default: decoders.push_back(std::make_unique<WaveDecoder>(first)); break;
        }
    }
    uint32_t channel = 0;
    for (size_t i = 0; i < items.size(); ++i) decoders[i]->init(out + items[i].offset, channel);

    for (uint64_t p = 1; p < count; ++p) {
        uint8_t* record = out + p * recordLength;
        channel = 0;   // POINT14 sets it only where the channel changes (see ChannelContexts)
        for (size_t i = 0; i < items.size(); ++i) decoders[i]->decode(record + items[i].offset, channel);
    }

    // A layer that needed bytes past its end was cut short (the coder's flush leaves a few to spare).
    for (const ItemPlan& item : items) {
        for (uint32_t l = 0; l < item.layers; ++l) {
            const InLayer& layer = layers[item.firstLayer + l];
            if (layer.active && layer.dec.overrun() > 4) {
                char name[32];
                layerName(item, l, name, sizeof name);
                return fail("layer '%s' of item %s ends early", name, item.name);
            }
        }
    }
    return {};
}

Result<void> encodeLayeredChunk(const LaszipVlr& vlr, const uint8_t* records, uint64_t count, std::vector<uint8_t>& out) {
    if (count == 0) return {};
    if (count > UINT32_MAX) return fail("a chunk holds at most 2^32 - 1 points, not %llu", static_cast<unsigned long long>(count));
    auto planned = planItems(vlr);
    if (!planned) return planned.error();
    const std::vector<ItemPlan>& items = *planned;
    const size_t recordLength = items.back().offset + items.back().size;
    const uint32_t totalLayers = items.back().firstLayer + items.back().layers;

    std::unique_ptr<OutLayer[]> layers(new OutLayer[totalLayers]);
    std::vector<std::unique_ptr<ItemEncoder>> encoders;
    for (const ItemPlan& item : items) {
        OutLayer* first = layers.get() + item.firstLayer;
        switch (item.type) {
        case ItemType::Point14:
            encoders.push_back(makePoint14Encoder(first));
            // LASzip always writes these two, changing or not.
            first[kXY].changed = first[kZ].changed = true;
            break;
        case ItemType::Rgb14: encoders.push_back(std::make_unique<ColourEncoder>(first, false)); break;
        case ItemType::RgbNir14: encoders.push_back(std::make_unique<ColourEncoder>(first, true)); break;
        case ItemType::Byte14: encoders.push_back(std::make_unique<BytesEncoder>(first, item.size)); break;
        default: encoders.push_back(std::make_unique<WaveEncoder>(first)); break;
        }
    }
    uint32_t channel = 0;
    for (size_t i = 0; i < items.size(); ++i) encoders[i]->init(records + items[i].offset, channel);
    for (uint64_t p = 1; p < count; ++p) {
        const uint8_t* record = records + p * recordLength;
        channel = 0;
        for (size_t i = 0; i < items.size(); ++i) encoders[i]->encode(record + items[i].offset, channel);
    }

    out.insert(out.end(), records, records + recordLength);
    uint8_t word[4];
    bytes::put(word, uint32_t(count));
    out.insert(out.end(), word, word + 4);
    for (uint32_t l = 0; l < totalLayers; ++l) {
        layers[l].enc.done();
        bytes::put(word, layers[l].changed ? uint32_t(layers[l].bytes.size()) : 0u);
        out.insert(out.end(), word, word + 4);
    }
    for (uint32_t l = 0; l < totalLayers; ++l) {
        if (layers[l].changed) out.insert(out.end(), layers[l].bytes.begin(), layers[l].bytes.end());
    }
    return {};
}

}  // namespace orbis::points::laz::detail
