// A point's position relative to the eye, from its node's data (layers/points/PointStore.h):
// quantised (3 x 21 bits in two words, offset 2^20, times the node's step) or 3 floats, both
// relative to the node's centre. Needs `words` (kPointBindingWords) in scope. Which of the two is a
// specialisation constant: the layer draws quantised and float nodes with separate pipelines,
// as a CPU device would run both paths under a mask.

layout(constant_id = kPointSpecQuantised) const bool kQuantised = true;

vec3 pointPosition(PointNode node, uint local) {
    float step = node.step;
    vec3 offset;
    if (kQuantised) {
        uint at = node.firstWord + 2u * local;
        uint w0 = words[at], w1 = words[at + 1u];
        uvec3 q = uvec3(w0 & 0x1FFFFFu, (w0 >> 21) | ((w1 & 0x3FFu) << 11), w1 >> 10);
        offset = (vec3(q) - 1048576.0) * step;
    } else {
        uint at = node.firstWord + 3u * local;
        offset = vec3(uintBitsToFloat(words[at]), uintBitsToFloat(words[at + 1u]), uintBitsToFloat(words[at + 2u]));
    }
    return node.centre + offset;
}

// Level-aware size: the radius (pixels) of a point of `node` at `p` (relative to the eye), from
// the spacing of the deepest level drawn at its place: the node's own where no child is drawn in
// its octant, halved for each level drawn below it there (layers/points/PointsLayer.cpp). So a
// budget that leaves out the finer nodes of a place draws that place's points larger, and holes
// do not open.
float adaptiveRadius(PointNode node, vec3 p) {
    uint octant = (p.x >= node.centre.x ? 1u : 0u) | (p.y >= node.centre.y ? 2u : 0u) | (p.z >= node.centre.z ? 4u : 0u);
    uint below = (node.octants >> (4u * octant)) & 15u;
    float spacing = node.spacing * exp2(-float(below));
    return 0.5 * spacing * pu.adaptivePixels / max(length(p), 1e-3);
}
