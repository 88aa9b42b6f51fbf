#pragma once
// Inside the LAS/LAZ/COPC readers and writers: little-endian values in byte buffers (the formats
// are little-endian, as is every machine Orbis builds for) and a point's LAS record.

#include "layers/points/LasReader.h"

#include <cstdint>
#include <cstring>

namespace orbis::points {

namespace bytes {
template <typename T>
T get(const uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}
template <typename T>
void put(uint8_t* p, T v) {
    std::memcpy(p, &v, sizeof(T));
}
}  // namespace bytes

/// Writes `p` as a record of point format `format` (0..10) at `r` (the format's standard bytes;
/// extra bytes are the caller's), its position as the integers `q` (already scaled and offset).
/// Attributes a format does not hold are left out; angles in 0.006 degree steps (formats 6..10)
/// or whole degrees.
void packLasRecord(const LasPoint& p, const int32_t q[3], uint8_t format, uint8_t* r);

}  // namespace orbis::points
