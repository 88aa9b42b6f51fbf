#include "engine/gpu/VkCheck.h"

#include <filesystem>

namespace orbis::gpu {

const char* resultName(VkResult r) {
    switch (r) {
#define ORBIS_CASE(x) case x: return #x;
        ORBIS_CASE(VK_SUCCESS)
        ORBIS_CASE(VK_NOT_READY)
        ORBIS_CASE(VK_TIMEOUT)
        ORBIS_CASE(VK_INCOMPLETE)
        ORBIS_CASE(VK_SUBOPTIMAL_KHR)
        ORBIS_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        ORBIS_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        ORBIS_CASE(VK_ERROR_INITIALIZATION_FAILED)
        ORBIS_CASE(VK_ERROR_DEVICE_LOST)
        ORBIS_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        ORBIS_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        ORBIS_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        ORBIS_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        ORBIS_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        ORBIS_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        ORBIS_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        ORBIS_CASE(VK_ERROR_FRAGMENTED_POOL)
        ORBIS_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        ORBIS_CASE(VK_ERROR_SURFACE_LOST_KHR)
        ORBIS_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
        ORBIS_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        ORBIS_CASE(VK_ERROR_VALIDATION_FAILED_EXT)
#undef ORBIS_CASE
        default: return "VkResult(unknown)";
    }
}

void throwVkError(VkResult result, const char* expression, const char* file, int line) {
    throw GpuError(result, std::string(expression) + " failed at " +
                               std::filesystem::path(file).filename().string() + ":" + std::to_string(line));
}

}  // namespace orbis::gpu
