#include "layers/vector/IconCache.h"

#include "base/Log.h"

#include <algorithm>
#include <filesystem>

namespace orbis::vector {

std::shared_ptr<const ImageRgba8> IconCache::get(const std::string& path) {
    std::lock_guard lock(mutex_);
    if (auto it = icons_.find(path); it != icons_.end()) return it->second;
    std::shared_ptr<const ImageRgba8> icon;
    std::string why;   // "FILE: reason"
    std::filesystem::path file(path);
    if (file.is_relative() && !baseDir_.empty()) file = std::filesystem::path(baseDir_) / file;
    if (icons_.size() >= kMaxIcons) {
        why = file.string() + ": more than " + std::to_string(kMaxIcons) + " icons in one layer";
    } else if (path.rfind("http://", 0) == 0 || path.rfind("https://", 0) == 0) {
        why = path + ": icons are read from files, not URLs";
    } else if (auto png = readPng(file); !png) {
        why = png.message();   // names the file
    } else if (png->width > kMaxIconSide || png->height > kMaxIconSide) {
        why = file.string() + ": " + std::to_string(png->width) + "x" + std::to_string(png->height) + " pixels: more than " +
              std::to_string(kMaxIconSide) + " a side";
    } else {
        icon = std::make_shared<const ImageRgba8>(std::move(*png));
    }
    if (!icon) {
        errors_.push_back(why);
        log::warn("vector icon ", why, " (its points are drawn as markers)");
    }
    icons_.emplace(path, icon);
    order_.push_back(path);
    return icon;
}

std::optional<std::pair<uint32_t, std::shared_ptr<const ImageRgba8>>> IconCache::indexed(const std::string& path) {
    auto icon = get(path);
    if (!icon) return std::nullopt;
    std::lock_guard lock(mutex_);
    const auto it = std::find(order_.begin(), order_.end(), path);
    return std::make_pair(uint32_t(it - order_.begin()), std::move(icon));
}

std::vector<std::shared_ptr<const ImageRgba8>> IconCache::byIndex() const {
    std::lock_guard lock(mutex_);
    std::vector<std::shared_ptr<const ImageRgba8>> out;
    out.reserve(order_.size());
    for (const std::string& path : order_) out.push_back(icons_.at(path));
    return out;
}

std::vector<std::string> IconCache::errors() const {
    std::lock_guard lock(mutex_);
    return errors_;
}

}  // namespace orbis::vector
