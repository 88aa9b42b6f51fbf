#include "globe/TileCacheFs.h"

#include "base/Log.h"

#include <cpl_string.h>
#include <cpl_vsi.h>
#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string_view>
#include <vector>

namespace orbis::globe {

namespace {

constexpr std::string_view kPrefix = "/vsiorbiscache";   // followed by the absolute real path
constexpr char kPrefixSlash[] = "/vsiorbiscache/";       // as installed
constexpr uint32_t kMagic = 0x3143544F;                  // "OTC1" read little-endian
constexpr std::string_view kPartTag = ".part-";          // a tile being written
constexpr uint64_t kMaxTileBytes = 256ull << 20;         // a larger file is not a tile of ours

std::atomic<uint64_t> gWriteFailures{0};
std::atomic<uint64_t> gDropped{0};
std::atomic<uint64_t> gPartCounter{0};

/// A tile's file name in GDAL's cache: the MD5 of its key, 32 hex digits (no extension is set).
/// Only those are checked and removed when bad: other files met on the way are left alone.
bool isTileName(const std::string& real) {
    const size_t slash = real.rfind('/');
    const std::string_view name = std::string_view(real).substr(slash == std::string::npos ? 0 : slash + 1);
    return name.size() == 32 && std::all_of(name.begin(), name.end(), [](char c) { return std::isxdigit(uint8_t(c)) != 0; });
}

/// The real path of what GDAL names: GDAL hands the callbacks the name without the installed
/// prefix ("tmp/cache/..."); a name that still has it is taken whole.
std::string realPath(const char* path) {
    std::string_view p(path);
    if (p.substr(0, kPrefix.size()) == kPrefix) return std::string(p.substr(kPrefix.size()));
    std::string real(1, '/');
    real.append(p);
    return real;
}

void put32(uint8_t* out, uint32_t v) {
    for (int i = 0; i < 4; ++i) out[i] = uint8_t(v >> (8 * i));
}
uint32_t get32(const uint8_t* in) {
    return uint32_t(in[0]) | uint32_t(in[1]) << 8 | uint32_t(in[2]) << 16 | uint32_t(in[3]) << 24;
}

bool readAll(int fd, uint8_t* out, size_t n, off_t at) {
    while (n > 0) {
        const ssize_t r = ::pread(fd, out, n, at);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        out += r, n -= size_t(r), at += r;
    }
    return true;
}

/// A file in the cache that is not a whole tile of ours: removed, said (the first few times and
/// then at powers of two, not once per tile of a large old cache).
void drop(const std::string& real, const char* why) {
    ::unlink(real.c_str());
    const uint64_t n = ++gDropped;
    if (n <= 4 || (n & (n - 1)) == 0)
        log::warn("tile cache: ", real, " ", why, ": removed, the tile is fetched again (", n, " so far)");
}

void writeFailed(const std::string& real, int error) {
    const uint64_t n = ++gWriteFailures;
    if (n == 1 || (n & (n - 1)) == 0)
        log::warn("tile cache: cannot write ", real, " (", std::strerror(error),
                  "): tiles are fetched without the cache until it can (", n, " failed writes so far)");
}

/// The trailer of the regular file `fd` of `size` bytes: true when it is ours.
bool hasTrailer(int fd, uint64_t size, uint32_t* crc) {
    if (size < kTileCacheTrailerBytes || size > kMaxTileBytes) return false;
    uint8_t t[kTileCacheTrailerBytes];
    if (!readAll(fd, t, sizeof t, off_t(size - sizeof t))) return false;
    *crc = get32(t);
    return get32(t + 4) == kMagic;
}

struct Handle {
    bool writing = false;
    // reading: the tile, checked
    std::vector<uint8_t> data;
    uint64_t pos = 0;
    bool eof = false;
    // writing: a temporary file renamed over `real` on a clean close
    int fd = -1;
    std::string real, part;
    uLong crc = crc32(0, nullptr, 0);
    int error = 0;
};

// ---- file system callbacks ---------------------------------------------------------------------

int statCb(void*, const char* path, VSIStatBufL* out, int) {
    const std::string real = realPath(path);
    struct stat st {};
    if (::stat(real.c_str(), &st) != 0) return -1;
    std::memset(out, 0, sizeof *out);
    out->st_mode = st.st_mode;
    out->st_mtime = st.st_mtime;
    out->st_size = st.st_size;
    if (!S_ISREG(st.st_mode) || !isTileName(real)) return 0;
    const int fd = ::open(real.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return -1;
    uint32_t crc = 0;
    const bool ours = hasTrailer(fd, uint64_t(st.st_size), &crc);
    ::close(fd);
    if (!ours) {
        drop(real, "is cut short or not a tile of this cache");
        return -1;
    }
    out->st_size = st.st_size - off_t(kTileCacheTrailerBytes);
    return 0;
}

int unlinkCb(void*, const char* path) { return ::unlink(realPath(path).c_str()); }
int renameCb(void*, const char* from, const char* to) { return ::rename(realPath(from).c_str(), realPath(to).c_str()); }
int mkdirCb(void*, const char* path, long mode) { return ::mkdir(realPath(path).c_str(), mode_t(mode) | S_IRWXU); }
int rmdirCb(void*, const char* path) { return ::rmdir(realPath(path).c_str()); }

char** readDirCb(void*, const char* path, int maxFiles) {
    DIR* dir = ::opendir(realPath(path).c_str());
    if (!dir) return nullptr;
    CPLStringList names;
    while (const dirent* e = ::readdir(dir)) {
        const std::string_view name(e->d_name);
        if (name == "." || name == ".." || name.find(kPartTag) != std::string_view::npos) continue;
        names.AddString(e->d_name);
        if (maxFiles > 0 && names.size() >= maxFiles) break;
    }
    ::closedir(dir);
    return names.StealList();
}

void* openRead(const std::string& real) {
    const int fd = ::open(real.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return nullptr;
    struct stat st {};
    uint32_t crc = 0;
    auto h = std::make_unique<Handle>();
    bool whole = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && hasTrailer(fd, uint64_t(st.st_size), &crc);
    if (whole) {
        h->data.resize(size_t(st.st_size) - kTileCacheTrailerBytes);
        whole = readAll(fd, h->data.data(), h->data.size(), 0) &&
                crc32(crc32(0, nullptr, 0), h->data.data(), uInt(h->data.size())) == crc;
    }
    ::close(fd);
    if (!whole) {
        drop(real, "fails its checksum");
        return nullptr;
    }
    return h.release();
}

void* openWrite(const std::string& real) {
    auto h = std::make_unique<Handle>();
    h->writing = true;
    h->real = real;
    h->part = real + std::string(kPartTag) + std::to_string(::getpid()) + "-" + std::to_string(++gPartCounter);
    h->fd = ::open(h->part.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (h->fd < 0) {
        // A missing folder is GDAL's to make (it tries again after making it); anything else is said.
        if (errno != ENOENT) writeFailed(real, errno);
        return nullptr;
    }
    return h.release();
}

void* openCb(void*, const char* path, const char* access) {
    const std::string real = realPath(path);
    const std::string_view a(access ? access : "");
    if (!isTileName(real)) return nullptr;   // GDAL reads and writes nothing else here
    if (a == "r" || a == "rb") return openRead(real);
    if (a == "w" || a == "wb") return openWrite(real);
    return nullptr;   // no update or append: a tile is written once, whole
}

Handle& handle(void* f) { return *static_cast<Handle*>(f); }

vsi_l_offset tellCb(void* f) { return handle(f).pos; }

int seekCb(void* f, vsi_l_offset offset, int whence) {
    Handle& h = handle(f);
    if (h.writing) return offset == h.pos && whence != SEEK_END ? 0 : -1;
    const uint64_t base = whence == SEEK_SET ? 0 : whence == SEEK_CUR ? h.pos : h.data.size();
    h.pos = base + offset;
    h.eof = false;
    return 0;
}

size_t readCb(void* f, void* out, size_t size, size_t count) {
    Handle& h = handle(f);
    if (h.writing || size == 0) return 0;
    const uint64_t want = uint64_t(size) * count;
    const uint64_t have = h.pos < h.data.size() ? h.data.size() - h.pos : 0;
    const uint64_t n = std::min(want, have);
    if (n > 0) std::memcpy(out, h.data.data() + h.pos, size_t(n));
    h.pos += n;
    if (n < want) h.eof = true;
    return size_t(n / size);
}

int eofCb(void* f) { return handle(f).eof ? 1 : 0; }

size_t writeCb(void* f, const void* in, size_t size, size_t count) {
    Handle& h = handle(f);
    if (!h.writing || h.error != 0 || size == 0) return 0;
    const auto* p = static_cast<const uint8_t*>(in);
    size_t left = size * count;
    while (left > 0) {
        const ssize_t w = ::write(h.fd, p, left);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            h.error = w < 0 ? errno : ENOSPC;
            break;
        }
        h.crc = crc32(h.crc, p, uInt(w));
        p += w, left -= size_t(w), h.pos += uint64_t(w);
    }
    return (size * count - left) / size;
}

int flushCb(void*) { return 0; }
int truncateCb(void*, vsi_l_offset) { return -1; }

int closeCb(void* f) {
    std::unique_ptr<Handle> h(static_cast<Handle*>(f));
    if (!h->writing) return 0;
    if (h->error == 0) {
        uint8_t t[kTileCacheTrailerBytes];
        put32(t, uint32_t(h->crc));
        put32(t + 4, kMagic);
        if (writeCb(h.get(), t, 1, sizeof t) != sizeof t && h->error == 0) h->error = ENOSPC;
    }
    if (::close(h->fd) != 0 && h->error == 0) h->error = errno;
    if (h->error == 0 && ::rename(h->part.c_str(), h->real.c_str()) != 0) h->error = errno;
    if (h->error == 0) return 0;
    ::unlink(h->part.c_str());
    writeFailed(h->real, h->error);
    return -1;
}

void install() {
    VSIFilesystemPluginCallbacksStruct* cb = VSIAllocFilesystemPluginCallbacksStruct();
    cb->stat = statCb;
    cb->unlink = unlinkCb;
    cb->rename = renameCb;
    cb->mkdir = mkdirCb;
    cb->rmdir = rmdirCb;
    cb->read_dir = readDirCb;
    cb->open = openCb;
    cb->tell = tellCb;
    cb->seek = seekCb;
    cb->read = readCb;
    cb->eof = eofCb;
    cb->write = writeCb;
    cb->flush = flushCb;
    cb->truncate = truncateCb;
    cb->close = closeCb;
    // GDAL keeps the prefix's pointer, not a copy: it must live as long as the process.
    VSIInstallPluginHandler(kPrefixSlash, cb);
    VSIFreeFilesystemPluginCallbacksStruct(cb);
}

}  // namespace

std::string tileCachePath(const std::string& dir) {
    static std::once_flag once;
    std::call_once(once, install);
    std::error_code ec;
    std::filesystem::path abs = std::filesystem::absolute(dir, ec);
    if (ec) abs = dir;
    return std::string(kPrefix) + abs.lexically_normal().string();
}

uint64_t tileCacheWriteFailures() { return gWriteFailures.load(); }

}  // namespace orbis::globe
