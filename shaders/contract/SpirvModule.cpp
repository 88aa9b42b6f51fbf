#include "shaders/contract/SpirvModule.h"

#include <map>
#include <unordered_map>

namespace orbis::contract {
namespace {

// The SPIR-V 1.5 specification's values: opcodes (3.32), execution models (3.3), execution
// modes (3.6), storage classes (3.7), decorations (3.20).
enum Op : uint32_t {
    kOpName = 5,
    kOpEntryPoint = 15,
    kOpExecutionMode = 16,
    kOpTypeBool = 20,
    kOpTypeInt = 21,
    kOpTypeFloat = 22,
    kOpTypeImage = 25,
    kOpTypeSampler = 26,
    kOpTypeSampledImage = 27,
    kOpTypeArray = 28,
    kOpTypeRuntimeArray = 29,
    kOpTypePointer = 32,
    kOpConstant = 43,
    kOpSpecConstantTrue = 48,
    kOpSpecConstantFalse = 49,
    kOpSpecConstant = 50,
    kOpVariable = 59,
    kOpDecorate = 71,
    kOpExecutionModeId = 331,
};
enum Decoration : uint32_t { kSpecId = 1, kBufferBlock = 3, kBuiltIn = 11, kLocation = 30, kBinding = 33, kDescriptorSet = 34 };
enum StorageClass : uint32_t { kUniformConstant = 0, kInput = 1, kUniform = 2, kStorageBuffer = 12 };
enum ExecutionModel : uint32_t { kModelVertex = 0, kModelFragment = 4, kModelCompute = 5 };
constexpr uint32_t kMagic = 0x07230203;
constexpr uint32_t kModeLocalSize = 17, kModeLocalSizeId = 38;
constexpr uint32_t kImageSampled = 1, kImageStorage = 2;   // OpTypeImage's "Sampled" operand

/// Every id the checks need, gathered in one pass over the instructions.
struct Ids {
    struct Type {
        uint32_t op = 0;
        std::vector<uint32_t> operands;   // after the result id
    };
    struct Variable {
        uint32_t id, pointerType, storage;
    };
    struct Spec {
        uint32_t id, op, type;
    };
    std::unordered_map<uint32_t, Type> types;
    std::unordered_map<uint32_t, uint32_t> constants;   // the first word of each OpConstant
    std::unordered_map<uint32_t, std::string> names;
    std::unordered_map<uint32_t, std::map<uint32_t, uint32_t>> decorations;   // id -> decoration -> first literal
    std::vector<Variable> variables;
    std::vector<Spec> specs;
    uint32_t model = ~0u;
    int entryPoints = 0;
    std::array<uint32_t, 3> localSize{0, 0, 0};
    bool localSizeFromIds = false;

    const Type* type(uint32_t id) const {
        auto it = types.find(id);
        return it == types.end() ? nullptr : &it->second;
    }
    std::optional<uint32_t> decoration(uint32_t id, uint32_t what) const {
        auto it = decorations.find(id);
        if (it == decorations.end()) return std::nullopt;
        auto d = it->second.find(what);
        return d == it->second.end() ? std::nullopt : std::optional<uint32_t>(d->second);
    }
    std::string name(uint32_t id) const {
        auto it = names.find(id);
        return it == names.end() ? std::string() : it->second;
    }
};

std::string literalString(std::span<const uint32_t> words) {
    std::string s;
    for (uint32_t w : words)
        for (int b = 0; b < 4; ++b) {
            const char c = char((w >> (8 * b)) & 0xffu);
            if (c == '\0') return s;
            s += c;
        }
    return s;
}

void readInstruction(uint32_t op, std::span<const uint32_t> a, Ids& ids) {
    switch (op) {
        case kOpName: ids.names[a[0]] = literalString(a.subspan(1)); break;
        case kOpEntryPoint: ids.model = a[0], ++ids.entryPoints; break;
        case kOpExecutionMode:
            if (a[1] == kModeLocalSize && a.size() >= 5) ids.localSize = {a[2], a[3], a[4]};
            break;
        case kOpExecutionModeId:
            if (a[1] == kModeLocalSizeId) ids.localSizeFromIds = true;
            break;
        case kOpTypeBool: case kOpTypeInt: case kOpTypeFloat: case kOpTypeImage: case kOpTypeSampler:
        case kOpTypeSampledImage: case kOpTypeArray: case kOpTypeRuntimeArray: case kOpTypePointer:
            ids.types[a[0]] = {op, std::vector<uint32_t>(a.begin() + 1, a.end())};
            break;
        case kOpConstant: ids.constants[a[1]] = a[2]; break;
        case kOpSpecConstantTrue: case kOpSpecConstantFalse: case kOpSpecConstant: ids.specs.push_back({a[1], op, a[0]}); break;
        case kOpVariable: ids.variables.push_back({a[1], a[0], a[2]}); break;
        case kOpDecorate: ids.decorations[a[0]][a[1]] = a.size() > 2 ? a[2] : 0u; break;
        default: break;
    }
}

/// The descriptor kind and array size of a variable of `storage` class pointing at `type`.
Resource descriptorKind(const Ids& ids, uint32_t type, uint32_t storage, uint32_t& count) {
    count = 1;
    for (const Ids::Type* t = ids.type(type); t && (t->op == kOpTypeArray || t->op == kOpTypeRuntimeArray); t = ids.type(type)) {
        if (t->op == kOpTypeArray) {
            auto n = ids.constants.find(t->operands[1]);
            count *= n == ids.constants.end() ? 0u : n->second;
        } else {
            count = 0;
        }
        type = t->operands[0];
    }
    if (storage == kStorageBuffer) return Resource::StorageBuffer;
    if (storage == kUniform) return ids.decoration(type, kBufferBlock) ? Resource::StorageBuffer : Resource::UniformBuffer;
    if (storage != kUniformConstant) return Resource::Other;
    const Ids::Type* t = ids.type(type);
    if (!t) return Resource::Other;
    if (t->op == kOpTypeSampledImage) return Resource::CombinedImageSampler;
    if (t->op == kOpTypeSampler) return Resource::Sampler;
    if (t->op == kOpTypeImage && t->operands.size() >= 6)
        return t->operands[5] == kImageStorage ? Resource::StorageImage
               : t->operands[5] == kImageSampled ? Resource::SampledImage
                                                 : Resource::Other;
    return Resource::Other;
}

std::optional<shader::SpecType> specType(const Ids& ids, const Ids::Spec& s) {
    if (s.op != kOpSpecConstant) return shader::SpecType::Bool;
    const Ids::Type* t = ids.type(s.type);
    if (!t || t->operands.empty() || t->operands[0] != 32) return std::nullopt;
    if (t->op == kOpTypeFloat) return shader::SpecType::Float;
    if (t->op == kOpTypeInt) return t->operands[1] ? shader::SpecType::Int : shader::SpecType::Uint;
    return std::nullopt;
}

SpirvModule collect(const Ids& ids) {
    SpirvModule m;
    m.stage = ids.model == kModelVertex     ? ShaderStage::Vertex
              : ids.model == kModelFragment ? ShaderStage::Fragment
              : ids.model == kModelCompute  ? ShaderStage::Compute
                                            : ShaderStage::Other;
    m.localSize = ids.localSize;
    m.localSizeFromIds = ids.localSizeFromIds;
    for (const Ids::Variable& v : ids.variables) {
        const Ids::Type* pointer = ids.type(v.pointerType);
        const uint32_t pointee = pointer && pointer->operands.size() >= 2 ? pointer->operands[1] : 0u;
        if (const auto set = ids.decoration(v.id, kDescriptorSet)) {
            SpirvDescriptor d;
            d.set = *set;
            d.binding = ids.decoration(v.id, kBinding).value_or(0);
            d.kind = descriptorKind(ids, pointee, v.storage, d.count);
            d.name = ids.name(v.id).empty() ? ids.name(pointee) : ids.name(v.id);
            m.descriptors.push_back(d);
        } else if (v.storage == kInput && !ids.decoration(v.id, kBuiltIn)) {
            if (const auto location = ids.decoration(v.id, kLocation)) m.inputs.push_back({*location, ids.name(v.id)});
        }
    }
    for (const Ids::Spec& s : ids.specs)
        if (const auto id = ids.decoration(s.id, kSpecId)) m.specConstants.push_back({*id, specType(ids, s), ids.name(s.id)});
    return m;
}

}  // namespace

std::optional<SpirvModule> readSpirv(std::span<const uint32_t> words, std::string* error) {
    const auto fail = [&](const std::string& why) {
        if (error) *error = why;
        return std::nullopt;
    };
    if (words.size() < 5 || words[0] != kMagic) return fail("not a SPIR-V module (no magic number)");
    Ids ids;
    for (size_t at = 5; at < words.size();) {
        const uint32_t count = words[at] >> 16, op = words[at] & 0xffffu;
        if (count == 0 || at + count > words.size()) return fail("a truncated instruction at word " + std::to_string(at));
        readInstruction(op, words.subspan(at + 1, count - 1), ids);
        at += count;
    }
    if (ids.entryPoints != 1) return fail(std::to_string(ids.entryPoints) + " entry points (one expected)");
    return collect(ids);
}

const char* toString(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return "vertex";
        case ShaderStage::Fragment: return "fragment";
        case ShaderStage::Compute: return "compute";
        case ShaderStage::Other: break;
    }
    return "other";
}

const char* toString(Resource kind) {
    switch (kind) {
        case Resource::UniformBuffer: return "a uniform buffer";
        case Resource::StorageBuffer: return "a storage buffer";
        case Resource::CombinedImageSampler: return "a combined image sampler";
        case Resource::StorageImage: return "a storage image";
        case Resource::SampledImage: return "a sampled image";
        case Resource::Sampler: return "a sampler";
        case Resource::Other: break;
    }
    return "something else";
}

const char* toString(shader::DescriptorKind kind) {
    switch (kind) {
        case shader::DescriptorKind::UniformBuffer: return "a uniform buffer";
        case shader::DescriptorKind::StorageBuffer: return "a storage buffer";
        case shader::DescriptorKind::StorageBufferDynamic: return "a dynamic storage buffer";
        case shader::DescriptorKind::CombinedImageSampler: return "a combined image sampler";
        case shader::DescriptorKind::StorageImage: return "a storage image";
    }
    return "?";
}

const char* toString(shader::SpecType type) {
    switch (type) {
        case shader::SpecType::Bool: return "bool";
        case shader::SpecType::Int: return "int";
        case shader::SpecType::Uint: return "uint";
        case shader::SpecType::Float: return "float";
    }
    return "?";
}

Resource toResource(shader::DescriptorKind kind) {
    switch (kind) {
        case shader::DescriptorKind::UniformBuffer: return Resource::UniformBuffer;
        case shader::DescriptorKind::StorageBuffer:
        case shader::DescriptorKind::StorageBufferDynamic: return Resource::StorageBuffer;
        case shader::DescriptorKind::CombinedImageSampler: return Resource::CombinedImageSampler;
        case shader::DescriptorKind::StorageImage: return Resource::StorageImage;
    }
    return Resource::Other;
}

uint32_t stageBit(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return shader::kStageVertex;
        case ShaderStage::Fragment: return shader::kStageFragment;
        case ShaderStage::Compute: return shader::kStageCompute;
        case ShaderStage::Other: break;
    }
    return 0;
}

}  // namespace orbis::contract
