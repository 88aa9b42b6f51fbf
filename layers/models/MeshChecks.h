#pragma once
// Checks on a mesh file's bytes before Assimp reads it, for what Assimp itself does not bound:
// a PLY header whose element counts its file cannot hold (Assimp reserves them first: 4e9
// vertices asked for tens of GB), and a COLLADA node graph that instantiates itself (Assimp
// recurses until the stack overflows) or expands to more nodes than memory holds. And the model
// a KMZ's KML links. CPU only, no allocation that depends on the input beyond its size. Each
// returns why the input is refused, or empty.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace orbis::models {

/// The most nodes a COLLADA scene may expand to (instances counted as copies).
inline constexpr uint64_t kMaxColladaNodes = 1'000'000;

/// A PLY file (its first bytes and its whole size): the header's elements must fit in the file.
std::string checkPlyHeader(std::string_view head, uint64_t fileBytes);

/// A COLLADA document: no node instantiates itself, directly or through others, and the scene
/// expands to at most kMaxColladaNodes nodes. A document expat cannot parse is left to Assimp.
std::string checkColladaNodes(std::string_view xml);

/// The href of the first <Model>'s <Link> in a KML document, trimmed and unescaped (&amp;);
/// empty when there is none.
std::string kmlModelHref(std::string_view kml);

}  // namespace orbis::models
