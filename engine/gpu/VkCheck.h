#pragma once
// Setup failures (no device, missing layer, out of memory) throw one exception type that
// carries the VkResult and the failing expression. Data paths never throw: they use Result<T>.

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace orbis::gpu {

const char* resultName(VkResult result);

class GpuError : public std::runtime_error {
public:
    GpuError(VkResult result, const std::string& what)
        : std::runtime_error(what + " (" + resultName(result) + ")"), result_(result) {}
    VkResult result() const { return result_; }

private:
    VkResult result_;
};

[[noreturn]] void throwVkError(VkResult result, const char* expression, const char* file, int line);

}  // namespace orbis::gpu

#define VK_CHECK(expr)                                                                   \
    do {                                                                                 \
        VkResult orbisVkResult_ = (expr);                                                \
        if (orbisVkResult_ < 0)                                                          \
            ::orbis::gpu::throwVkError(orbisVkResult_, #expr, __FILE__, __LINE__);       \
    } while (false)
