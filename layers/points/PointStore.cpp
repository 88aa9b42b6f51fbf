#include "layers/points/PointStore.h"

#include "layers/points/PointStoreFormat.h"

#include "base/Log.h"

#include <fcntl.h>
#include <zlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

namespace orbis::points {

uint32_t store::checksum(const void* data, uint64_t bytes, uint32_t crc) {
    return uint32_t(::crc32_z(crc, static_cast<const Bytef*>(data), z_size_t(bytes)));
}

uint32_t store::tableChecksum(const FileHeader& header, const std::string& key, std::span<const StoredNode> nodes) {
    FileHeader h = header;
    h.tableCrc = 0;
    uint32_t crc = checksum(&h, sizeof h);
    crc = checksum(key.data(), key.size(), crc);
    return checksum(nodes.data(), nodes.size_bytes(), crc);
}

bool store::preadAll(int fd, void* out, uint64_t bytes, uint64_t offset) {
    auto* p = static_cast<uint8_t*>(out);
    while (bytes > 0) {
        const ssize_t r = ::pread(fd, p, bytes, off_t(offset));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        p += r, bytes -= uint64_t(r), offset += uint64_t(r);
    }
    return true;
}

std::shared_ptr<PointStore> PointStore::inMemory(std::vector<StoredNode> nodes, std::vector<uint8_t> data,
                                                 const CloudInfo& info) {
    std::shared_ptr<PointStore> s(new PointStore);
    s->nodes_ = std::move(nodes);
    s->data_ = std::move(data);
    s->info_ = info;
    return s;
}

PointStore::~PointStore() {
    if (fd_ >= 0) ::close(fd_);
}

namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

Result<std::shared_ptr<PointStore>> PointStore::open(const std::string& path, const std::string& key) {
    const auto fail = [&](const std::string& why) { return makeError(std::string("point cache ").append(path).append(": ").append(why)); };
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return fail(std::strerror(errno));
    std::shared_ptr<PointStore> s(new PointStore);
    s->fd_ = fd;   // closed with s
    s->path_ = path;
    struct stat st {};
    if (::fstat(fd, &st) != 0) return fail(std::strerror(errno));
    const uint64_t size = uint64_t(st.st_size);
    store::FileHeader h{};
    if (size < sizeof h || !store::preadAll(fd, &h, sizeof h, 0)) return fail("shorter than its header");
    if (std::memcmp(h.magic, store::kMagic, sizeof h.magic) != 0) return fail("not an Orbis point cache");
    if (h.version != store::kVersion) return fail("written by another version of Orbis");
    if (h.keyBytes > store::kMaxKeyBytes || h.dataOffset != sizeof h + h.keyBytes || h.dataOffset > size)
        return fail("bad header (key)");
    std::string stored(h.keyBytes, '\0');
    if (!store::preadAll(fd, stored.data(), h.keyBytes, sizeof h)) return fail("truncated key");
    if (stored != key) return fail("built from another file, CRS or options");
    if (h.dataBytes > size - h.dataOffset || h.nodeTableOffset != h.dataOffset + h.dataBytes ||
        (size - h.nodeTableOffset) != h.nodeCount * sizeof(StoredNode))
        return fail("sizes disagree with the file's size (truncated?)");
    s->nodes_.resize(h.nodeCount);
    if (!s->nodes_.empty() && !store::preadAll(fd, s->nodes_.data(), h.nodeCount * sizeof(StoredNode), h.nodeTableOffset))
        return fail("cannot read the node table");
    if (store::tableChecksum(h, stored, s->nodes_) != h.tableCrc) return fail("corrupted (its header or node table fails the checksum)");
    uint64_t points = 0;
    const int64_t n = int64_t(s->nodes_.size());
    for (int64_t i = 0; i < n; ++i) {
        const StoredNode& nd = s->nodes_[size_t(i)];
        const std::string which = "node " + std::to_string(i) + ": ";
        if (!finite(nd.centre) || !(nd.halfSize > 0.0) || !std::isfinite(nd.halfSize) || !(nd.step >= 0.0) ||
            !std::isfinite(nd.step) || nd.level > 64)
            return fail(which + "bad cube");
        if (nd.offset > h.dataBytes || nd.bytes() > h.dataBytes - nd.offset) return fail(which + "data outside the file");
        if (nd.parent < -1 || nd.parent >= n || (i > 0) != (nd.parent >= 0)) return fail(which + "bad parent");
        for (int32_t c : nd.children)
            if (c < -1 || c >= n || c == 0 || (c > 0 && s->nodes_[size_t(c)].parent != i)) return fail(which + "bad child");
        points += nd.count;
    }
    s->info_ = h.info;
    if (points != s->info_.points) return fail("point counts disagree");
    s->dataOffset_ = h.dataOffset;
    return s;
}

std::shared_ptr<PointStore> PointStore::streamed(std::vector<StoredNode> nodes, const CloudInfo& info, NodeSource source) {
    std::shared_ptr<PointStore> s(new PointStore());
    s->nodes_ = std::move(nodes);
    s->info_ = info;
    s->source_ = std::move(source);
    return s;
}

bool PointStore::read(size_t node, std::vector<uint8_t>& out, std::string* error) const {
    const StoredNode& n = nodes_[node];
    if (source_) {
        auto made = source_(node);
        if (made && made->size() == n.bytes()) {
            out = std::move(made).value();
            return true;
        }
        if (error) *error = made ? std::string("node ").append(std::to_string(node)).append(": its data is not the size its table says") : made.message();
        return false;
    }
    out.resize(n.bytes());
    if (fd_ < 0) {
        std::memcpy(out.data(), data_.data() + n.offset, out.size());
        return true;
    }
    if (!store::preadAll(fd_, out.data(), out.size(), dataOffset_ + n.offset)) {
        if (error) *error = std::string("point cache ").append(path_).append(": cannot read node ").append(std::to_string(node));
        return false;
    }
    if (store::checksum(out.data(), out.size()) == n.crc) return true;
    // Corrupted on disk since it was written: this run shows what it can without the node, and
    // the file goes, so that the next load builds it again.
    std::call_once(corruptOnce_, [&] {
        ::unlink(path_.c_str());
        log::error("point cache ", path_, ": node ", node, " fails its checksum: the cache is corrupted and removed; "
                   "the cloud is built again when it is next loaded");
    });
    if (error) *error = std::string("point cache ").append(path_).append(": node ").append(std::to_string(node)).append(" is corrupted");
    return false;
}

std::span<const uint8_t> PointStore::view(size_t node) const {
    if (fd_ >= 0 || source_) return {};
    const StoredNode& n = nodes_[node];
    return {data_.data() + n.offset, n.bytes()};
}

glm::dvec3 PointStore::position(const StoredNode& node, std::span<const uint8_t> data, uint32_t k) {
    const uint8_t* pos = data.data() + node.positionOffset();
    if (node.step > 0.0) {
        uint32_t w[2];
        std::memcpy(w, pos + 8 * size_t(k), sizeof w);
        const glm::uvec3 q = store::unpackPosition(w[0], w[1]);
        return node.centre + (glm::dvec3(q) - double(store::kQuantisedCentre)) * node.step;
    }
    float f[3];
    std::memcpy(f, pos + 12 * size_t(k), sizeof f);
    return node.centre + glm::dvec3(f[0], f[1], f[2]);
}

}  // namespace orbis::points
