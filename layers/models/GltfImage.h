#pragma once
// The checks a glTF image's bytes pass before stb decodes them. glTF's images are PNG or JPEG;
// stb trusts a PNG's chunk lengths and grows its output for as long as the compressed data
// inflates (a 1 KiB file asked for 1.9 GB in the fuzzer; a zlib bomb gives gigabytes), so a PNG
// is walked first: every chunk inside the bytes, and its image data inflating to no more than
// its header's size. No allocation here depends on the input.

#include <cstddef>
#include <string>

namespace orbis::models {

/// Empty when stb may decode `bytes`; else why not ("a PNG chunk runs past the end of the data").
std::string checkGltfImageBytes(const unsigned char* bytes, size_t size);

}  // namespace orbis::models
