#pragma once
// What the out-of-core octree builds share (PointCacheBuild.cpp: the point cache; CopcWriter.cpp:
// COPC files): temporary files of fixed-size records, read and written a block at a time, and the
// split of the root cube into chunks (the largest cells of a counting grid that hold at most so
// many points) whose records are then copied next to each other. Internal to layers/points.

#include "base/Result.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace orbis::points::ooc {

/// A temporary or output file, written and read at offsets; removed when closed with `remove`
/// (and when destroyed while open).
class File {
public:
    File() = default;
    File(const File&) = delete;
    File& operator=(const File&) = delete;
    ~File() { close(true); }
    Result<void> create(const std::string& path);
    Result<void> write(const void* data, uint64_t bytes, uint64_t offset);
    Result<void> read(void* out, uint64_t bytes, uint64_t offset) const;
    /// Waits until the data written is on the disk.
    Result<void> sync();
    /// Closes; `remove`: deletes the file too (temporary files, failed builds).
    void close(bool remove);
    const std::string& path() const { return path_; }

private:
    Error fail(const char* what) const;
    int fd_ = -1;
    std::string path_;
};

/// Records appended to a file through a buffer.
template <typename T>
class RecordWriter {
public:
    explicit RecordWriter(File& f) : file_(f) { buffer_.reserve(kBuffer); }
    Result<void> add(std::span<const T> r) {
        for (const T& p : r)
            if (auto w = add(p); !w) return w;
        return {};
    }
    Result<void> add(const T& p) {
        buffer_.push_back(p);
        if (buffer_.size() == kBuffer) return flush();
        return {};
    }
    Result<void> flush() {
        auto w = file_.write(buffer_.data(), buffer_.size() * sizeof(T), written_ * sizeof(T));
        written_ += buffer_.size();
        buffer_.clear();
        return w;
    }
    uint64_t written() const { return written_ + buffer_.size(); }

private:
    static constexpr size_t kBuffer = (size_t(2) << 20) / sizeof(T);
    File& file_;
    std::vector<T> buffer_;
    uint64_t written_ = 0;
};

/// Calls fn(records) over records [0, count) of `file`, a block at a time; stops with an error
/// ("cancelled") when `cancel` is set.
template <typename T, typename Fn>
Result<void> forEachBlock(const File& file, uint64_t count, const std::atomic<bool>* cancel, Fn&& fn) {
    std::vector<T> block;
    constexpr uint64_t kBlock = (uint64_t(16) << 20) / sizeof(T);
    for (uint64_t first = 0; first < count; first += kBlock) {
        if (cancel && cancel->load()) return makeError("cancelled");
        block.resize(std::min(kBlock, count - first));
        if (auto r = file.read(block.data(), block.size() * sizeof(T), first * sizeof(T)); !r) return r;
        fn(std::span<const T>(block));
    }
    return {};
}

/// A cell of the counting grid: its level and its index on each axis.
struct Cell {
    uint32_t level = 0, x = 0, y = 0, z = 0;
    uint64_t packed() const { return uint64_t(level) << 60 | uint64_t(x) << 40 | uint64_t(y) << 20 | z; }
    /// Its index among the (2^level)^3 cells of its level.
    size_t index() const { return x | size_t(y) << level | size_t(z) << (2 * level); }
    Cell child(int octant) const {
        return {level + 1, x << 1 | uint32_t(octant & 1), y << 1 | uint32_t((octant >> 1) & 1), z << 1 | uint32_t((octant >> 2) & 1)};
    }
    /// The octant its path from the root takes at level l (< level).
    int octantAt(uint32_t l) const {
        const uint32_t s = level - 1 - l;
        return int(((x >> s) & 1) | ((y >> s) & 1) << 1 | ((z >> s) & 1) << 2);
    }
};

/// A chunk: a cell and its records' range in the chunk file.
struct Chunk {
    Cell cell;
    uint64_t count = 0, first = 0;
};

/// The largest cells holding at most `maxPoints` (or of the grid's finest level), from the
/// counts of the finest level's cells (indexed by Cell::index); their ranges follow each other.
std::vector<Chunk> makeChunks(const std::vector<uint32_t>& counts, uint32_t levels, uint64_t maxPoints);

/// For each finest cell of the grid, the index of the chunk that holds it.
std::vector<uint32_t> chunkOfCells(const std::vector<Chunk>& chunks, uint32_t levels);

/// Copies the `count` records of `spill` into their chunks' ranges of `out` (chunkOf(record)
/// names a record's chunk), through a buffer per chunk (64 MB in all).
template <typename T, typename ChunkOf>
Result<void> distribute(const File& spill, uint64_t count, const std::atomic<bool>* cancel, ChunkOf&& chunkOf,
                        const std::vector<Chunk>& chunks, File& out) {
    const size_t perChunk = std::clamp<size_t>((size_t(64) << 20) / sizeof(T) / std::max<size_t>(chunks.size(), 1), 256, 1u << 16);
    std::vector<std::vector<T>> buffers(chunks.size());
    std::vector<uint64_t> cursor(chunks.size());
    for (size_t c = 0; c < chunks.size(); ++c) cursor[c] = chunks[c].first;
    Result<void> written;   // the first write error, if any
    const auto flush = [&](size_t c) {
        if (written) written = out.write(buffers[c].data(), buffers[c].size() * sizeof(T), cursor[c] * sizeof(T));
        cursor[c] += buffers[c].size();
        buffers[c].clear();
    };
    auto r = forEachBlock<T>(spill, count, cancel, [&](std::span<const T> block) {
        for (const T& p : block) {
            const uint32_t c = chunkOf(p);
            buffers[c].push_back(p);
            if (buffers[c].size() >= perChunk) flush(c);
        }
    });
    if (!r) return r;
    for (size_t c = 0; c < chunks.size(); ++c) flush(c);
    return written;
}

}  // namespace orbis::points::ooc
