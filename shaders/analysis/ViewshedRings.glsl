// The viewshed's body (viewshed.comp for GPUs, viewshed_cpu.comp for CPU devices: the same code
// with a workgroup of another size). Included after the workgroup size is declared.

layout(push_constant) uniform PushBlock { ViewshedPush push; };

layout(set = kViewshedSet, binding = kViewshedBindingHeights, std430) readonly buffer Heights { float heights[]; };
layout(set = kViewshedSet, binding = kViewshedBindingHorizon, std430) coherent buffer Horizon { float horizon[]; };
layout(set = kViewshedSet, binding = kViewshedBindingSight, std430) writeonly buffer Sights { uint sights[]; };

int at(ivec2 offset) { return (push.observerRow + offset.y) * push.side + push.observerCol + offset.x; }
float Z(ivec2 offset) { return horizon[at(offset)]; }

// One cell at `o` from the observer (|o.x|, |o.y| <= d, one of them d).
void cell(ivec2 o) {
    ivec2 c = ivec2(push.observerCol, push.observerRow) + o;
    if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, ivec2(push.side)))) return;
    int index = at(o);
    float r2 = float(o.x * o.x + o.y * o.y);
    float raw = heights[index];
    float h = raw - push.eye - push.dropPerCell2 * r2;
    if (push.radius2Cells > 0.0 && r2 > push.radius2Cells) {
        sights[index] = kSightOutOfRange;
        horizon[index] = isnan(h) ? 0.0 : h;
        return;
    }
    int i = abs(o.x), j = abs(o.y);
    ivec2 sgn = ivec2(sign(o));
    bool own = i <= 1 && j <= 1;
    float z = h;
    if (own) z = h;
    else if (i == j) z = Z(o - sgn) * float(i) / float(i - 1);
    else if (j == 0) z = Z(o - ivec2(sgn.x, 0)) * float(i) / float(i - 1);
    else if (i == 0) z = Z(o - ivec2(0, sgn.y)) * float(j) / float(j - 1);
    else if (i > j) z = (Z(o - sgn) * float(j) + Z(o - ivec2(sgn.x, 0)) * float(i - j)) / float(i - 1);
    else z = (Z(o - sgn) * float(i) + Z(o - ivec2(0, sgn.y)) * float(j - i)) / float(j - 1);
    if (isnan(raw)) {
        sights[index] = kSightNoData;
        horizon[index] = own ? -push.observerHeight : z;
        return;
    }
    sights[index] = own || h + push.targetHeight >= z ? kSightVisible : kSightHidden;
    horizon[index] = max(h, z);
}

void main() {
    // The quadrant: x and y directions from the workgroup's number.
    ivec2 q = ivec2((gl_WorkGroupID.x & 1u) == 0u ? 1 : -1, (gl_WorkGroupID.x & 2u) == 0u ? 1 : -1);
    int lane = int(gl_LocalInvocationID.x);
    if (lane == 0) {
        sights[at(ivec2(0))] = kSightVisible;
        horizon[at(ivec2(0))] = -push.observerHeight;
    }
    memoryBarrierBuffer();
    barrier();
    for (int d = 1; d <= push.ring; ++d) {
        // (d, 0) .. (d, d), then (d - 1, d) .. (0, d): t in [0, 2 d].
        for (int t = lane; t <= 2 * d; t += int(gl_WorkGroupSize.x)) {
            ivec2 o = t <= d ? ivec2(d, t) : ivec2(2 * d - t, d);
            cell(o * q);
        }
        memoryBarrierBuffer();
        barrier();
    }
}
