#pragma once
// The Vulkan instance, with the Khronos validation layer and a debug messenger when asked.
// Validation messages are logged and counted: tests fail when the count is not zero.

#include <vulkan/vulkan.h>

#include <atomic>
#include <string>
#include <vector>

namespace orbis::gpu {

struct InstanceOptions {
    bool validation = false;                  ///< load VK_LAYER_KHRONOS_validation (+ sync validation)
    std::vector<std::string> extensions;      ///< e.g. the ones glfwGetRequiredInstanceExtensions lists
    std::string applicationName = "orbis";
};

class Instance {
public:
    explicit Instance(const InstanceOptions& options);
    ~Instance();
    Instance(const Instance&) = delete;
    Instance& operator=(const Instance&) = delete;

    VkInstance vk() const { return instance_; }
    bool validationEnabled() const { return validation_; }
    bool debugUtilsEnabled() const { return debugUtils_; }

    /// Validation warnings and errors seen so far (any thread).
    int validationMessages() const { return validationMessages_.load(); }
    /// The text of the first validation message, for test failure output.
    std::string firstValidationMessage() const;

    static bool validationLayerAvailable();

private:
    static VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                        VkDebugUtilsMessageTypeFlagsEXT types,
                                                        const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                        void* user);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    bool validation_ = false;
    bool debugUtils_ = false;
    std::atomic<int> validationMessages_{0};
    mutable std::atomic<bool> firstSet_{false};
    std::string firstMessage_;
};

}  // namespace orbis::gpu
