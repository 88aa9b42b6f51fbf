#pragma once
// Inside LasFile (LasReader.cpp, LasRemote.cpp): what the local and the remote reading share.

#include "base/Result.h"
#include "layers/points/LasReader.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <string>

namespace orbis::points::las_detail {

inline Error fail(const std::string& path, const std::string& what) { return makeError(std::string(path).append(": ").append(what)); }
inline std::string num(uint64_t v) { return std::to_string(v); }

/// A CRS in WKT is a few KB; a larger "sidecar" is some other file that shares the name.
inline constexpr std::uintmax_t kMaxSidecarBytes = 1u << 20;

/// The header and VLRs' view of a file, mapped while it opens.
struct Mapping {
    const uint8_t* data = nullptr;
    uint64_t bytes = 0;
    ~Mapping() {
        if (data) munmap(const_cast<uint8_t*>(data), bytes);
    }
};

/// Reads exactly `n` bytes at `offset`; false when the file is shorter now.
inline bool preadAll(int fd, uint8_t* p, uint64_t n, uint64_t offset) {
    while (n > 0) {
        const ssize_t r = ::pread(fd, p, n, off_t(offset));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        p += r, n -= uint64_t(r), offset += uint64_t(r);
    }
    return true;
}

/// The sidecar of a file on a server (LasRemote.cpp).
LasCrs remoteSidecarCrs(const std::string& url);

}  // namespace orbis::points::las_detail
