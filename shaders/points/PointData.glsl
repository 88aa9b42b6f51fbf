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
