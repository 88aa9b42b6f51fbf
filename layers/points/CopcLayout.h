#pragma once
// The bytes of a COPC 1.0 file around its point chunks, as CopcWriter.cpp writes them: the LAS
// 1.4 header with the copc info VLR first (at byte 375), the laszip VLR and the CRS as a WKT VLR;
// the hierarchy as one page in an EVLR. Internal to layers/points.

#include "layers/points/Copc.h"
#include "layers/points/LazChunks.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace orbis::points {

/// Nodes in the order they are written: level by level, then z, y, x.
bool levelOrder(const copc::Key& p, const copc::Key& q);

/// The CRS as WKT1 (OGC 01-009, what LAS 1.4 and COPC readers parse): kept as it is when it is
/// WKT1 already, else converted by OGR; the text as it came when OGR cannot express it as WKT1.
std::string wkt1(const std::string& crs);

/// The laszip VLR of a COPC file of point format 6, 7 or 8: layered chunks of variable size.
laz::LaszipVlr copcLaszip(uint8_t format);

/// The header (zeros until fillCopcHead) and the VLRs, then 8 bytes for the chunk table's
/// offset: the points start right after.
std::vector<uint8_t> copcHead(const laz::LaszipVlr& laszip, const std::string& wkt);

/// The hierarchy EVLR: its 60-byte header and one page of `entries` in level order (an empty
/// cloud: one entry, the root's, with no points).
std::vector<uint8_t> hierarchyEvlr(std::vector<copc::Node> entries);

/// What the header says of the file once its parts are placed.
struct CopcHeadFields {
    uint16_t globalEncoding = 0;   ///< the input's (its GPS time's kind is kept)
    uint8_t format = 6;
    uint16_t recordLength = 30;
    glm::dvec3 scale{1.0}, offset{0.0}, lo{0.0}, hi{0.0};
    uint64_t points = 0;
    std::array<uint64_t, 15> byReturn{};
    uint64_t evlrAt = 0, chunkTableAt = 0;
};

/// Fills the header and the copc info VLR of `head` (from copcHead); `info`'s root page is
/// where the hierarchy EVLR's page starts.
void fillCopcHead(std::vector<uint8_t>& head, const CopcHeadFields& f, const copc::Info& info);

}  // namespace orbis::points
