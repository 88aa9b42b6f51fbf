#pragma once
// What the two builds of a PointStore share (PointStoreBuild.cpp: in memory for small clouds,
// and where the cache file is and what it is built from; PointCacheBuild.cpp: the out-of-core
// build into that file): pass 1 (every point read, placed and measured), the packing of node
// data, and appending a built tree to the node table. Internal to layers/points.

#include "base/Result.h"
#include "layers/points/PointCloud.h"
#include "layers/points/PointOctree.h"
#include "layers/points/PointStoreFormat.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace orbis::points::build {

/// The error of a load cancelled through PointLoadOptions::cancel.
Error cancelled(const LasFile& file);

/// What pass 1 learns of the cloud on the way.
struct Statistics {
    CloudInfo info;
    glm::dvec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
    uint64_t kept = 0;
};

/// Takes a batch of records; an error stops the read.
using RecordSink = std::function<Result<void>(std::span<const PointRecord>)>;

/// Pass 1: every point read, placed in ECEF and handed to `sink` in batches (points without a
/// finite position are dropped and counted); progress runs up to `progressTo`.
Result<Statistics> readRecords(const LasFile& file, const PointGeoreference& georef, const PointLoadOptions& options,
                               double progressTo, const RecordSink& sink);

/// How node data is packed for this cloud: its height ramp and quantisation tolerance.
store::Packing packingFor(const Statistics& s, double tolerance, bool morton);

/// Appends the nodes of `tree` (built over `points`) to `nodes`, their data to `data` (its
/// size so far is where they start); the subtree's root gets `parent`. Returns the root's index.
int32_t appendTree(const PointOctree& tree, std::span<const PointRecord> points, const store::Packing& packing, int32_t parent,
                   uint64_t dataBase, std::vector<StoredNode>& nodes, std::vector<uint8_t>& data);

/// The out-of-core build's inputs; temporary files go to folder/stem.*.tmp.
struct BuildContext {
    const LasFile& file;
    const PointGeoreference& georef;
    const PointLoadOptions& options;
    std::string folder, stem;   // temporary files: folder/stem.*.tmp
    void progress(double f) const {
        if (options.progress) options.progress(f);
    }
    bool cancelled() const { return options.cancel && options.cancel->load(); }
};

/// Builds the cache file `out` (which starts with `key`) out of core, pass by pass
/// (PointCacheBuild.cpp).
Result<void> buildCacheFile(const BuildContext& ctx, const std::string& out, const std::string& key, double tolerance);

}  // namespace orbis::points::build
