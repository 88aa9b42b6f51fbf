#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "shared/FrameUniforms.h"
#include "shared/VolumeTypes.h"

// Ray casting of a (lon, lat, height) grid in its curved box: one ray per pixel, marched
// relative to the volume's origin (float, small numbers), each sample turned into (lon, lat,
// height) in a numerically stable form. Direct volume rendering composites front to back with
// opacity corrected for the step; isosurfaces are found by a sign change between samples, then
// refined by secant/bisection steps, lit with Phong shading and a normal from central
// differences. A jittered start, early termination, and an end at the scene depth.

layout(local_size_x = kVolumeGroupSize, local_size_y = kVolumeGroupSize) in;

// What the scene's modes use is compiled in; the rest is left out.
layout(constant_id = kVolumeSpecDvr) const bool kDvr = true;
layout(constant_id = kVolumeSpecIsoCount) const int kIsoCount = 0;     // isosurfaces (0 .. kVolumeMaxIso)
layout(constant_id = kVolumeSpecSliceCount) const int kSliceCount = 0; // slice planes (0 .. kVolumeMaxSlices)
// Measurement only (tests, benchmarks): write each ray's first isosurface distance, and find
// crossings without refinement (at the sample after the sign change).
layout(constant_id = kVolumeSpecHitOutput) const bool kHitOutput = false;
layout(constant_id = kVolumeSpecRefine) const bool kRefine = true;
// Time steps blended at the current time: a second field fetch per sample (only then).
layout(constant_id = kVolumeSpecBlendTimeSteps) const bool kBlendTimeSteps = false;
// Which axes are evenly spaced (bit 1 << kVolumeAxis*): those map linearly, the others
// through the lookup table. A constant, not a uniform: CPU devices run both sides of a branch.
layout(constant_id = kVolumeSpecUniformAxes) const int kUniformAxes = 7;
// Empty-space skipping: rays jump over bricks that show nothing.
layout(constant_id = kVolumeSpecSkipEmpty) const bool kSkipEmpty = true;
// Pre-integrated transfer function: a DVR step composites the segment from the previous sample
// (the value taken as linear between the two) from a 2-D table, instead of the sample's value.
layout(constant_id = kVolumeSpecPreIntegrate) const bool kPreIntegrate = false;
// Which pass: one ray per pixel (kVolumePassFull); rays at a reduced resolution into lowImage
// (kVolumePassLowRes); or, at full resolution, lowImage interpolated where its rays agree and
// the scene's depth is continuous, a ray of the pixel's own elsewhere (kVolumePassRefine).
layout(constant_id = kVolumeSpecPass) const int kPass = kVolumePassFull;

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = kVolumeSet, binding = kVolumeBindingUniforms) uniform VolumeBlock { VolumeUniforms vol; };
layout(set = kVolumeSet, binding = kVolumeBindingField) uniform sampler3D field;
layout(set = kVolumeSet, binding = kVolumeBindingAxes, std430) readonly buffer AxisBlock { float axisTable[]; };
layout(set = kVolumeSet, binding = kVolumeBindingTransfer) uniform sampler1D transfer;
layout(set = kVolumeSet, binding = kVolumeBindingSceneDepth) uniform sampler2D sceneDepth;
layout(set = kVolumeSet, binding = kVolumeBindingCastImage, rgba16f) uniform writeonly image2D outImage;
layout(set = kVolumeSet, binding = kVolumeBindingHits, r32f) uniform writeonly image2D hitImage;   // kHitOutput only
layout(set = kVolumeSet, binding = kVolumeBindingBricks, std430) readonly buffer BrickBlock { uint brickBits[]; };
layout(set = kVolumeSet, binding = kVolumeBindingPreIntegrated) uniform sampler2D preIntegrated;   // kPreIntegrate only
layout(set = kVolumeSet, binding = kVolumeBindingLowRes, rgba16f) uniform image2D lowImage;   // kVolumePassLowRes, Refine

// One ray, marched relative to the volume's origin in ECEF axes (float, small numbers): its
// eye, its unit direction, and the cosine and sine of the origin's longitude (longitudes are
// taken relative to the origin's meridian).
struct Ray {
    vec3 eye;
    vec3 dir;
    float c0, s0;
};

// One sample of the field, as the march and the refinement see it.
struct Sample {
    vec3 geo;      // (lon, lat, height): degrees, degrees, metres of data height
    float rho;     // distance from the polar axis (m)
    float value;   // the field (0 outside the box; NaN where there is no data)
    bool ok;       // inside the box, with data
    bool inBox;
    // Empty-space skipping only (kSkipEmpty): voxel coordinates, and whether the sample's brick
    // shows nothing.
    vec3 vox;
    bool empty;
};

// The march along one segment: where the next sample is (t), the step (dt), the rate at which
// the box's normalised coordinates change per metre, and the previous sample (its t, its
// normalised position, the sample itself).
struct March {
    float t, dt, rate;
    bool jumped;   // the last advance jumped: the sample stands for one step, not the jump
    float prevT;
    vec3 prevN;
    Sample prev;
};

// This ray's slice hits, two per slice: ray parameter (1e30: none) and colour.
struct SliceHits {
    float t[2 * kVolumeMaxSlices];
    vec4 c[2 * kVolumeMaxSlices];
};

bool uniformAxis(int axis) { return (kUniformAxes & (1 << axis)) != 0; }

// Coordinate -> texture coordinate along one axis (texel centres at the samples).
float axisCoord(int axis, float x, float first, float last, float n, bool uniformAxis) {
    float f = clamp((x - first) / (last - first), 0.0, 1.0);
    if (uniformAxis) return (f * (n - 1.0) + 0.5) / n;
    float s = f * float(kVolumeAxisTable - 1);
    int t0 = min(int(s), int(kVolumeAxisTable) - 2);
    int base = axis * int(kVolumeAxisTable);
    return mix(axisTable[base + t0], axisTable[base + t0 + 1], s - float(t0));
}

// Where the ray meets the surface at height H (semi-axes a + H, a + H, b + H): t entering and
// leaving. `os` is the origin scaled by 1 / axes, c0 = |os|^2 - 1 (from doubles on the CPU), so
// the quadratic's constant term is small numbers only.
vec2 shellHits(Ray ray, vec3 os, float c0, vec2 invAxes) {
    vec3 sc = vec3(invAxes.x, invAxes.x, invAxes.y);
    vec3 es = ray.eye * sc, w = ray.dir * sc;
    float qa = dot(w, w);
    float qb = dot(os + es, w);
    float qc = c0 + 2.0 * dot(os, es) + dot(es, es);
    float disc = qb * qb - qa * qc;
    if (disc < 0.0) return vec2(1e30, -1e30);
    float q = -(qb + (qb >= 0.0 ? 1.0 : -1.0) * sqrt(disc));   // stable roots q / qa and qc / q
    float r0 = q / qa, r1 = q != 0.0 ? qc / q : r0;
    return vec2(min(r0, r1), max(r0, r1));
}

float hash(uvec2 p, uint frameIndex) {
    uint h = p.x * 1973u + p.y * 9277u + frameIndex * 26699u;
    h = (h ^ (h >> 13)) * 1274126177u;
    h ^= h >> 16;
    return float(h & 0xffffu) / 65536.0;
}

// (lon, lat, height) of the point at ray parameter t: degrees, degrees, metres of data height;
// `rho` its distance from the polar axis.
vec3 geoAt(Ray ray, float t, out float rho) {
    vec3 d = ray.eye + t * ray.dir;   // relative to the origin, ECEF axes
    // Longitude relative to the origin's meridian: no large number is subtracted.
    float xa = vol.originRho + (d.x * ray.c0 + d.y * ray.s0);
    float yb = d.y * ray.c0 - d.x * ray.s0;
    rho = length(vec2(xa, yb));
    float z = vol.originZ + d.z;
    float lonDeg = degrees(vol.originLon + atan(yb, xa));
    lonDeg = vol.lonFirst + mod(lonDeg - vol.lonFirst, 360.0);
    float latDeg = degrees(atan(z, rho * vol.oneMinusE2));   // geodetic, near the surface
    // Radius of the ellipsoid along the point's direction, without trigonometry:
    // r = a b |p| / sqrt(b^2 rho^2 + a^2 z^2).
    float a = vol.equatorialRadius, b = vol.polarRadius;
    float r = length(vec2(rho, z));
    float rEll = a * b * r / length(vec2(b * rho, a * z));
    return vec3(lonDeg, latDeg, (r - rEll) / vol.verticalExaggeration);
}

// The position in the box's normalised coordinates (0..1 along lon, lat and height).
vec3 normalised(vec3 geo) {
    return vec3((geo.x - vol.lonFirst) / (vol.lonLast - vol.lonFirst),
                (geo.y - vol.latFirst) / (vol.latLast - vol.latFirst),
                (geo.z - vol.heightFirst) / (vol.heightLast - vol.heightFirst));
}

// The field at a position (`rho` from geoAt); not ok outside the box or where there is no data.
Sample sampleGeo(vec3 geo, float rho) {
    Sample s;
    s.geo = geo;
    s.rho = rho;
    s.value = 0.0;
    s.vox = vec3(0.0);
    s.empty = false;
    s.inBox = !(geo.x > vol.lonLast || geo.y < vol.latFirst || geo.y > vol.latLast || geo.z < vol.heightFirst ||
                geo.z > vol.heightLast);
    vec3 tc = vec3(axisCoord(kVolumeAxisLon, geo.x, vol.lonFirst, vol.lonLast, vol.samples.x, uniformAxis(kVolumeAxisLon)),
                   axisCoord(kVolumeAxisLat, geo.y, vol.latFirst, vol.latLast, vol.samples.y, uniformAxis(kVolumeAxisLat)),
                   axisCoord(kVolumeAxisHeight, geo.z, vol.heightFirst, vol.heightLast, vol.samples.z,
                             uniformAxis(kVolumeAxisHeight)));
    // Its brick (a brick covers the voxels a linear sample reads): empty-space skipping.
    if (kSkipEmpty) {
        s.vox = clamp(tc * vol.samples - 0.5, vec3(0.0), vol.samples - 1.0);
        ivec3 b = min(ivec3(s.vox / vol.brickSize), ivec3(vol.bricks) - 1);
        int brick = (b.z * int(vol.bricks.y) + b.y) * int(vol.bricks.x) + b.x;
        s.empty = s.inBox && (brickBits[brick >> 5] & (1u << (brick & 31))) == 0u;
    }
    s.ok = false;
    if (!s.inBox) return s;
    // Time steps are stacked along z: time step s occupies [s, s + 1) / timeSteps, and tc.z stays
    // half a texel inside one, so filtering never mixes time steps.
    float timeSteps = vol.timeStepCount;
    // One fetch site, in a loop of one or two: with two textureLod calls on `field` here,
    // lavapipe (Mesa 22.3.6) keeps about 0.4 MB of host memory more after every dispatch at
    // 640x360, without end (found by the soak, tools/soak.sh; valgrind's massif puts it inside
    // lavapipe's queue thread). With one call site the process stays flat.
    const int fetches = kBlendTimeSteps && vol.timeStepWeight > 0.0 ? 2 : 1;
    float value = 0.0;
    for (int k = 0; k < fetches; ++k) {
        float v = textureLod(field, vec3(tc.xy, ((k == 0 ? vol.timeStepA : vol.timeStepB) + tc.z) / timeSteps), 0.0).r;
        value = k == 0 ? v : mix(value, v, vol.timeStepWeight);
    }
    s.value = value * vol.valueScale + vol.valueOffset;   // half-float fields are stored relative to the range
    s.ok = !isnan(s.value);
    return s;
}

Sample sampleAt(Ray ray, float t) {
    float rho;
    vec3 geo = geoAt(ray, t, rho);
    return sampleGeo(geo, rho);
}

vec4 transferAt(float value) {
    float f = clamp((value - vol.rangeMin) * vol.rangeInvSpan, 0.0, 1.0);
    const float n = float(kVolumeTransferSize);
    return textureLod(transfer, (f * (n - 1.0) + 0.5) / n, 0.0);
}

float isovalue(int i) { return vol.isovalues[i / 4][i % 4]; }

// Where the field crosses `c` between ta (value va) and tb (value vb): regula falsi, with a
// bisection step whenever the secant lands badly or a sample has no data.
float refineCrossing(Ray ray, float ta, float va, float tb, float vb, float c) {
    for (int k = 0; k < 8; ++k) {
        float denom = vb - va;
        float tm = abs(denom) > 1e-20 ? ta + (c - va) * (tb - ta) / denom : 0.5 * (ta + tb);
        if (!(tm > ta && tm < tb) || k % 3 == 2) tm = 0.5 * (ta + tb);   // keep the bracket shrinking
        Sample m = sampleAt(ray, tm);
        if (!m.ok) return tm;
        if ((va - c) * (m.value - c) <= 0.0) { tb = tm; vb = m.value; }
        else { ta = tm; va = m.value; }
    }
    float denom = vb - va;
    return abs(denom) > 1e-20 ? ta + (c - va) * (tb - ta) / denom : 0.5 * (ta + tb);
}

// Unit gradient direction of the field at t (world axes), by central differences over `e`
// metres (one-sided at the box's faces); zero gradients (constant fields) fall back to facing
// the eye.
vec3 normalAt(Ray ray, float t, float e) {
    vec3 g = vec3(0.0);
    Sample s0 = sampleAt(ray, t);
    for (int axis = 0; axis < 3; ++axis) {
        vec3 off = vec3(0.0);
        off[axis] = e;
        // Sample along the ray's frame with the eye moved: the same position function is used.
        Ray moved = ray;
        moved.eye = ray.eye + off;
        Sample p = sampleAt(moved, t);
        moved.eye = ray.eye - off;
        Sample m = sampleAt(moved, t);
        // Central where both neighbours have data; one-sided at the box's faces and next to
        // no-data cells.
        if (p.ok && m.ok) g[axis] = (p.value - m.value) / (2.0 * e);
        else if (p.ok && s0.ok) g[axis] = (p.value - s0.value) / e;
        else if (m.ok && s0.ok) g[axis] = (s0.value - m.value) / e;
    }
    float len = length(g);
    return len > 1e-30 ? -g / len : -ray.dir;   // pointing toward lower values
}

// Ray parameters where the ray meets slice i (up to two; 1e30 where it does not).
vec2 sliceHits(Ray ray, int i) {
    vec3 A = vol.slices[i].vector;
    vec4 B = vol.slices[i].terms;
    int kind = int(vol.slices[i].kind + 0.5);
    vec2 none = vec2(1e30);
    vec3 e = ray.eye, dir = ray.dir;
    if (kind == kVolumeSliceLon) {   // meridian plane through the axis: n . (O + eye + t dir) = 0
        float nd = dot(A, dir);
        if (abs(nd) < 1e-12) return none;
        return vec2(-(B.x + dot(A, e)) / nd, 1e30);
    }
    if (kind == kVolumeSliceLat) {   // cone (z - apex)^2 = k rho^2
        float k = B.x;
        float qa = dir.z * dir.z - k * dot(dir.xy, dir.xy);
        float qb = (A.z + e.z) * dir.z - k * dot(A.xy + e.xy, dir.xy);
        float qc = B.y + 2.0 * (A.z * e.z - k * dot(A.xy, e.xy)) + (e.z * e.z - k * dot(e.xy, e.xy));
        if (abs(qa) < 1e-20) return abs(qb) > 1e-20 ? vec2(-0.5 * qc / qb, 1e30) : none;
        float disc = qb * qb - qa * qc;
        if (disc < 0.0) return none;
        float q = -(qb + (qb >= 0.0 ? 1.0 : -1.0) * sqrt(disc));
        return vec2(q / qa, q != 0.0 ? qc / q : 1e30);
    }
    vec2 h = shellHits(ray, A, B.x, B.yz);   // surface at a height
    return h.x < h.y ? h : none;
}

// The slices' hits in front of the scene (tEnter .. tExit), inside the box. The arrays are only
// ever indexed with loop counters of constant trip count, unrolled on request ([[unroll]]:
// lavapipe leaves loops this large rolled), never with data: dynamic indexing is very slow on
// CPU rasterisers (slices 143 -> 50 ms at 960x540 with the loops unrolled).
SliceHits findSliceHits(Ray ray, float tEnter, float tExit) {
    SliceHits hits;
    [[unroll]] for (int k = 0; k < 2 * kVolumeMaxSlices; ++k) hits.t[k] = 1e30;
    [[unroll]] for (int i = 0; i < kSliceCount; ++i) {
        vec2 ts = sliceHits(ray, i);
        [[unroll]] for (int j = 0; j < 2; ++j) {
            float th = ts[j];
            if (!(th >= tEnter && th <= tExit) || th >= 1e29) continue;
            float rho;
            vec3 geo = geoAt(ray, th, rho);
            // The right half-plane or nappe: the hit is at the slice's coordinate.
            int kind = int(vol.slices[i].kind + 0.5);
            if (kind == kVolumeSliceLon && abs(geo.x - vol.slices[i].terms.y) > 1.0) continue;
            if (kind == kVolumeSliceLat && abs(geo.y - vol.slices[i].terms.z) > 1.0) continue;
            Sample s = sampleGeo(geo, rho);
            if (!s.ok) continue;
            hits.t[i * 2 + j] = th;
            hits.c[i * 2 + j] = vec4(transferAt(s.value).rgb, vol.sliceOpacity);
        }
    }
    return hits;
}

float nearestSlice(SliceHits hits) {
    float t = 1e30;
    [[unroll]] for (int k = 0; k < 2 * kSliceCount; ++k) t = min(t, hits.t[k]);
    return t;
}

// Composites the nearest remaining slice hit over `acc`, removes it, returns the next one's t.
float compositeNearestSlice(inout SliceHits hits, inout vec4 acc) {
    float t = nearestSlice(hits);
    bool done = false;
    [[unroll]] for (int k = 0; k < 2 * kSliceCount; ++k) {
        if (!done && hits.t[k] == t) {
            vec4 c = hits.c[k];
            acc.rgb += (1.0 - acc.a) * c.a * c.rgb;
            acc.a += (1.0 - acc.a) * c.a;
            hits.t[k] = 1e30;
            done = true;
        }
    }
    return nearestSlice(hits);
}

// Front-to-back compositing of one DVR sample standing for `ds` of the normalised box. The
// table's alpha channel holds log2(1 - alpha) (alpha clamped to 0.9999): the opacity of a step
// of any length is one exp2 (no per-sample log).
void compositeSample(inout vec4 acc, float value, float ds) {
    vec4 tf = transferAt(value);
    // Opacity per 1/opacityPerUnit of the normalised box, whatever the step.
    float alpha = 1.0 - exp2(tf.a * (min(ds, 2.0) * vol.opacityPerUnit));
    acc.rgb += (1.0 - acc.a) * alpha * tf.rgb;
    acc.a += (1.0 - acc.a) * alpha;
}

// Front-to-back compositing of the ray segment `ds` of the normalised box long along which the
// value runs from `front` to `back` (kPreIntegrate): the table holds the segment's colour per
// unit of opacity, self-attenuation included, and the mean of log2(1 - alpha) along it, so the
// opacity is exact for any length (layers/volume/VolumeData.h, buildPreIntegratedTable).
void compositeSegment(inout vec4 acc, float front, float back, float ds) {
    const float n = float(kVolumeTransferSize);
    vec2 f = clamp((vec2(front, back) - vol.rangeMin) * vol.rangeInvSpan, 0.0, 1.0);
    vec4 tf = textureLod(preIntegrated, (f * (n - 1.0) + 0.5) / n, 0.0);
    float alpha = 1.0 - exp2(tf.a * (min(ds, 2.0) * vol.opacityPerUnit));
    acc.rgb += (1.0 - acc.a) * alpha * tf.rgb;
    acc.a += (1.0 - acc.a) * alpha;
}

// The DVR contribution of the step that ends at sample `s` (`ds` long): with pre-integration
// the segment from the previous sample (for the first, the entry) where there is one with data,
// otherwise `s` alone; without, `s`'s value over the step. After a jump over bricks that show
// nothing the step is one step long, from the value before the jump: a narrow band of opacity
// just past the jump is integrated across, not sampled at one point (which shows as speckles).
void compositeStep(inout vec4 acc, March m, Sample s, float ds) {
    if (kPreIntegrate) compositeSegment(acc, m.prev.ok ? m.prev.value : s.value, s.value, ds);
    else compositeSample(acc, s.value, ds);
}

// The march at the entry t0 of a segment. Steps are of equal length in the box's normalised
// coordinates (a thin shell gets as many samples across as a thick box); the rate of change is
// probed at the entry, then followed from sample to sample.
March startMarch(Ray ray, float t0, float jitter, float target, float dtMin, float dtMax) {
    March m;
    float rho;
    m.prevN = normalised(geoAt(ray, t0, rho));
    m.rate = length(normalised(geoAt(ray, t0 + vol.probeLength, rho)) - m.prevN) / vol.probeLength;
    m.dt = clamp(target / max(m.rate, 1e-20), dtMin, dtMax);
    m.t = t0 + jitter * m.dt;
    m.prevT = t0;
    m.prev = Sample(vec3(0.0), 0.0, 0.0, false, false, vec3(0.0), false);   // none yet
    m.jumped = false;
    return m;
}

// Next sample, after sample `s` (the march's i-th, at normalised position n, `ds` of the
// normalised box after the previous one): the step follows the rate at which the box's
// coordinates change along the ray. From a brick that shows nothing the ray jumps, in whole
// steps, to the first sample past the brick (its exit extrapolated from the last two samples'
// voxel coordinates; the jump is kept short enough that the curvature of (lon, lat, height)
// along the ray moves it < 1/4 voxel).
void advance(inout March m, Sample s, vec3 n, int i, float ds, float target, float dtMin, float dtMax) {
    float span = max(m.t - m.prevT, 1e-6);
    if (i > 0) m.rate = ds / span;
    m.dt = clamp(target / max(m.rate, 1e-20), dtMin, min(dtMax, 2.0 * m.dt));
    float stepT = m.dt;
    if (kSkipEmpty && s.empty && m.prev.inBox && i > 0) {
        vec3 dv = (s.vox - m.prev.vox) / span;   // voxels per metre
        vec3 wall = (floor(s.vox / vol.brickSize) + step(0.0, dv)) * vol.brickSize;
        vec3 tw = mix(vec3(1e30), (wall - s.vox) / dv, greaterThan(abs(dv), vec3(1e-20)));
        float tJump = min(min(tw.x, tw.y), min(tw.z, min(vol.jumpMax, s.rho * vol.jumpPerRho)));
        stepT = (min(floor(max(tJump, 0.0) * 0.98 / m.dt), 64.0) + 1.0) * m.dt;
    }
    m.jumped = stepT > 1.5 * m.dt;
    m.prevT = m.t;
    m.prevN = n;
    m.prev = s;
    m.t += stepT;
}

// An isosurface hit at tHit (isovalue c), Phong-shaded with the field's gradient over `e` metres.
vec3 shadeIsosurface(Ray ray, float tHit, float c, float e) {
    vec3 nrm = normalAt(ray, tHit, e);
    if (dot(nrm, ray.dir) > 0.0) nrm = -nrm;   // the side facing the eye
    bool sunLight = frame.sunLighting > 0.5;
    vec3 l = sunLight ? frame.sunDirection : -ray.dir;
    vec3 hv = normalize(l - ray.dir);
    vec3 base = transferAt(c).rgb;
    return base * (0.25 + 0.75 * max(dot(nrm, l), 0.0)) + 0.25 * pow(max(dot(nrm, hv), 0.0), 32.0);
}

Ray pixelRay(ivec2 px, ivec2 size) {
    vec2 ndc = (vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 far = frame.clipToWorldDir * vec4(ndc, 1.0, 1.0);
    Ray ray;
    ray.dir = normalize(far.xyz / far.w);
    ray.eye = vol.eyeFromOrigin;
    ray.c0 = cos(vol.originLon);
    ray.s0 = sin(vol.originLon);
    return ray;
}

// The part of the ray inside the box's bounds and before the scene's surface: (tEnter, tExit).
vec2 boxSpan(Ray ray, ivec2 px) {
    vec3 inv = 1.0 / ray.dir;
    vec3 ta = (vol.boxMin - ray.eye) * inv, tb = (vol.boxMax - ray.eye) * inv;
    vec3 tlo = min(ta, tb), thi = max(ta, tb);
    float tEnter = max(max(tlo.x, tlo.y), max(tlo.z, 0.0));
    float tExit = min(min(thi.x, thi.y), thi.z);
    float depth = texelFetch(sceneDepth, px, 0).r;
    if (depth > 0.0) tExit = min(tExit, vol.nearPlane / depth / max(dot(ray.dir, vol.forward), 1e-6));
    return vec2(tEnter, tExit);
}

// The parts of the ray between the bottom and top surfaces: up to two segments (in through the
// top and out through the bottom or the top again; or up from below the bottom).
void shellSegments(Ray ray, out vec2 segments[2]) {
    vec2 top = shellHits(ray, vol.shellHiOrigin, vol.shellHiC0, vol.shellHiInvAxes);
    vec2 bottom = shellHits(ray, vol.shellLoOrigin, vol.shellLoC0, vol.shellLoInvAxes);
    segments[0] = vec2(top.x, bottom.x > top.x && bottom.x < bottom.y ? min(top.y, bottom.x) : top.y);
    segments[1] = bottom.x < bottom.y && bottom.y > top.x && bottom.y < top.y ? vec2(bottom.y, top.y) : vec2(1e30, -1e30);
}

// The isovalue crossed between two samples (values a, then b): the nearest to a over all
// isovalues, by linear interpolation (refined by the caller); -1 for none.
int crossedIsovalue(float a, float b) {
    float best = 2.0;
    int hit = -1;
    [[unroll]] for (int k = 0; k < kIsoCount; ++k) {
        float c = isovalue(k);
        if ((a - c) * (b - c) < 0.0 || (b == c && a != c)) {
            float f = (c - a) / (b - a);
            if (f < best) { best = f; hit = k; }
        }
    }
    return hit;
}

// The surface c crossed between ta (value va) and tb (vb): found exactly (unless refinement is
// off), shaded with the gradient over `e` metres and composited; its distance kept as the first
// hit (measurement).
void compositeIsosurface(inout vec4 acc, Ray ray, float ta, float va, float tb, float vb, float c, float e,
                         inout float firstHit) {
    float tHit = kRefine ? refineCrossing(ray, ta, va, tb, vb, c) : tb;
    if (kHitOutput && firstHit >= 1e29) firstHit = tHit;
    vec3 lit = shadeIsosurface(ray, tHit, c, e);
    float alpha = vol.isoOpacity;
    acc.rgb += (1.0 - acc.a) * alpha * lit;
    acc.a += (1.0 - acc.a) * alpha;
}

// Marches the segment t0 .. t1 front to back into `acc`: DVR samples, isosurface crossings, and
// the slice hits on the way.
void marchSegment(Ray ray, float t0, float t1, float jitter, inout vec4 acc, inout SliceHits slices,
                  inout float nextSlice, inout float firstHit) {
    float dtMax = vol.stepLength, dtMin = vol.minStep, target = vol.normalisedStep;
    int maxSteps = int(vol.maxSteps);
    March m = startMarch(ray, t0, jitter, target, dtMin, dtMax);
    // Pre-integration: the entry is sampled too, so that the part of the ray before the first
    // (jittered) sample is a segment like the others (a point value there speckles the edges
    // where a face of the box cuts a narrow band of opacity).
    if (kPreIntegrate && kDvr) m.prev = sampleAt(ray, t0);
    int i = 0;
    // The march stops at each isosurface crossing, which is refined and shaded outside the
    // marching loop, then goes on. On SIMD devices (CPU rasterisers) every lane pays for what
    // any lane executes inside the loop: this way the expensive work runs once a hit instead of
    // at every step.
    for (;;) {
        bool found = false;
        int hitIso = -1;
        vec3 n = m.prevN;
        float ds = target;
        Sample s = m.prev;   // (the loop's first sample replaces it)
        for (; i < maxSteps && m.t < t1; ++i) {
            while (kSliceCount > 0 && nextSlice <= m.t) nextSlice = compositeNearestSlice(slices, acc);
            if (acc.a >= 0.99) break;
            s = sampleAt(ray, m.t);
            n = normalised(s.geo);
            // The first sample stands for a whole step; with pre-integration, for the part of
            // the ray from the entry (the jittered start), as the segments after it join samples.
            ds = i == 0 ? (kPreIntegrate ? jitter * target : target) : length(n - m.prevN);
            float dsSample = m.jumped ? target : ds;
            if (kIsoCount > 0 && s.ok && m.prev.ok) {
                hitIso = crossedIsovalue(m.prev.value, s.value);
                if (hitIso >= 0) { found = true; break; }
            }
            if (kDvr && s.ok) compositeStep(acc, m, s, dsSample);
            if (acc.a >= 0.99) break;
            advance(m, s, n, i, ds, target, dtMin, dtMax);
        }
        if (!found) {
            // Pre-integration: the rest of the segment after the last sample, up to the exit
            // (sampled there too).
            if (kPreIntegrate && kDvr && acc.a < 0.99 && i < maxSteps && m.prev.ok && t1 > m.prevT) {
                Sample e = sampleAt(ray, t1);
                compositeSegment(acc, m.prev.value, e.ok ? e.value : m.prev.value, (t1 - m.prevT) * m.rate);
            }
            break;
        }
        // The crossing between the previous sample and this one, shaded.
        compositeIsosurface(acc, ray, m.prevT, m.prev.value, m.t, s.value, isovalue(hitIso), max(0.25 * m.dt, 0.5), firstHit);
        if (acc.a >= 0.99) break;
        // This sample's own contribution, then on.
        if (kDvr && s.ok) compositeStep(acc, m, s, m.jumped ? target : ds);
        if (acc.a >= 0.99) break;
        advance(m, s, n, i, ds, target, dtMin, dtMax);
        ++i;
    }
}

// The ray through pixel `px` of an image `size` big (its scene depth read at the full-resolution
// pixel `depthPx`): premultiplied colour and opacity; `firstHit` its first isosurface distance.
vec4 castRay(ivec2 px, ivec2 size, ivec2 depthPx, inout float firstHit) {
    Ray ray = pixelRay(px, size);
    vec2 span = boxSpan(ray, depthPx);
    vec2 segments[2];
    shellSegments(ray, segments);
    SliceHits slices = findSliceHits(ray, span.x, span.y);
    float nextSlice = nearestSlice(slices);

    vec4 acc = vec4(0.0);
    float jitter = hash(uvec2(px), uint(vol.frameIndex));
    for (int sgi = 0; sgi < 2 && acc.a < 0.99 && (kDvr || kIsoCount > 0); ++sgi) {
        float t0 = max(segments[sgi].x, span.x), t1 = min(segments[sgi].y, span.y);
        if (t1 > t0) marchSegment(ray, t0, t1, jitter, acc, slices, nextSlice, firstHit);
    }
    // Slices beyond the last sample (or all of them when only slices are drawn).
    while (kSliceCount > 0 && nextSlice < 1e29 && acc.a < 0.99) nextSlice = compositeNearestSlice(slices, acc);
    return acc;
}

// The full-resolution pixel nearest to the centre of pixel `px` of the reduced image.
ivec2 fullPixel(ivec2 px, ivec2 low, ivec2 full) {
    return min(ivec2((vec2(px) + 0.5) * vec2(full) / vec2(low)), full - 1);
}

// kVolumePassRefine: the reduced-resolution rays around full-resolution pixel `px`,
// interpolated bilinearly into `c`, when they agree (each RGBA channel spread over the four
// no more than refineThreshold) and the scene's depth at their pixels is the pixel's own
// (within 2 %: a ray that ends on a surface stands only for pixels on that surface).
bool upsampled(ivec2 px, ivec2 full, out vec4 c) {
    ivec2 low = imageSize(lowImage);
    vec2 q = (vec2(px) + 0.5) * vec2(low) / vec2(full) - 0.5;
    ivec2 i0 = ivec2(floor(q));
    vec2 w = q - vec2(i0);
    ivec2 a = clamp(i0, ivec2(0), low - 1), b = clamp(i0 + 1, ivec2(0), low - 1);
    ivec2 n[4] = ivec2[4](a, ivec2(b.x, a.y), ivec2(a.x, b.y), b);
    vec4 v[4];
    vec4 lo = vec4(1e30), hi = vec4(-1e30);
    float d = texelFetch(sceneDepth, px, 0).r;
    bool sameSurface = true;
    [[unroll]] for (int k = 0; k < 4; ++k) {
        v[k] = imageLoad(lowImage, n[k]);
        lo = min(lo, v[k]);
        hi = max(hi, v[k]);
        float dn = texelFetch(sceneDepth, fullPixel(n[k], low, full), 0).r;
        sameSurface = sameSurface && abs(dn - d) <= 0.02 * max(dn, d);
    }
    c = mix(mix(v[0], v[1], w.x), mix(v[2], v[3], w.x), w.y);
    return sameSurface && all(lessThanEqual(hi - lo, vec4(vol.refineThreshold)));
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(outImage);
    float firstHit = 1e30;
    if (kPass == kVolumePassLowRes) {
        ivec2 low = imageSize(lowImage);
        if (any(greaterThanEqual(px, low))) return;
        imageStore(lowImage, px, castRay(px, low, fullPixel(px, low, size), firstHit));
        return;
    }
    if (any(greaterThanEqual(px, size))) return;
    vec4 acc;
    if (kPass == kVolumePassRefine && upsampled(px, size, acc)) {
        imageStore(outImage, px, acc);
        return;
    }
    acc = castRay(px, size, px, firstHit);
    imageStore(outImage, px, acc);
    if (kHitOutput) imageStore(hitImage, px, vec4(firstHit < 1e29 ? firstHit : -1.0));
}
