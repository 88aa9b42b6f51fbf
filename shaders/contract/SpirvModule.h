#pragma once
// What a SPIR-V module declares that its C++ side must match: its descriptors (set, binding,
// kind, array size), its specialisation constants (ID, type), its compute workgroup size and
// its vertex inputs. A reader of the few instructions that say so (SPIR-V 1.5 spec, section 3
// for the enums' values), not a general reflection library. No Vulkan.

#include "shared/Common.h"

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace orbis::contract {

enum class ShaderStage { Vertex, Fragment, Compute, Other };

/// The descriptor kinds a shader can declare (more than shader::DescriptorKind: a shader may
/// declare what no table in this project uses).
enum class Resource { UniformBuffer, StorageBuffer, CombinedImageSampler, StorageImage, SampledImage, Sampler, Other };

struct SpirvDescriptor {
    uint32_t set = 0, binding = 0;
    Resource kind = Resource::Other;
    uint32_t count = 1;   ///< array size; 0 for a runtime-sized array
    std::string name;     ///< the variable's (or its block's) name, when the module has it
};

struct SpirvSpecConstant {
    uint32_t id = 0;
    std::optional<shader::SpecType> type;   ///< none: a type no table uses (64-bit, ...)
    std::string name;
};

struct SpirvInput {
    uint32_t location = 0;
    std::string name;
};

struct SpirvModule {
    ShaderStage stage = ShaderStage::Other;
    std::vector<SpirvDescriptor> descriptors;
    std::vector<SpirvSpecConstant> specConstants;
    std::vector<SpirvInput> inputs;   ///< Input variables with a Location (built-ins left out)
    std::array<uint32_t, 3> localSize{0, 0, 0};   ///< compute: OpExecutionMode LocalSize
    bool localSizeFromIds = false;                ///< LocalSizeId: sizes from constants the table cannot name
};

/// The module's declarations, or an error message when the words are not SPIR-V this reader
/// understands (one entry point).
std::optional<SpirvModule> readSpirv(std::span<const uint32_t> words, std::string* error);

const char* toString(ShaderStage stage);
const char* toString(Resource kind);
const char* toString(shader::DescriptorKind kind);
const char* toString(shader::SpecType type);
/// The shader-side kind a table's descriptor kind is declared as (a dynamic storage buffer is a
/// storage buffer to the shader).
Resource toResource(shader::DescriptorKind kind);
/// The table's stage bit for a shader stage (0 for Other).
uint32_t stageBit(ShaderStage stage);

}  // namespace orbis::contract
