#include "layers/models/GltfImage.h"

#include <zlib.h>

#include <array>
#include <cstdint>
#include <cstring>

namespace orbis::models {

namespace {

constexpr std::array<unsigned char, 8> kPngSignature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

uint32_t be32(const unsigned char* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }

/// Bytes per sample row of an image `width` wide, plus its filter byte.
uint64_t rowBytes(uint64_t width, uint64_t bitsPerPixel) { return (width * bitsPerPixel + 7) / 8 + 1; }

/// The size the image data inflates to, from the header (Adam7: the seven passes' rows).
uint64_t inflatedBytes(uint32_t w, uint32_t h, uint64_t bitsPerPixel, bool interlaced) {
    if (!interlaced) return rowBytes(w, bitsPerPixel) * h;
    static constexpr int kX0[7] = {0, 4, 0, 2, 0, 1, 0}, kY0[7] = {0, 0, 4, 0, 2, 0, 1};
    static constexpr int kDx[7] = {8, 8, 4, 4, 2, 2, 1}, kDy[7] = {8, 8, 8, 4, 4, 2, 2};
    uint64_t total = 0;
    for (int p = 0; p < 7; ++p) {
        const uint64_t pw = w > uint32_t(kX0[p]) ? (w - kX0[p] + kDx[p] - 1) / kDx[p] : 0;
        const uint64_t ph = h > uint32_t(kY0[p]) ? (h - kY0[p] + kDy[p] - 1) / kDy[p] : 0;
        if (pw > 0 && ph > 0) total += rowBytes(pw, bitsPerPixel) * ph;
    }
    return total;
}

int channels(unsigned colorType) {
    switch (colorType) {
        case 0: return 1;   // grey
        case 2: return 3;   // RGB
        case 3: return 1;   // palette index
        case 4: return 2;   // grey and alpha
        case 6: return 4;   // RGBA
        default: return 0;
    }
}

std::string checkPng(const unsigned char* bytes, size_t size) {
    size_t at = kPngSignature.size();
    uint64_t expected = 0;
    z_stream z{};
    if (inflateInit(&z) != Z_OK) return "cannot start zlib";
    struct End {
        z_stream& z;
        ~End() { inflateEnd(&z); }
    } end{z};
    std::array<unsigned char, 16384> scratch;
    uint64_t inflated = 0;
    bool header = false, ended = false;
    while (!ended) {
        if (size - at < 12) return "a PNG ends without its IEND chunk";
        const uint32_t length = be32(bytes + at);
        const unsigned char* type = bytes + at + 4;
        if (length > size - at - 12) return "a PNG chunk runs past the end of the data";
        const unsigned char* data = bytes + at + 8;
        if (std::memcmp(type, "IHDR", 4) == 0) {
            if (length != 13) return "a PNG's IHDR chunk is not 13 bytes";
            const uint32_t w = be32(data), h = be32(data + 4);
            const int ch = channels(data[9]);
            if (ch == 0) return "a PNG's colour type is not one PNG defines";
            expected = inflatedBytes(w, h, uint64_t(ch) * data[8], data[12] != 0);
            header = true;
        } else if (std::memcmp(type, "IDAT", 4) == 0) {
            if (!header) return "a PNG's image data comes before its IHDR chunk";
            z.next_in = const_cast<unsigned char*>(data);
            z.avail_in = length;
            while (z.avail_in > 0) {
                z.next_out = scratch.data();
                z.avail_out = uInt(scratch.size());
                const int r = inflate(&z, Z_NO_FLUSH);
                inflated += scratch.size() - z.avail_out;
                if (inflated > expected) return "a PNG's image data inflates past the size its header gives";
                if (r == Z_STREAM_END) break;
                if (r != Z_OK) return "a PNG's image data is not a zlib stream";
            }
        } else if (std::memcmp(type, "IEND", 4) == 0) {
            ended = true;
        }
        at += 12 + size_t(length);
    }
    return header ? "" : "a PNG has no IHDR chunk";
}

}  // namespace

std::string checkGltfImageBytes(const unsigned char* bytes, size_t size) {
    if (size >= kPngSignature.size() && std::memcmp(bytes, kPngSignature.data(), kPngSignature.size()) == 0)
        return checkPng(bytes, size);
    if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return "";   // JPEG
    return "not a PNG or JPEG (the image formats of glTF)";
}

}  // namespace orbis::models
