// The out-of-core builds' files and chunks (OutOfCore.h).
#include "layers/points/OutOfCore.h"

#include "layers/points/PointStoreFormat.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace orbis::points::ooc {

Result<void> File::create(const std::string& path) {
    path_ = path;
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) return fail("cannot create");
    return {};
}

Result<void> File::write(const void* data, uint64_t bytes, uint64_t offset) {
    auto* p = static_cast<const uint8_t*>(data);
    while (bytes > 0) {
        const ssize_t w = ::pwrite(fd_, p, bytes, off_t(offset));
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return fail("cannot write (disk full?)");
        p += w, bytes -= uint64_t(w), offset += uint64_t(w);
    }
    return {};
}

Result<void> File::read(void* out, uint64_t bytes, uint64_t offset) const {
    if (!store::preadAll(fd_, out, bytes, offset)) return fail("cannot read");
    return {};
}

Result<void> File::sync() {
    if (::fdatasync(fd_) != 0) return fail("cannot flush to the disk");
    return {};
}

void File::close(bool remove) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    if (remove && !path_.empty()) ::unlink(path_.c_str());
    path_.clear();
}

Error File::fail(const char* what) const {
    return Error{std::string(path_).append(": ").append(what).append(": ").append(std::strerror(errno))};
}

std::vector<Chunk> makeChunks(const std::vector<uint32_t>& counts, uint32_t levels, uint64_t maxPoints) {
    // Counts per level, finest first (level l: (2^l)^3 cells, x | y << l | z << 2l).
    std::vector<std::vector<uint64_t>> pyramid(levels + 1);
    pyramid[levels].assign(counts.begin(), counts.end());
    for (uint32_t l = levels; l-- > 0;) {
        const uint32_t side = 1u << l;
        pyramid[l].assign(size_t(side) * side * side, 0);
        for (uint32_t z = 0; z < 2 * side; ++z)
            for (uint32_t y = 0; y < 2 * side; ++y)
                for (uint32_t x = 0; x < 2 * side; ++x)
                    pyramid[l][Cell{l, x >> 1, y >> 1, z >> 1}.index()] += pyramid[l + 1][Cell{l + 1, x, y, z}.index()];
    }
    std::vector<Chunk> chunks;
    std::vector<Cell> stack{Cell{}};
    while (!stack.empty()) {
        const Cell c = stack.back();
        stack.pop_back();
        const uint64_t n = pyramid[c.level][c.index()];
        if (n == 0) continue;
        if (n <= maxPoints || c.level == levels) {
            chunks.push_back({c, n, 0});
            continue;
        }
        for (int o = 0; o < 8; ++o) stack.push_back(c.child(o));
    }
    uint64_t first = 0;
    for (Chunk& c : chunks) c.first = first, first += c.count;
    return chunks;
}

std::vector<uint32_t> chunkOfCells(const std::vector<Chunk>& chunks, uint32_t levels) {
    const size_t side = size_t(1) << levels;
    std::vector<uint32_t> chunkOf(side * side * side, 0);
    for (uint32_t c = 0; c < chunks.size(); ++c) {
        const Cell& cell = chunks[c].cell;
        const uint32_t shift = levels - cell.level, span = 1u << shift;
        for (uint32_t z = 0; z < span; ++z)
            for (uint32_t y = 0; y < span; ++y)
                for (uint32_t x = 0; x < span; ++x)
                    chunkOf[Cell{levels, cell.x << shift | x, cell.y << shift | y, cell.z << shift | z}.index()] = c;
    }
    return chunkOf;
}

}  // namespace orbis::points::ooc
