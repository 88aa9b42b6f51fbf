#pragma once
// PNG files of RGBA8 pixels (stb_image / stb_image_write).

#include "base/Result.h"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace orbis {

struct ImageRgba8 {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> pixels;   ///< width * height * 4, top row first
};

Result<void> writePng(const std::filesystem::path& file, const ImageRgba8& image);
Result<ImageRgba8> readPng(const std::filesystem::path& file);

}  // namespace orbis
