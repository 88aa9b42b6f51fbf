#include "base/Png.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cerrno>
#include <cstring>

namespace orbis {

Result<void> writePng(const std::filesystem::path& file, const ImageRgba8& image) {
    if (image.pixels.size() != size_t(image.width) * image.height * 4 || image.width == 0)
        return Error{file.string() + ": image has no pixels or a wrong size"};
    if (!stbi_write_png(file.c_str(), int(image.width), int(image.height), 4, image.pixels.data(),
                        int(image.width * 4)))
        return Error{file.string() + ": cannot write PNG (" + std::strerror(errno) + ")"};
    return {};
}

Result<ImageRgba8> readPng(const std::filesystem::path& file) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load(file.c_str(), &w, &h, &channels, 4);
    if (!data) return Error{file.string() + ": cannot read image (" + stbi_failure_reason() + ")"};
    ImageRgba8 image;
    image.width = uint32_t(w);
    image.height = uint32_t(h);
    image.pixels.assign(data, data + size_t(w) * h * 4);
    stbi_image_free(data);
    return image;
}

}  // namespace orbis
