#pragma once
// Reading glTF accessors with every byte checked against its buffer view and buffer: the one
// place where file offsets turn into pointers. Internal to the glTF reader (GltfModel.cpp and
// GltfRig.cpp); includes tinygltf. No Vulkan.
//
// Sparse accessors (glTF 2.0, 3.6.2.3) are read whole: the base values (zeros when the accessor
// has no buffer view) with the sparse values written over them at their indices. Morph targets
// use them often.

#include "base/Result.h"

#include <tiny_gltf.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace orbis::models {

int gltfComponentCount(int type);       ///< 1 for SCALAR ... 16 for MAT4; 0 for an unknown type
int gltfComponentBytes(int componentType);   ///< 1, 2 or 4; 0 for an unknown type

class GltfAccessors {
public:
    GltfAccessors(const tinygltf::Model& model, std::string file) : m_(model), file_(std::move(file)) {}

    /// "<file>: accessor N (<what>)", the start of every message about an accessor.
    std::string where(int accessor, const std::string& what) const;
    /// Reads `components` numbers per element as floats (normalized integers scaled). At most
    /// `maxCount` elements.
    Result<std::vector<float>> floats(int accessor, int components, const std::string& what, uint64_t maxCount) const;
    /// Unsigned integer scalars (indices).
    Result<std::vector<uint32_t>> indices(int accessor, const std::string& what, uint64_t maxCount) const;
    /// The number of elements, or nothing when the accessor does not exist.
    std::optional<size_t> count(int accessor) const;

private:
    /// The byte span of `count` elements of `elementBytes` at `byteOffset` in `bufferView`,
    /// checked; the stride in `stride` (`tight`: ignore the view's byteStride, as sparse data).
    Result<const uint8_t*> view(int bufferView, size_t byteOffset, size_t count, size_t elementBytes, bool tight,
                                size_t* stride, const std::string& where) const;

    const tinygltf::Model& m_;
    std::string file_;
};

}  // namespace orbis::models
