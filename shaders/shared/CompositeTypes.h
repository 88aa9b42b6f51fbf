// A layer's own image (premultiplied linear colour and alpha, one texel a pixel) blended over
// the scene: shaders/common/fullscreen.vert + composite.frag, one pipeline per layer (the FMV's
// decal, the volume's ray-cast image). The composite reads set kCompositeSet, binding
// kCompositeBindingImage, a combined image sampler seen by the fragment stage: each such layer
// puts its image there in its own set layout (FmvTypes.h, VolumeTypes.h); the rest of that set
// is the layer's own, and the build checks the composite against each layer's table.
#ifndef ORBIS_SHADERS_SHARED_COMPOSITE_TYPES_H
#define ORBIS_SHADERS_SHARED_COMPOSITE_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kCompositeSet, 1)
ORBIS_CONST(uint, kCompositeBindingImage, 6)

ORBIS_NAMESPACE_END

#endif
