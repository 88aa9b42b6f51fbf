#pragma once
// Writes a LAS or LAZ cloud as COPC 1.0 (Cloud Optimized Point Cloud, https://copc.io): a LAZ
// 1.4 file (point format 6, 7 with colours, 8 with near-infrared) whose layered chunks are the
// nodes of an octree, described by the `copc` info VLR (the first VLR) and one hierarchy page
// (the "EPT hierarchy" EVLR). CPU only. The output reads back through LasFile and copc::.
//
// The octree: the root is the cube around the points' bounds (centred on them, its edge the
// largest extent). Every point gets a pseudo-random key from its index in the input (pointKey,
// as PointOctree); in key order each point goes to the first node on its path with room for it
// (`maxNodePoints`), so every node holds a uniform random sample of what reaches its cube, and a
// node of `maxLevel` keeps everything that reaches it. Each node is one LAZ chunk; inside it the
// points keep the input's order (acquisition order usually, which LAZ compresses best).
//
// Points keep every attribute LasPoint carries: the positions as the same integers (the input's
// scale and offset are kept), intensity, returns, classification, the flags, user data, scan
// angle (a LAS 1.0-1.3 angle in degrees becomes 0.006 degree steps), point source, GPS time, RGB,
// NIR, scan direction, edge of flight line and scanner channel. What LasPoint does not carry is
// not written: extra bytes and waveform packets.
//
// Memory is bounded, so clouds larger than RAM convert: the octree is built out of core (as the
// point cache's is, PointCacheBuild.cpp) in batches of at most `batchPoints` points (about 72
// bytes each in memory), plus 4 bytes for each point of the nodes above the batches' cells and the
// chunks being encoded. A cloud of more points than a batch goes through temporary files next to
// the output (about 100 bytes a point on the disk at the peak: 48 in a spill file, then in a chunk
// file); a smaller one stays in memory. The tree does not depend on `batchPoints`: it is the one
// the whole cloud inserted in key order makes. (A batch is a cell of a 128^3 grid over the root
// cube at the finest: points closer together than that are one batch whatever its size.)

#include "base/Result.h"

#include <cstdint>
#include <functional>
#include <string>

namespace orbis::points {

class LasFile;

struct CopcWriteOptions {
    uint32_t maxNodePoints = 100000;   ///< a node keeps at most this many points, the rest go to its children
    uint32_t maxLevel = 16;            ///< the deepest level keeps every point that reaches it (at most 30)
    uint64_t batchPoints = 10000000;   ///< points held in memory at once (at least 8 x maxNodePoints)
    std::function<void(double)> progress;   ///< 0..1, called on the calling thread
};

struct CopcWriteStats {
    uint64_t points = 0;
    uint32_t nodes = 0, depth = 0;   ///< nodes with points; the deepest level (the root's is 0)
    uint64_t bytes = 0;              ///< the file's size
    uint32_t batches = 0;            ///< the cells the octree was built in, one after the other
};

/// Writes every point of `in` (LAS or LAZ, any format) as a COPC 1.0 file at `path`: LAS 1.4,
/// point format 6, 7 (colours) or 8 (near-infrared), the input's scale, offset and CRS (as a WKT
/// VLR, WKT1 where it can be expressed so; COPC requires WKT), layered LAZ chunks, one per octree
/// node. A cloud without a CRS is refused. Errors name the file; a file left half written is
/// removed.
Result<CopcWriteStats> writeCopc(const LasFile& in, const std::string& path, const CopcWriteOptions& options);

}  // namespace orbis::points
