#include "engine/gpu/Instance.h"

#include "base/Log.h"
#include "engine/gpu/VkCheck.h"

#include <cstring>

namespace orbis::gpu {
namespace {
constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool hasInstanceExtension(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> props(count);
    vkEnumerateInstanceExtensionProperties(nullptr, &count, props.data());
    for (const auto& p : props)
        if (std::strcmp(p.extensionName, name) == 0) return true;
    return false;
}
}  // namespace

bool Instance::validationLayerAvailable() {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, kValidationLayer) == 0) return true;
    return false;
}

Instance::Instance(const InstanceOptions& options) : validation_(options.validation) {
    uint32_t loaderVersion = VK_API_VERSION_1_0;
    vkEnumerateInstanceVersion(&loaderVersion);
    if (loaderVersion < VK_API_VERSION_1_3)
        throw GpuError(VK_ERROR_INCOMPATIBLE_DRIVER, "the Vulkan loader is older than 1.3");

    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    for (const auto& e : options.extensions) extensions.push_back(e.c_str());
    if (validation_) {
        if (!validationLayerAvailable())
            throw GpuError(VK_ERROR_LAYER_NOT_PRESENT,
                           "validation requested but VK_LAYER_KHRONOS_validation is not installed "
                           "(Debian package vulkan-validationlayers)");
        layers.push_back(kValidationLayer);
    }
    const bool debugUtils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    debugUtils_ = debugUtils;
    if (debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = options.applicationName.c_str();
    app.pEngineName = "orbis";
    app.apiVersion = VK_API_VERSION_1_3;

    // Synchronization validation catches missing barriers, which plain validation cannot.
    VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;

    VkDebugUtilsMessengerCreateInfoEXT messengerInfo{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messengerInfo.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
    messengerInfo.pfnUserCallback = &Instance::debugCallback;
    messengerInfo.pUserData = this;
    if (validation_) features.pNext = debugUtils ? &messengerInfo : nullptr;

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = static_cast<uint32_t>(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    info.pNext = validation_ ? &features : nullptr;
    VK_CHECK(vkCreateInstance(&info, nullptr, &instance_));

    if (validation_ && debugUtils) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (create) VK_CHECK(create(instance_, &messengerInfo, nullptr, &messenger_));
    }
}

Instance::~Instance() {
    if (messenger_ != VK_NULL_HANDLE) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

std::string Instance::firstValidationMessage() const {
    return firstSet_.load() ? firstMessage_ : std::string();
}

VkBool32 Instance::debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                 VkDebugUtilsMessageTypeFlagsEXT types,
                                 const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* self = static_cast<Instance*>(user);
    const char* text = data && data->pMessage ? data->pMessage : "(no message)";
    // General messages come from the loader (e.g. an ICD that fails to load): logged, not counted.
    if (!(types & (VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT))) {
        log::debug("vulkan: ", text);
        return VK_FALSE;
    }
    if (self->validationMessages_.fetch_add(1) == 0) {
        self->firstMessage_ = text;
        self->firstSet_.store(true);
    }
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)
        log::error("validation: ", text);
    else
        log::warn("validation: ", text);
    return VK_FALSE;
}

}  // namespace orbis::gpu
