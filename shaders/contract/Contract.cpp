#include "shaders/contract/Contract.h"

#include "shaders/contract/SpirvModule.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <regex>
#include <set>

namespace orbis::contract {
namespace {

using Errors = std::vector<std::string>;

std::string describe(const SpirvDescriptor& d) {
    std::string s = "set " + std::to_string(d.set) + " binding " + std::to_string(d.binding);
    return d.name.empty() ? s : s + " ('" + d.name + "')";
}

std::string arraySize(uint32_t count) { return count == 1 ? "" : count == 0 ? "[]" : "[" + std::to_string(count) + "]"; }

void checkDescriptor(const PipelineContract& p, const SpirvModule& m, const SpirvDescriptor& d, const std::string& where,
                     Errors& errors) {
    const auto table = std::find_if(p.sets.begin(), p.sets.end(), [&](const SetTable& t) { return t.set == d.set; });
    if (table == p.sets.end()) {
        errors.push_back(where + " declares " + describe(d) + " (" + toString(d.kind) + "), but the C++ pipeline layout has no table for set " +
                         std::to_string(d.set));
        return;
    }
    const auto b = std::find_if(table->bindings.begin(), table->bindings.end(),
                                [&](const shader::DescriptorBinding& x) { return x.binding == d.binding; });
    const std::string cpp = std::string(table->table) + " (set " + std::to_string(d.set) + ")";
    if (b == table->bindings.end()) {
        errors.push_back(where + " declares " + describe(d) + " as " + toString(d.kind) + arraySize(d.count) + ", but " + cpp +
                         " has no binding " + std::to_string(d.binding));
        return;
    }
    if (toResource(b->kind) != d.kind)
        errors.push_back(where + ": " + describe(d) + " is " + toString(d.kind) + " in the shader but " + toString(b->kind) + " in " +
                         cpp);
    if (b->count != d.count)
        errors.push_back(where + ": " + describe(d) + " is an array of " + std::to_string(d.count) + " in the shader but " +
                         std::to_string(b->count) + " in " + cpp);
    if ((b->stages & stageBit(m.stage)) == 0)
        errors.push_back(where + ": " + describe(d) + " is read by the " + toString(m.stage) + " stage, which " + cpp +
                         " does not give it");
}

void checkSpecConstants(const PipelineContract& p, const SpirvModule& m, const std::string& where, Errors& errors) {
    const std::string table = p.specTable ? p.specTable : "the pipeline's constants (it names none)";
    for (const SpirvSpecConstant& c : m.specConstants) {
        const std::string what = "constant_id " + std::to_string(c.id) + (c.name.empty() ? "" : " ('" + c.name + "')");
        const auto named = std::find_if(p.specConstants.begin(), p.specConstants.end(),
                                        [&](const shader::SpecConstant& s) { return s.id == c.id; });
        if (named == p.specConstants.end())
            errors.push_back(where + ": " + what + " is not one of " + table);
        else if (!c.type || *c.type != named->type)
            errors.push_back(where + ": " + what + " is " + (c.type ? toString(*c.type) : "of another type") + " in the shader but " +
                             toString(named->type) + " in " + table);
    }
}

void checkLocalSize(const PipelineContract& p, const SpirvModule& m, const std::string& where, Errors& errors) {
    const auto text = [](const std::array<uint32_t, 3>& s) {
        char t[48];
        std::snprintf(t, sizeof t, "(%u, %u, %u)", s[0], s[1], s[2]);
        return std::string(t);
    };
    if (m.localSizeFromIds)
        errors.push_back(where + ": the workgroup size comes from specialisation constants; give it from the shared header's constants");
    else if (m.localSize != p.localSize)
        errors.push_back(where + ": the workgroup size is " + text(m.localSize) + " in the shader but " + text(p.localSize) +
                         " from the C++ group size constants");
}

void checkVertexInputs(const PipelineContract& p, const SpirvModule& m, const std::string& where, Errors& errors) {
    const std::set<uint32_t> cpp(p.vertexInputs.begin(), p.vertexInputs.end());
    std::set<uint32_t> glsl;
    for (const SpirvInput& in : m.inputs) {
        glsl.insert(in.location);
        if (!cpp.count(in.location))
            errors.push_back(where + ": vertex input location " + std::to_string(in.location) + " ('" + in.name +
                             "') is not one the C++ attributes name");
    }
    for (uint32_t location : cpp)
        if (!glsl.count(location))
            errors.push_back(where + ": the C++ attributes feed vertex input location " + std::to_string(location) +
                             ", which the shader does not declare");
}

}  // namespace

Errors checkPipeline(const PipelineContract& p) {
    Errors errors;
    for (const ShaderModule& s : p.shaders) {
        const std::string where = std::string(p.name) + ": " + s.file;
        std::string error;
        const std::optional<SpirvModule> m = readSpirv(s.spirv, &error);
        if (!m) {
            errors.push_back(where + ": " + error);
            continue;
        }
        for (const SpirvDescriptor& d : m->descriptors) checkDescriptor(p, *m, d, where, errors);
        checkSpecConstants(p, *m, where, errors);
        if (m->stage == ShaderStage::Compute) checkLocalSize(p, *m, where, errors);
        if (m->stage == ShaderStage::Vertex) checkVertexInputs(p, *m, where, errors);
    }
    return errors;
}

std::vector<LayoutLiteral> findLayoutLiterals(const std::filesystem::path& folder) {
    static const std::regex layout(R"(layout\s*\(([^)]*)\)(.*))");
    static const std::regex qualifier(R"(^\s*(set|binding|constant_id|local_size_[xyz]|location)\s*=\s*([0-9]\S*)\s*$)");
    static const std::regex vertexInput(R"(^\s*(flat\s+)?in\b)");
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::recursive_directory_iterator(folder)) {
        const std::string ext = e.path().extension().string();
        if (e.is_regular_file() && (ext == ".vert" || ext == ".frag" || ext == ".comp" || ext == ".glsl")) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    std::vector<LayoutLiteral> found;
    for (const auto& path : files) {
        std::ifstream in(path);
        std::string line;
        for (int n = 1; std::getline(in, line); ++n) {
            line = line.substr(0, line.find("//"));
            std::smatch l;
            if (!std::regex_search(line, l, layout)) continue;
            const std::string qualifiers = l[1].str(), rest = l[2].str();
            size_t start = 0;
            for (size_t comma = 0; comma != std::string::npos; start = comma + 1) {
                comma = qualifiers.find(',', start);
                const std::string part = qualifiers.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
                std::smatch q;
                if (!std::regex_match(part, q, qualifier)) continue;
                const bool isLocation = q[1] == "location";
                // A location is the C++ side's only on a vertex shader's inputs.
                if (isLocation && (path.extension() != ".vert" || !std::regex_search(rest, vertexInput))) continue;
                found.push_back({std::filesystem::relative(path, folder).generic_string(), n, q[1].str() + " = " + q[2].str()});
            }
        }
    }
    return found;
}

}  // namespace orbis::contract
