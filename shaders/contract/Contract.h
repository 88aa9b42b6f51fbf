#pragma once
// The checks of the shader/C++ contract: each pipeline's SPIR-V modules against the tables of
// the shared headers (shaders/shared/*Types.h) that the C++ side builds that pipeline from; and
// a lint for numbers written into GLSL layout qualifiers instead of those headers' names.

#include "shared/Common.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace orbis::contract {

/// One compiled shader of a pipeline: the file it came from (for messages) and its words.
struct ShaderModule {
    const char* file;
    std::span<const uint32_t> spirv;
};

/// A set's layout as the C++ side creates it: a shared header's table.
struct SetTable {
    uint32_t set;
    const char* table;   ///< its name, for messages ("shader::kPointBindings")
    std::span<const shader::DescriptorBinding> bindings;
};

/// What a pipeline's C++ side says its shaders declare.
struct PipelineContract {
    const char* name;
    std::vector<ShaderModule> shaders;
    std::vector<SetTable> sets;
    const char* specTable = nullptr;   ///< the constants' table name, for messages
    std::span<const shader::SpecConstant> specConstants;
    std::array<uint32_t, 3> localSize{0, 0, 0};   ///< compute pipelines: the group size constants
    std::vector<uint32_t> vertexInputs;            ///< the named locations of the C++ vertex attributes
};

/// Every disagreement between the pipeline's shaders and its tables, one message each, naming
/// the pipeline, the shader, the set/binding (or constant, or location) and both sides.
std::vector<std::string> checkPipeline(const PipelineContract& pipeline);

/// A numeric literal in a GLSL layout qualifier that C++ must match by hand.
struct LayoutLiteral {
    std::string file;   ///< relative to the shader folder
    int line = 0;
    std::string text;   ///< "binding = 6"
};

/// The literals in `set`, `binding`, `constant_id`, `local_size_*` and vertex-input `location`
/// qualifiers of every .vert/.frag/.comp/.glsl file under `folder` (fragment outputs and
/// varyings between stages are not the C++ side's business).
std::vector<LayoutLiteral> findLayoutLiterals(const std::filesystem::path& folder);

}  // namespace orbis::contract
