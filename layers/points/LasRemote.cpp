// LasFile over HTTP: a file on a web server read with range requests through GDAL's /vsicurl/
// (its block cache, Orbis's HTTP timeouts): the head, the VLRs and the tables at the file's end
// when it opens, then only the points or nodes asked for; those ranges kept in a disk cache when
// the reader asks for one (cacheRemoteReads).
#include "layers/points/LasBytes.h"
#include "layers/points/LasReader.h"
#include "layers/points/LasReaderDetail.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

namespace orbis::points {

using namespace las_detail;
using bytes::get;

/// The sidecar of a file on a server: `URL.wkt` or `URL.prj` next to it, when the server has one.
LasCrs las_detail::remoteSidecarCrs(const std::string& url) {
    for (const char* ext : {".wkt", ".prj"}) {
        const std::string vsi = std::string("/vsicurl/").append(url).append(ext);
        CPLPushErrorHandler(CPLQuietErrorHandler);
        VSILFILE* f = VSIFOpenL(vsi.c_str(), "rb");
        std::string text(kMaxSidecarBytes, '\0');
        const size_t n = f ? VSIFReadL(text.data(), 1, text.size(), f) : 0;
        if (f) VSIFCloseL(f);
        CPLPopErrorHandler();
        text.resize(n);
        while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
        if (!text.empty() && n < kMaxSidecarBytes) return {text, std::string("sidecar ").append(url).append(ext)};
    }
    return {};
}

/// A file on a server, through GDAL's /vsicurl/ (range requests, its block cache). GDAL's file
/// handles are not thread-safe: reads take turns.
struct LasFile::Remote {
    std::mutex mutex;
    VSILFILE* file = nullptr;
    std::atomic<uint64_t> fetched{0}, fromCache{0};
    int64_t modified = 0;     // the server's date of the file (Last-Modified), 0 when it gives none
    std::string cacheFolder;  // set once by cacheRemoteReads, before the reads that use it
    ~Remote() {
        if (file) VSIFCloseL(file);
    }

    static constexpr char kTrailer[4] = {'O', 'R', 'C', '1'};
    static std::string rangePath(const std::string& folder, uint64_t offset, uint64_t n) {
        return folder + "/" + std::to_string(offset) + "-" + std::to_string(n);
    }
    /// The cached range, when its file is whole and its CRC right (else removed).
    bool readCached(const std::string& folder, uint8_t* out, uint64_t n, uint64_t offset) {
        const std::string path = rangePath(folder, offset, n);
        std::ifstream in(path, std::ios::binary);
        if (!in) return false;
        in.read(reinterpret_cast<char*>(out), std::streamsize(n));
        uint8_t trailer[8];
        in.read(reinterpret_cast<char*>(trailer), 8);
        const bool whole = in.gcount() == 8 && in.peek() == std::char_traits<char>::eof();
        in.close();
        uint32_t crc = 0;
        std::memcpy(&crc, trailer, 4);
        if (whole && std::memcmp(trailer + 4, kTrailer, 4) == 0 && uint32_t(crc32(crc32(0, nullptr, 0), out, uInt(n))) == crc) {
            fromCache += n;
            return true;
        }
        std::error_code ec;
        std::filesystem::remove(path, ec);
        return false;
    }
    /// Keeps a range fetched: under a temporary name, renamed when every byte is out.
    static void store(const std::string& folder, const uint8_t* data, uint64_t n, uint64_t offset) {
        const std::string path = rangePath(folder, offset, n);
        const std::string tmp = path + ".tmp" + std::to_string(::getpid()) + "-" +
                                std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()));
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) return;
        uint8_t trailer[8];
        const uint32_t crc = uint32_t(crc32(crc32(0, nullptr, 0), data, uInt(n)));
        std::memcpy(trailer, &crc, 4);
        std::memcpy(trailer + 4, kTrailer, 4);
        const bool written = std::fwrite(data, 1, size_t(n), f) == n && std::fwrite(trailer, 1, 8, f) == 8;
        if (std::fclose(f) == 0 && written && std::rename(tmp.c_str(), path.c_str()) == 0) return;
        std::remove(tmp.c_str());
    }
};

namespace {

/// FNV-1a, 64 bits: a cache folder's name.
uint64_t fnv1a(const std::string& s) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
}

/// Removes the least recently written ranges under `root` until it holds 3/4 of `maxBytes`,
/// when it holds more than `maxBytes`.
void pruneRangeCache(const std::filesystem::path& root, uint64_t maxBytes) {
    namespace fs = std::filesystem;
    struct Entry {
        fs::file_time_type written;
        uint64_t bytes;
        fs::path path;
    };
    std::vector<Entry> entries;
    uint64_t total = 0;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        const uint64_t bytes = it->file_size(ec);
        const auto written = it->last_write_time(ec);
        if (ec) continue;
        entries.push_back({written, bytes, it->path()});
        total += bytes;
    }
    if (total <= maxBytes) return;
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.written < b.written; });
    for (const Entry& e : entries) {
        if (total <= maxBytes / 4 * 3) break;
        if (fs::remove(e.path, ec)) total -= e.bytes;
    }
}

}  // namespace

void LasFile::cacheRemoteReads(const std::string& folder, uint64_t maxBytes) const {
    if (!remote_ || folder.empty()) return;
    namespace fs = std::filesystem;
    pruneRangeCache(folder, maxBytes);
    char name[17];
    std::snprintf(name, sizeof name, "%016llx",
                  static_cast<unsigned long long>(fnv1a(path_ + "\n" + std::to_string(bytes_) + "\n" + std::to_string(remote_->modified))));
    const fs::path dir = fs::path(folder) / name;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return;   // reads go to the server, as without a cache
    std::lock_guard lock(remote_->mutex);
    remote_->cacheFolder = dir.string();
}

uint64_t LasFile::bytesFromCache() const { return remote_ ? remote_->fromCache.load() : 0; }

bool LasFile::readAt(uint8_t* out, uint64_t n, uint64_t offset, std::string& why) const {
    if (!remote_) {
        if (preadAll(fd_, out, n, offset)) return true;
        why = "the file is shorter than when it was opened (changed while loading?)";
        return false;
    }
    std::string cacheFolder;
    {
        std::lock_guard lock(remote_->mutex);
        cacheFolder = remote_->cacheFolder;
    }
    if (!cacheFolder.empty() && remote_->readCached(cacheFolder, out, n, offset)) return true;
    std::unique_lock lock(remote_->mutex);
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool ok = VSIFSeekL(remote_->file, offset, SEEK_SET) == 0 && VSIFReadL(out, 1, size_t(n), remote_->file) == n;
    CPLPopErrorHandler();
    if (ok) {
        remote_->fetched += n;
        lock.unlock();
        if (!cacheFolder.empty()) Remote::store(cacheFolder, out, n, offset);
        return true;
    }
    const std::string gdal = CPLGetLastErrorMsg();
    if (gdal.find("Range downloading not supported") != std::string::npos) {
        why = "the server does not honour range requests (HTTP Range): Orbis streams clouds from servers that do";
        return false;
    }
    why = std::string("the server did not send bytes ").append(num(offset)).append(" to ").append(num(offset + n))
              .append(gdal.empty() ? std::string() : std::string(": ").append(gdal));
    return false;
}

uint64_t LasFile::bytesFetched() const { return remote_ ? remote_->fetched.load() : 0; }

/// The bytes at a remote file's end that opening may need (the LAZ chunk table, the EVLRs: a
/// COPC file's hierarchy) are fetched whole; more than this is refused rather than downloaded.
constexpr uint64_t kMaxRemoteTailBytes = uint64_t(256) << 20;

Result<std::unique_ptr<LasFile>> LasFile::openRemote(const std::string& url) {
    std::unique_ptr<LasFile> f(new LasFile());
    f->path_ = url;
    f->remote_ = std::make_shared<Remote>();
    // The same bounds the rest of Orbis gives GDAL's HTTP (globe/GdalSetup), where not set.
    for (const auto& [key, value] : {std::pair{"GDAL_HTTP_TIMEOUT", "30"}, {"GDAL_HTTP_CONNECTTIMEOUT", "10"},
                                     {"GDAL_HTTP_LOW_SPEED_TIME", "30"}, {"GDAL_HTTP_LOW_SPEED_LIMIT", "1"}})
        if (!CPLGetConfigOption(key, nullptr)) CPLSetConfigOption(key, value);
    const std::string vsi = std::string("/vsicurl/").append(url);
    // What GDAL keeps of the URL from an earlier open in this process (its size, its blocks) is
    // forgotten: a file replaced on the server is read as it is now (and gets its own node cache).
    VSICurlPartialClearCache(vsi.c_str());
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    VSIStatBufL st{};
    const bool found = VSIStatExL(vsi.c_str(), &st, VSI_STAT_EXISTS_FLAG | VSI_STAT_SIZE_FLAG) == 0;
    if (found) f->remote_->file = VSIFOpenExL(vsi.c_str(), "rb", TRUE);
    CPLPopErrorHandler();
    if (!found || !f->remote_->file)
        return fail(url, std::string("cannot open: the server has no such file or cannot be reached")
                             .append(*CPLGetLastErrorMsg() ? std::string(" (").append(CPLGetLastErrorMsg()).append(")") : std::string()));
    f->bytes_ = uint64_t(st.st_size);
    f->remote_->modified = int64_t(st.st_mtime);
    if (f->bytes_ < 227) return fail(url, std::string("not a LAS file (").append(num(f->bytes_)).append(" bytes, shorter than a LAS header)"));
    // A view of the whole file in which only the head and the tail are fetched: the parsing reads
    // nothing else (untouched pages of the anonymous mapping cost nothing).
    void* map = mmap(nullptr, f->bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (map == MAP_FAILED) return fail(url, std::string("cannot reserve a view of ").append(num(f->bytes_)).append(" bytes: ").append(std::strerror(errno)));
    const Mapping mapping{static_cast<const uint8_t*>(map), f->bytes_};
    uint8_t* d = static_cast<uint8_t*>(map);
    const auto fetch = [&](uint64_t from, uint64_t to) -> Result<void> {
        to = std::min(to, f->bytes_);
        if (from >= to) return {};
        if (std::string why; !f->readAt(d + from, to - from, from, why)) return fail(url, why);
        return {};
    };
    if (auto r = fetch(0, 375); !r) return r.error();
    const uint64_t pointOffset = bytes::get<uint32_t>(d + 96);
    if (auto r = fetch(375, pointOffset + 8); !r) return r.error();
    uint64_t tail = f->bytes_;
    if (d[25] >= 4 && bytes::get<uint32_t>(d + 243) > 0) tail = std::min<uint64_t>(tail, bytes::get<uint64_t>(d + 235));   // EVLRs
    if (d[104] & 0xC0) {   // LAZ: the chunk table (or, when written last, the offset of it)
        const int64_t table = pointOffset + 8 <= f->bytes_ ? bytes::get<int64_t>(d + pointOffset) : 0;
        if (table == -1) tail = std::min(tail, f->bytes_ - 8);
        else if (table > int64_t(pointOffset) && uint64_t(table) < tail) tail = uint64_t(table);
    }
    if (f->bytes_ - tail > kMaxRemoteTailBytes)
        return fail(url, std::string("the tables at the file's end are ").append(num((f->bytes_ - tail) >> 20)).append(" MB, more than Orbis fetches to open a file"));
    if (auto r = fetch(tail, f->bytes_); !r) return r.error();
    if (d[104] & 0xC0 && pointOffset + 8 <= f->bytes_ && bytes::get<int64_t>(d + pointOffset) == -1) {
        const int64_t table = bytes::get<int64_t>(d + f->bytes_ - 8);
        if (table > int64_t(pointOffset) && uint64_t(table) < tail && tail - uint64_t(table) <= kMaxRemoteTailBytes)
            if (auto r = fetch(uint64_t(table), tail); !r) return r.error();
    }
    if (auto parsed = parse(*f, d); !parsed) return parsed.error();
    return f;
}

}  // namespace orbis::points
