#include "layers/models/GltfAccessors.h"

#include <algorithm>
#include <cstring>

namespace orbis::models {
namespace {

float readComponent(const uint8_t* p, int componentType, bool normalized) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; std::memcpy(&v, p, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? float(*p) / 255.0f : float(*p);
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const float v = float(int8_t(*p));
            return normalized ? std::max(v / 127.0f, -1.0f) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v; std::memcpy(&v, p, 2);
            return normalized ? float(v) / 65535.0f : float(v);
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t v; std::memcpy(&v, p, 2);
            return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; std::memcpy(&v, p, 4); return float(v); }
        case TINYGLTF_COMPONENT_TYPE_INT: { int32_t v; std::memcpy(&v, p, 4); return float(v); }
        default: return 0.0f;
    }
}

uint32_t readIndex(const uint8_t* p, int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; std::memcpy(&v, p, 2); return v; }
        default: { uint32_t v; std::memcpy(&v, p, 4); return v; }
    }
}

bool isIndexType(int componentType) {
    return componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

}  // namespace

int gltfComponentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        case TINYGLTF_TYPE_MAT2: return 4;
        case TINYGLTF_TYPE_MAT3: return 9;
        case TINYGLTF_TYPE_MAT4: return 16;
        default: return 0;
    }
}

int gltfComponentBytes(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

std::string GltfAccessors::where(int accessor, const std::string& what) const {
    return file_ + ": accessor " + std::to_string(accessor) + " (" + what + ")";
}

std::optional<size_t> GltfAccessors::count(int accessor) const {
    if (accessor < 0 || size_t(accessor) >= m_.accessors.size()) return std::nullopt;
    return m_.accessors[size_t(accessor)].count;
}

Result<const uint8_t*> GltfAccessors::view(int bufferView, size_t byteOffset, size_t count, size_t elementBytes, bool tight,
                                           size_t* stride, const std::string& where) const {
    if (bufferView < 0 || size_t(bufferView) >= m_.bufferViews.size())
        return makeError(where + ": buffer view " + std::to_string(bufferView) + " does not exist");
    const tinygltf::BufferView& v = m_.bufferViews[size_t(bufferView)];
    if (v.buffer < 0 || size_t(v.buffer) >= m_.buffers.size()) return makeError(where + ": its buffer view names no buffer");
    const tinygltf::Buffer& buffer = m_.buffers[size_t(v.buffer)];
    const size_t s = (!tight && v.byteStride) ? v.byteStride : elementBytes;
    if (s < elementBytes) return makeError(where + ": byte stride " + std::to_string(s) + " is smaller than an element");
    *stride = s;
    if (v.byteOffset > buffer.data.size() || v.byteLength > buffer.data.size() - v.byteOffset)
        return makeError(where + ": buffer view " + std::to_string(bufferView) + " runs past its buffer");
    const uint8_t* base = buffer.data.data() + v.byteOffset;
    if (count == 0) return base;
    // The last element's end, in overflow-safe arithmetic.
    const unsigned __int128 end = (unsigned __int128)byteOffset + (unsigned __int128)(count - 1) * s + elementBytes;
    if (end > v.byteLength)
        return makeError(where + ": its " + std::to_string(count) + " elements run past buffer view " + std::to_string(bufferView));
    return base + byteOffset;
}

Result<std::vector<float>> GltfAccessors::floats(int index, int components, const std::string& what, uint64_t maxCount) const {
    if (index < 0 || size_t(index) >= m_.accessors.size()) return makeError(where(index, what) + ": no such accessor");
    const tinygltf::Accessor& a = m_.accessors[size_t(index)];
    const int n = gltfComponentCount(a.type);
    const int cb = gltfComponentBytes(a.componentType);
    if (n != components || cb == 0) {
        return makeError(where(index, what) + ": expected " + std::to_string(components) + " components, found type " +
                         std::to_string(a.type) + " of component type " + std::to_string(a.componentType));
    }
    if (a.count > maxCount) return makeError(where(index, what) + ": " + std::to_string(a.count) + " elements is more than allowed");
    const size_t elementBytes = size_t(n) * size_t(cb);
    std::vector<float> out(a.count * size_t(n), 0.0f);
    auto readInto = [&](const uint8_t* p, size_t i) {
        for (int c = 0; c < n; ++c) out[i * size_t(n) + size_t(c)] = readComponent(p + c * cb, a.componentType, a.normalized);
    };
    if (a.bufferView >= 0) {
        size_t stride = 0;
        auto p = view(a.bufferView, a.byteOffset, a.count, elementBytes, false, &stride, where(index, what));
        if (!p) return p.error();
        for (size_t i = 0; i < a.count; ++i) readInto(*p + i * stride, i);
    } else if (!a.sparse.isSparse) {
        return makeError(where(index, what) + ": has no buffer view and no sparse values");
    }
    if (a.sparse.isSparse) {
        const auto& sp = a.sparse;
        if (sp.count <= 0 || size_t(sp.count) > a.count)
            return makeError(where(index, what) + ": sparse count " + std::to_string(sp.count) + " is not within 1.." + std::to_string(a.count));
        if (!isIndexType(sp.indices.componentType))
            return makeError(where(index, what) + ": sparse indices must be unsigned byte, short or int");
        size_t istride = 0, vstride = 0;
        const int ib = gltfComponentBytes(sp.indices.componentType);
        auto idx = view(sp.indices.bufferView, size_t(std::max(0, sp.indices.byteOffset)), size_t(sp.count), size_t(ib), true,
                        &istride, where(index, what) + " sparse indices");
        if (!idx) return idx.error();
        auto val = view(sp.values.bufferView, size_t(std::max(0, sp.values.byteOffset)), size_t(sp.count), elementBytes, true,
                        &vstride, where(index, what) + " sparse values");
        if (!val) return val.error();
        for (size_t k = 0; k < size_t(sp.count); ++k) {
            const uint32_t i = readIndex(*idx + k * istride, sp.indices.componentType);
            if (i >= a.count)
                return makeError(where(index, what) + ": sparse index " + std::to_string(i) + " is past its " + std::to_string(a.count) + " elements");
            readInto(*val + k * vstride, i);
        }
    }
    return out;
}

Result<std::vector<uint32_t>> GltfAccessors::indices(int index, const std::string& what, uint64_t maxCount) const {
    if (index < 0 || size_t(index) >= m_.accessors.size()) return makeError(where(index, what) + ": no such accessor");
    const tinygltf::Accessor& a = m_.accessors[size_t(index)];
    const int cb = gltfComponentBytes(a.componentType);
    if (a.type != TINYGLTF_TYPE_SCALAR || !isIndexType(a.componentType))
        return makeError(where(index, what) + ": indices must be unsigned byte, short or int scalars");
    if (a.count > maxCount) return makeError(where(index, what) + ": " + std::to_string(a.count) + " indices is more than allowed");
    if (a.bufferView < 0 || a.sparse.isSparse)
        return makeError(where(index, what) + ": indices without a buffer view, or sparse, are not supported");
    size_t stride = 0;
    auto p = view(a.bufferView, a.byteOffset, a.count, size_t(cb), false, &stride, where(index, what));
    if (!p) return p.error();
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i) out[i] = readIndex(*p + i * stride, a.componentType);
    return out;
}

}  // namespace orbis::models
