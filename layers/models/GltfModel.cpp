#include "layers/models/GltfModel.h"

#include "layers/models/GltfAccessors.h"
#include "layers/models/GltfAnimation.h"
#include "layers/models/GltfImage.h"
#include "layers/models/GltfRig.h"
#include "formats/motion/Attitude.h"

#include <tiny_gltf.h>
#include <stb_image.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <set>

namespace orbis::models {
namespace {

namespace fs = std::filesystem;

// Extensions whose absence from our reader changes only the look, not the geometry.
const std::set<std::string> kUnderstoodExtensions = {
    "KHR_materials_unlit", "KHR_texture_transform", "KHR_materials_emissive_strength",
    "KHR_materials_specular", "KHR_materials_ior", "KHR_materials_transmission",
    "KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_volume",
    "KHR_materials_variants", "KHR_lights_punctual", "KHR_mesh_quantization",
};

// Decodes an image with stb after checking its size from the header alone, so that a small
// file claiming a huge image cannot make us allocate without bound. `user` is the model being
// loaded: tinygltf hands on an image's bufferView without checking it against its buffer (a
// byteOffset past the end pointed stb at wild memory), so the bytes must lie in one of the
// model's buffers, which it has read by then.
bool loadImage(tinygltf::Image* image, const int index, std::string* err, std::string* /*warn*/, int, int,
               const unsigned char* bytes, int size, void* user) {
    // An image from a file or a data URI has no bufferView: tinygltf read it into memory of its own.
    if (image->bufferView >= 0) {
        const auto* model = static_cast<const tinygltf::Model*>(user);
        const auto at = reinterpret_cast<std::uintptr_t>(bytes);
        const bool inBuffer = size >= 0 && std::any_of(model->buffers.begin(), model->buffers.end(), [&](const tinygltf::Buffer& b) {
            const auto begin = reinterpret_cast<std::uintptr_t>(b.data.data());
            return !b.data.empty() && at >= begin && at - begin <= b.data.size() && size_t(size) <= b.data.size() - (at - begin);
        });
        if (!inBuffer) {
            if (err) *err += "image " + std::to_string(index) + ": its bufferView lies outside its buffer\n";
            return false;
        }
    }
    if (size < 0) return false;
    if (const std::string why = checkGltfImageBytes(bytes, size_t(size)); !why.empty()) {
        if (err) *err += "image " + std::to_string(index) + ": " + why + "\n";
        return false;
    }
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(bytes, size, &w, &h, &comp)) {
        if (err) *err += "image " + std::to_string(index) + ": not a PNG/JPEG/... stb can read (" + stbi_failure_reason() + ")\n";
        return false;
    }
    if (w <= 0 || h <= 0 || w > int(kMaxGltfImageSide) || h > int(kMaxGltfImageSide)) {
        if (err) {
            *err += "image " + std::to_string(index) + ": " + std::to_string(w) + "x" + std::to_string(h) +
                    " is larger than the " + std::to_string(kMaxGltfImageSide) + " pixels a side allowed\n";
        }
        return false;
    }
    unsigned char* data = stbi_load_from_memory(bytes, size, &w, &h, &comp, 4);
    if (!data) {
        if (err) *err += "image " + std::to_string(index) + ": cannot decode (" + stbi_failure_reason() + ")\n";
        return false;
    }
    image->width = w;
    image->height = h;
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image.assign(data, data + size_t(w) * size_t(h) * 4);
    stbi_image_free(data);
    return true;
}

// tinygltf reads external buffers and images whole: refuse files over the model limit first.
bool readWholeFileBounded(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (!ec && size > kMaxGltfFileBytes) {
        if (err) *err += path + ": " + std::to_string(size >> 20) + " MiB is more than a model's file may have\n";
        return false;
    }
    return tinygltf::ReadWholeFile(out, err, path, user);
}

/// A primitive's vertex attributes as floats (each empty when the primitive has none).
struct PrimitiveAttributes {
    std::vector<float> positions, normals, uvs, colors, joints, weights;
    int colorComponents = 0;
    size_t count = 0;   ///< vertices
};

/// A primitive ready to append to the model: interleaved vertices, their skin and morph data,
/// triangle-list indices.
struct PrimitiveVertices {
    std::vector<ModelVertex> vertices;
    std::vector<ModelSkinVertex> skin;   ///< empty unless skinned
    std::vector<float> morph;            ///< (vertex, target) pairs of 6 floats
    std::vector<uint32_t> indices;
    uint32_t maxJoint = 0;
};

PrimitiveVertices buildVertices(const PrimitiveAttributes& a);
/// Flat normals: every triangle gets its own three vertices.
void flattenNormals(PrimitiveVertices& p, size_t targets);

class Reader {
public:
    Reader(const tinygltf::Model& m, std::string file) : m_(m), file_(file), acc_(m, std::move(file)) {}

    Result<ModelData> read();

private:
    std::string where(int accessor, const std::string& what) const { return acc_.where(accessor, what); }
    Result<std::vector<float>> floats(int accessor, int components, const std::string& what) const {
        return acc_.floats(accessor, components, what, kMaxGltfVertices);
    }
    Result<void> readPrimitive(const tinygltf::Primitive& p, const std::string& meshName, ModelData& out);
    Result<PrimitiveAttributes> readAttributes(const tinygltf::Primitive& p, const std::string& label, ModelData& out);
    Result<std::vector<float>> readMorphTargets(const tinygltf::Primitive& p, const std::string& label, size_t n,
                                                const ModelData& out);
    Result<std::vector<uint32_t>> readIndices(const tinygltf::Primitive& p, const std::string& label, size_t n,
                                              const ModelData& out);
    void appendPrimitive(const tinygltf::Primitive& p, PrimitiveVertices v, ModelData& out) const;
    void readMaterials(ModelData& out);
    void readTextures(ModelData& out);
    Result<void> walk(int node, const glm::dmat4& parent, int depth, ModelData& out);
    /// The default scene's root nodes.
    std::vector<int> rootNodes() const;

    const tinygltf::Model& m_;
    std::string file_;
    GltfAccessors acc_;
    std::vector<std::vector<uint32_t>> meshPrimitives_;   // per mesh: our primitive indices
    std::set<std::string> warned_;
    void warnOnce(ModelData& out, const std::string& text) {
        if (warned_.insert(text).second) out.warnings.push_back(text);
    }
};

uint32_t packColor(float r, float g, float b, float a) {
    auto q = [](float v) { return uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    return q(r) | (q(g) << 8) | (q(b) << 16) | (q(a) << 24);
}

Result<void> Reader::readPrimitive(const tinygltf::Primitive& p, const std::string& meshName, ModelData& out) {
    const std::string label = "mesh '" + meshName + "'";
    if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP && p.mode != TINYGLTF_MODE_TRIANGLE_FAN && p.mode != -1) {
        warnOnce(out, "points and lines primitives are not drawn (" + label + ")");
        return {};
    }
    auto attributes = readAttributes(p, label, out);
    if (!attributes) return attributes.error();
    auto morph = readMorphTargets(p, label, attributes->count, out);
    if (!morph) return morph.error();
    auto indices = readIndices(p, label, attributes->count, out);
    if (!indices) return indices.error();
    PrimitiveVertices v = buildVertices(*attributes);
    v.morph = std::move(*morph);
    v.indices = std::move(*indices);
    // No normals: flat ones (the spec's rule), so every triangle gets its own three vertices.
    if (attributes->normals.empty()) {
        flattenNormals(v, p.targets.size());
        if (out.vertices.size() + v.vertices.size() > kMaxGltfVertices) return makeError(file_ + ": more than " + std::to_string(kMaxGltfVertices) + " vertices in all");
        if (out.rig.morphDeltas.size() / 6 + v.morph.size() / 6 > kMaxGltfMorphDeltas)
            return makeError(file_ + ": more than " + std::to_string(kMaxGltfMorphDeltas) + " morph target vertices in all");
    }
    appendPrimitive(p, std::move(v), out);
    return {};
}

Result<PrimitiveAttributes> Reader::readAttributes(const tinygltf::Primitive& p, const std::string& label, ModelData& out) {
    PrimitiveAttributes a;
    auto pos = p.attributes.find("POSITION");
    if (pos == p.attributes.end()) return makeError(file_ + ": a primitive of " + label + " has no POSITION");
    auto positions = floats(pos->second, 3, "POSITION of " + label);
    if (!positions) return positions.error();
    a.positions = std::move(*positions);
    a.count = a.positions.size() / 3;
    if (out.vertices.size() + a.count > kMaxGltfVertices) return makeError(file_ + ": more than " + std::to_string(kMaxGltfVertices) + " vertices in all");
    const auto read = [&](const char* name, int components, std::vector<float>& to) -> Result<void> {
        auto it = p.attributes.find(name);
        if (it == p.attributes.end()) return {};
        auto r = floats(it->second, components, std::string(name) + " of " + label);
        if (!r) return r.error();
        to = std::move(*r);
        return {};
    };
    if (auto r = read("NORMAL", 3, a.normals); !r) return r.error();
    if (auto r = read("TEXCOORD_0", 2, a.uvs); !r) return r.error();
    if (auto it = p.attributes.find("COLOR_0"); it != p.attributes.end() && it->second >= 0 && size_t(it->second) < m_.accessors.size()) {
        a.colorComponents = gltfComponentCount(m_.accessors[size_t(it->second)].type);
        if (a.colorComponents == 3 || a.colorComponents == 4)
            if (auto r = read("COLOR_0", a.colorComponents, a.colors); !r) return r.error();
    }
    // Skinning: JOINTS_0 (unsigned byte or short) and WEIGHTS_0 (float or normalized).
    const bool hasJoints = p.attributes.count("JOINTS_0") > 0, hasWeights = p.attributes.count("WEIGHTS_0") > 0;
    if (hasJoints != hasWeights)
        return makeError(file_ + ": a primitive of " + label + " has " + (hasJoints ? "JOINTS_0 without WEIGHTS_0" : "WEIGHTS_0 without JOINTS_0"));
    if (hasJoints) {
        if (auto r = read("JOINTS_0", 4, a.joints); !r) return r.error();
        if (auto r = read("WEIGHTS_0", 4, a.weights); !r) return r.error();
        if (p.attributes.count("JOINTS_1")) warnOnce(out, "only the first four joint influences (JOINTS_0) are used (" + label + ")");
    }
    for (auto* attr : {&a.normals, &a.uvs, &a.colors, &a.joints, &a.weights}) {
        const size_t per = attr == &a.uvs ? 2 : attr == &a.colors ? size_t(a.colorComponents) : (attr == &a.joints || attr == &a.weights) ? 4 : 3;
        if (!attr->empty() && attr->size() / per != a.count) {
            return makeError(file_ + ": the attributes of a primitive of " + label + " have different counts");
        }
    }
    return a;
}

Result<std::vector<float>> Reader::readMorphTargets(const tinygltf::Primitive& p, const std::string& label, size_t n,
                                                    const ModelData& out) {
    // POSITION and NORMAL deltas, (vertex, target) pairs of 6 floats.
    const size_t targets = p.targets.size();
    std::vector<float> morph;
    if (targets > kMaxGltfMorphTargets)
        return makeError(file_ + ": a primitive of " + label + " has " + std::to_string(targets) + " morph targets; at most " +
                         std::to_string(kMaxGltfMorphTargets) + " are read");
    if (targets == 0) return morph;
    if (out.rig.morphDeltas.size() / 6 + n * targets > kMaxGltfMorphDeltas)
        return makeError(file_ + ": more than " + std::to_string(kMaxGltfMorphDeltas) + " morph target vertices in all");
    morph.assign(n * targets * 6, 0.0f);
    for (size_t k = 0; k < targets; ++k) {
        for (const char* attr : {"POSITION", "NORMAL"}) {
            const auto it = p.targets[k].find(attr);
            if (it == p.targets[k].end()) continue;
            const std::string what = std::string(attr) + " of morph target " + std::to_string(k) + " of " + label;
            auto d = floats(it->second, 3, what);
            if (!d) return d.error();
            if (d->size() != n * 3) return makeError(where(it->second, what) + ": " + std::to_string(d->size() / 3) +
                                                     " elements for " + std::to_string(n) + " vertices");
            const size_t off = attr[0] == 'P' ? 0 : 3;
            for (size_t v = 0; v < n; ++v)
                for (size_t c = 0; c < 3; ++c) morph[(v * targets + k) * 6 + off + c] = (*d)[v * 3 + c];
        }
    }
    return morph;
}

Result<std::vector<uint32_t>> Reader::readIndices(const tinygltf::Primitive& p, const std::string& label, size_t n,
                                                  const ModelData& out) {
    std::vector<uint32_t> idx;
    if (p.indices >= 0) {
        auto r = acc_.indices(p.indices, "indices of " + label, kMaxGltfIndices);
        if (!r) return r.error();
        idx = std::move(*r);
        for (uint32_t i : idx) {
            if (i >= n) return makeError(where(p.indices, "indices of " + label) + ": index " + std::to_string(i) + " is past the " + std::to_string(n) + " vertices");
        }
    } else {
        idx.resize(n);
        for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
    }
    // Strips and fans to lists (the winding of every other strip triangle flipped back).
    if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP || p.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        std::vector<uint32_t> list;
        for (size_t i = 2; i < idx.size(); ++i) {
            if (p.mode == TINYGLTF_MODE_TRIANGLE_FAN) list.insert(list.end(), {idx[0], idx[i - 1], idx[i]});
            else if (i % 2 == 0) list.insert(list.end(), {idx[i - 2], idx[i - 1], idx[i]});
            else list.insert(list.end(), {idx[i - 1], idx[i - 2], idx[i]});
        }
        idx = std::move(list);
    }
    idx.resize(idx.size() / 3 * 3);
    if (out.indices.size() + idx.size() > kMaxGltfIndices) return makeError(file_ + ": more than " + std::to_string(kMaxGltfIndices) + " indices in all");
    return idx;
}

PrimitiveVertices buildVertices(const PrimitiveAttributes& a) {
    PrimitiveVertices out;
    out.vertices.resize(a.count);
    out.skin.resize(a.joints.empty() ? 0 : a.count);
    for (size_t i = 0; i < a.count; ++i) {
        ModelVertex& v = out.vertices[i];
        for (int c = 0; c < 3; ++c) v.position[c] = a.positions[i * 3 + size_t(c)];
        if (!a.normals.empty()) for (int c = 0; c < 3; ++c) v.normal[c] = a.normals[i * 3 + size_t(c)];
        else v.normal[0] = v.normal[1] = v.normal[2] = 0.0f;
        v.uv[0] = a.uvs.empty() ? 0.0f : a.uvs[i * 2];
        v.uv[1] = a.uvs.empty() ? 0.0f : a.uvs[i * 2 + 1];
        if (a.colors.empty()) v.color = 0xffffffffu;
        else {
            const float* c = &a.colors[i * size_t(a.colorComponents)];
            v.color = packColor(c[0], c[1], c[2], a.colorComponents == 4 ? c[3] : 1.0f);
        }
        if (out.skin.empty()) continue;
        for (int c = 0; c < 4; ++c) {
            const float j = a.joints[i * 4 + size_t(c)], w = a.weights[i * 4 + size_t(c)];
            out.skin[i].joints[c] = uint16_t(std::clamp(j, 0.0f, 65535.0f));
            out.skin[i].weights[c] = std::isfinite(w) ? w : 0.0f;
            if (out.skin[i].weights[c] != 0.0f) out.maxJoint = std::max<uint32_t>(out.maxJoint, out.skin[i].joints[c]);
        }
    }
    return out;
}

void flattenNormals(PrimitiveVertices& p, size_t targets) {
    // Skin and morph data follow their vertex; morphing does not turn flat normals.
    std::vector<ModelVertex> flat;
    std::vector<ModelSkinVertex> flatSkin;
    std::vector<float> flatMorph;
    const std::vector<uint32_t>& idx = p.indices;
    flat.reserve(idx.size());
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
        const glm::vec3 a = glm::make_vec3(p.vertices[idx[t]].position), b = glm::make_vec3(p.vertices[idx[t + 1]].position),
                        c = glm::make_vec3(p.vertices[idx[t + 2]].position);
        glm::vec3 nrm = glm::cross(b - a, c - a);
        const float len = glm::length(nrm);
        nrm = len > 0.0f ? nrm / len : glm::vec3(0.0f, 1.0f, 0.0f);
        for (int k = 0; k < 3; ++k) {
            const uint32_t src = idx[t + size_t(k)];
            ModelVertex v = p.vertices[src];
            v.normal[0] = nrm.x; v.normal[1] = nrm.y; v.normal[2] = nrm.z;
            flat.push_back(v);
            if (!p.skin.empty()) flatSkin.push_back(p.skin[src]);
            if (!p.morph.empty()) flatMorph.insert(flatMorph.end(), p.morph.begin() + long(src * targets * 6), p.morph.begin() + long((src + 1) * targets * 6));
        }
    }
    p.vertices = std::move(flat);
    p.skin = std::move(flatSkin);
    p.morph = std::move(flatMorph);
    for (size_t i = 0; i < p.indices.size(); ++i) p.indices[i] = uint32_t(i);
}

void Reader::appendPrimitive(const tinygltf::Primitive& p, PrimitiveVertices v, ModelData& out) const {
    ModelPrimitive prim;
    prim.firstIndex = uint32_t(out.indices.size());
    prim.indexCount = uint32_t(v.indices.size());
    prim.vertexOffset = int32_t(out.vertices.size());
    prim.vertexCount = uint32_t(v.vertices.size());
    prim.material = (p.material >= 0 && size_t(p.material) < m_.materials.size()) ? p.material : -1;
    prim.morphTargets = uint32_t(p.targets.size());
    prim.morphBase = uint32_t(out.rig.morphDeltas.size() / 6);
    prim.skinned = !v.skin.empty();
    prim.maxJoint = v.maxJoint;
    // Skin data stays parallel to the vertices once a skinned primitive has been read.
    if (prim.skinned || !out.rig.skinVertices.empty()) {
        out.rig.skinVertices.resize(out.vertices.size(), ModelSkinVertex{});   // zeros for the unskinned ones before
        if (prim.skinned) out.rig.skinVertices.insert(out.rig.skinVertices.end(), v.skin.begin(), v.skin.end());
        else out.rig.skinVertices.resize(out.rig.skinVertices.size() + v.vertices.size(), ModelSkinVertex{});
    }
    out.rig.morphDeltas.insert(out.rig.morphDeltas.end(), v.morph.begin(), v.morph.end());
    out.vertices.insert(out.vertices.end(), v.vertices.begin(), v.vertices.end());
    out.indices.insert(out.indices.end(), v.indices.begin(), v.indices.end());
    out.primitives.push_back(prim);
}

void Reader::readTextures(ModelData& out) {
    for (const tinygltf::Texture& t : m_.textures) {
        ModelTexture tex;
        tex.name = t.name;
        if (t.source >= 0 && size_t(t.source) < m_.images.size()) {
            const tinygltf::Image& img = m_.images[size_t(t.source)];
            if (tex.name.empty()) tex.name = img.name.empty() ? img.uri : img.name;
            if (img.width > 0 && img.height > 0 && img.component == 4 && img.bits == 8 &&
                img.image.size() == size_t(img.width) * size_t(img.height) * 4) {
                tex.width = uint32_t(img.width);
                tex.height = uint32_t(img.height);
                tex.mips = buildMips(img.image.data(), tex.width, tex.height);
            }
        }
        if (tex.mips.empty()) {   // missing or unreadable image: a white texel, and say so
            warnOnce(out, "texture '" + tex.name + "' has no readable image: drawn white");
            tex.width = tex.height = 1;
            tex.mips = {std::vector<uint8_t>{255, 255, 255, 255}};
        }
        if (t.sampler >= 0 && size_t(t.sampler) < m_.samplers.size()) {
            const tinygltf::Sampler& s = m_.samplers[size_t(t.sampler)];
            const auto wrap = [](int mode) {
                return mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? TextureWrap::Clamp
                       : mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? TextureWrap::Mirror
                                                                      : TextureWrap::Repeat;
            };
            tex.wrapU = wrap(s.wrapS);
            tex.wrapV = wrap(s.wrapT);
            tex.nearest = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        }
        out.textures.push_back(std::move(tex));
    }
}

void Reader::readMaterials(ModelData& out) {
    for (const tinygltf::Material& mat : m_.materials) {
        ModelMaterial m;
        m.name = mat.name;
        const auto& f = mat.pbrMetallicRoughness.baseColorFactor;
        if (f.size() == 4) m.baseColorFactor = glm::vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3]));
        const int t = mat.pbrMetallicRoughness.baseColorTexture.index;
        if (t >= 0 && size_t(t) < out.textures.size()) {
            m.baseColorTexture = t;
            if (mat.pbrMetallicRoughness.baseColorTexture.texCoord != 0) {
                warnOnce(out, "material '" + m.name + "' uses TEXCOORD_" + std::to_string(mat.pbrMetallicRoughness.baseColorTexture.texCoord) + ": TEXCOORD_0 is used");
            }
        }
        if (mat.alphaMode == "MASK") m.alphaMode = AlphaMode::Mask;
        else if (mat.alphaMode == "BLEND") m.alphaMode = AlphaMode::Blend;
        m.alphaCutoff = float(mat.alphaCutoff);
        m.doubleSided = mat.doubleSided;
        m.unlit = mat.extensions.count("KHR_materials_unlit") > 0;
        out.materials.push_back(std::move(m));
    }
}

glm::dmat4 nodeMatrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());
    glm::dmat4 m(1.0);
    if (n.translation.size() == 3) m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
    if (n.rotation.size() == 4) m *= glm::mat4_cast(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]));
    if (n.scale.size() == 3) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
    return m;
}

Result<void> Reader::walk(int node, const glm::dmat4& parent, int depth, ModelData& out) {
    if (node < 0 || size_t(node) >= m_.nodes.size()) return makeError(file_ + ": node " + std::to_string(node) + " does not exist");
    if (depth > 256) return makeError(file_ + ": the node hierarchy is deeper than 256 (a cycle?) at node " + std::to_string(node));
    const tinygltf::Node& n = m_.nodes[size_t(node)];
    const glm::dmat4 world = parent * nodeMatrix(n);
    if (n.skin >= 0 && size_t(n.skin) >= out.rig.skins.size())
        return makeError(file_ + ": node " + std::to_string(node) + " names skin " + std::to_string(n.skin) + ", which does not exist");
    if (n.mesh >= 0) {
        if (size_t(n.mesh) >= meshPrimitives_.size()) return makeError(file_ + ": node " + std::to_string(node) + " names mesh " + std::to_string(n.mesh) + ", which does not exist");
        const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
        for (uint32_t prim : meshPrimitives_[size_t(n.mesh)]) {
            if (out.draws.size() >= 1'000'000) return makeError(file_ + ": more than a million drawn primitives");
            const ModelPrimitive& p = out.primitives[prim];
            int skin = -1;
            if (p.skinned && n.skin < 0) {
                warnOnce(out, "node " + std::to_string(node) + " draws a mesh with joints but has no skin: drawn unskinned");
            } else if (p.skinned) {
                skin = n.skin;
                const size_t joints = out.rig.skins[size_t(skin)].joints.size();
                if (p.maxJoint >= joints)
                    return makeError(file_ + ": node " + std::to_string(node) + " uses skin " + std::to_string(skin) + " with " +
                                     std::to_string(joints) + " joints, but its mesh " + std::to_string(n.mesh) +
                                     " has vertices on joint " + std::to_string(p.maxJoint));
            }
            out.draws.push_back({prim, glm::mat4(world), mirrored, node, skin});
            out.triangles += p.indexCount / 3;
            for (uint32_t i = 0; i < p.indexCount; ++i) {
                const ModelVertex& v = out.vertices[size_t(p.vertexOffset) + out.indices[p.firstIndex + i]];
                const glm::dvec3 q = glm::dvec3(world * glm::dvec4(v.position[0], v.position[1], v.position[2], 1.0));
                out.boundsMin = glm::min(out.boundsMin, q);
                out.boundsMax = glm::max(out.boundsMax, q);
            }
        }
    }
    for (int child : n.children) {
        if (auto r = walk(child, world, depth + 1, out); !r) return r;
    }
    return {};
}

std::vector<int> Reader::rootNodes() const {
    if (!m_.scenes.empty()) {
        const int s = (m_.defaultScene >= 0 && size_t(m_.defaultScene) < m_.scenes.size()) ? m_.defaultScene : 0;
        return m_.scenes[size_t(s)].nodes;
    }
    // No scene: every node that is nobody's child.
    std::vector<int> roots;
    std::vector<bool> child(m_.nodes.size(), false);
    for (const auto& n : m_.nodes) for (int c : n.children) if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = true;
    for (size_t i = 0; i < m_.nodes.size(); ++i) if (!child[i]) roots.push_back(int(i));
    return roots;
}

Result<ModelData> Reader::read() {
    ModelData out;
    out.file = file_;
    for (const std::string& ext : m_.extensionsRequired) {
        if (!kUnderstoodExtensions.count(ext)) return makeError(file_ + ": requires the glTF extension " + ext + ", which Orbis does not read");
    }
    readTextures(out);
    readMaterials(out);
    meshPrimitives_.resize(m_.meshes.size());
    for (size_t mi = 0; mi < m_.meshes.size(); ++mi) {
        const tinygltf::Mesh& mesh = m_.meshes[mi];
        const std::string name = mesh.name.empty() ? std::to_string(mi) : mesh.name;
        for (const tinygltf::Primitive& p : mesh.primitives) {
            const size_t before = out.primitives.size();
            if (auto r = readPrimitive(p, name, out); !r) return r.error();
            if (out.primitives.size() > before) meshPrimitives_[mi].push_back(uint32_t(before));
        }
    }
    // The rig, when anything can move or bend (glTF 2.0 3.7.2.1: every primitive of a mesh has
    // the same morph targets).
    std::vector<uint32_t> meshTargets(m_.meshes.size(), 0);
    bool deforms = false;
    for (size_t mi = 0; mi < m_.meshes.size(); ++mi) {
        const auto& prims = m_.meshes[mi].primitives;
        for (const tinygltf::Primitive& p : prims) {
            if (p.targets.size() != prims.front().targets.size())
                return makeError(file_ + ": the primitives of mesh " + std::to_string(mi) + " have different numbers of morph targets");
        }
        if (!prims.empty()) meshTargets[mi] = uint32_t(prims.front().targets.size());
        deforms |= meshTargets[mi] > 0;
    }
    for (const ModelPrimitive& p : out.primitives) deforms |= p.skinned;
    if (deforms || !m_.animations.empty() || !m_.skins.empty()) {
        auto r = readRig(m_, acc_, file_, meshTargets, out, [&](const std::string& w) { warnOnce(out, w); });
        if (!r) return r.error();
    }
    out.boundsMin = glm::dvec3(std::numeric_limits<double>::max());
    out.boundsMax = glm::dvec3(-std::numeric_limits<double>::max());
    for (int r : rootNodes()) {
        if (auto w = walk(r, glm::dmat4(1.0), 0, out); !w) return w.error();
    }
    if (out.draws.empty()) return makeError(file_ + ": the scene has no triangles to draw");
    // Keep the rig only when a pose can differ from the rest pose baked in the draws: the fast
    // path for everything else.
    bool animated = false;
    for (const ModelAnimation& a : out.rig.animations) animated |= !a.channels.empty();
    for (const ModelDraw& d : out.draws) animated |= d.skin >= 0 || out.primitives[d.primitive].morphTargets > 0;
    if (!animated) {
        out.rig = {};
        for (ModelPrimitive& p : out.primitives) p.skinned = false, p.morphTargets = 0;
        for (ModelDraw& d : out.draws) d.skin = -1;
    } else {
        posedBounds(out);
    }
    return out;
}

}  // namespace

uint64_t ModelData::textureBytes() const {
    uint64_t bytes = 0;
    for (const auto& t : textures) for (const auto& m : t.mips) bytes += m.size();
    return bytes;
}

glm::dmat3 gltfToBody() { return motion::gltfToBody(); }

std::vector<std::vector<uint8_t>> buildMips(const uint8_t* rgba, uint32_t width, uint32_t height) {
    std::vector<std::vector<uint8_t>> mips;
    mips.emplace_back(rgba, rgba + size_t(width) * height * 4);
    uint32_t w = width, h = height;
    while (w > 1 || h > 1) {
        const uint32_t nw = std::max(1u, w / 2), nh = std::max(1u, h / 2);
        const std::vector<uint8_t>& src = mips.back();
        std::vector<uint8_t> dst(size_t(nw) * nh * 4);
        for (uint32_t y = 0; y < nh; ++y) {
            for (uint32_t x = 0; x < nw; ++x) {
                const uint32_t x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
                const uint32_t y0 = std::min(2 * y, h - 1), y1 = std::min(2 * y + 1, h - 1);
                for (int c = 0; c < 4; ++c) {
                    const unsigned sum = src[(size_t(y0) * w + x0) * 4 + c] + src[(size_t(y0) * w + x1) * 4 + c] +
                                         src[(size_t(y1) * w + x0) * 4 + c] + src[(size_t(y1) * w + x1) * 4 + c];
                    dst[(size_t(y) * nw + x) * 4 + c] = uint8_t((sum + 2) / 4);
                }
            }
        }
        mips.push_back(std::move(dst));
        w = nw;
        h = nh;
    }
    return mips;
}

Result<ModelData> loadGltf(const std::string& path) {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec) return makeError(path + ": cannot read (" + ec.message() + ")");
    if (size > kMaxGltfFileBytes) {
        return makeError(path + ": " + std::to_string(size >> 20) + " MiB is more than the " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB a model may have");
    }
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &readWholeFileBounded, &tinygltf::WriteWholeFile, nullptr});
    tinygltf::Model model;
    loader.SetImageLoader(&loadImage, &model);
    std::string err, warn;
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    bool binary = ext == ".glb";
    if (!binary && ext != ".gltf") {   // sniff: a .glb starts with "glTF"
        char magic[4] = {};
        if (FILE* f = std::fopen(path.c_str(), "rb")) {
            binary = std::fread(magic, 1, 4, f) == 4 && std::memcmp(magic, "glTF", 4) == 0;
            std::fclose(f);
        }
    }
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                           : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
        for (auto& c : err) if (c == '\n') c = ';';
        return makeError(path + ": not a readable glTF 2.0 file: " + (err.empty() ? std::string("unknown error") : err));
    }
    return Reader(model, path).read();
}

}  // namespace orbis::models
