#pragma once
// The PNG icons of a vector layer's points, read once each and shared by the threads that paint
// the drape's tiles. No Vulkan.
//
// Bounds: at most kMaxIcons icons, each at most kMaxIconSide pixels a side. An icon that cannot
// be read (missing, not a PNG, too large, past the count) is null: its points are drawn as
// markers, and the reason is logged once and kept in errors().

#include "base/Png.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace orbis::vector {

class IconCache {
public:
    static constexpr uint32_t kMaxIconSide = 1024;
    static constexpr size_t kMaxIcons = 256;

    /// `baseDir`: where relative paths are found (the source's folder: KML's own icons).
    explicit IconCache(std::string baseDir = {}) : baseDir_(std::move(baseDir)) {}

    /// The icon at `path` (absolute, or relative to the base folder); null when it cannot be
    /// read. Any thread.
    std::shared_ptr<const ImageRgba8> get(const std::string& path);
    /// The icon and its index: its place among the paths asked for so far, in the order they
    /// were first asked for (the 3-D markers name their icon by it); none when it cannot be
    /// read. Any thread.
    std::optional<std::pair<uint32_t, std::shared_ptr<const ImageRgba8>>> indexed(const std::string& path);
    /// Every path asked for so far, by index: its icon, or null where it could not be read.
    std::vector<std::shared_ptr<const ImageRgba8>> byIndex() const;
    /// One line per icon that could not be read: its path and why.
    std::vector<std::string> errors() const;

private:
    std::string baseDir_;
    mutable std::mutex mutex_;
    std::map<std::string, std::shared_ptr<const ImageRgba8>> icons_;
    std::vector<std::string> order_;   ///< icons_' paths in the order first asked for
    std::vector<std::string> errors_;
};

}  // namespace orbis::vector
