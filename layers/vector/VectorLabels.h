#pragma once
// The vector layer's labels on the CPU, frame by frame: which labelled features are seen, their
// text laid out (once per feature, with the glyph atlas), the choice of the labels to draw, and
// the glyph quads of those for the GPU (shared/VectorTypes.h: LabelRenderer draws them). No
// Vulkan. Main thread only.
//
// A labelled feature (a style that is visible and gives a label, an anchor: LabelAnchors.h) is
// a candidate this frame when it is shown at the scene's time, its anchor (at the ground's
// height: FrameContext::groundHeight, else 0) lies within the style's minRange..maxRange of the
// eye, in front of it, on the screen and on the near side of the ellipsoid; a line's label also
// needs the line to be longer on screen than the label. Candidates are ranked (labelPriority)
// and at most `maxCandidates` of the best are kept. LabelPlacer chooses among them (no two
// boxes overlap; hysteresis between frames) and, only for a label that has room, whether the
// terrain hides it (the straight line from the eye sampled against the ground).
//
// Alone, `update` does it all. The vector layers of a scene place their labels together, so
// that one layer's labels do not cover another's: each `gather`s its candidates, a LabelBoard
// places them all, and each `build`s the glyphs of its own.
//
// Label boxes: a point's text stands right of its icon (iconSize, drawn on the terrain by the
// drape), centred on the point's height, the icon inside its box; a polygon's text is centred
// on its interior point and wrapped at spaces into lines of 8 em at most; a line's text is
// centred on its middle and follows it glyph by glyph where it bends gently, else runs straight
// along it (kept upright; its box is the glyphs' bounding box). Every box is grown by the halo
// and `gapPx`.

#include "base/Result.h"
#include "engine/scene/FrameContext.h"
#include "layers/vector/GlyphAtlas.h"
#include "layers/vector/LabelAnchors.h"
#include "layers/vector/LabelLayout.h"
#include "layers/vector/LabelPlacement.h"
#include "layers/vector/VectorContent.h"
#include "shared/VectorTypes.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace orbis::vector {

struct VectorLabelOptions {
    GlyphAtlasOptions atlas;
    double haloPx = 2.0;              ///< the halo's width around each glyph's outline
    double gapPx = 1.0;               ///< clear space around every label (beyond its halo)
    double marginPx = 4.0;            ///< LabelPlacementOptions::marginPx: the hysteresis
    double priorityHysteresis = 4096.0;   ///< one size step of labelPriority: an old label keeps its place
    double iconGapPx = 3.0;           ///< between a point's icon and its text
    size_t maxCandidates = 20000;     ///< per frame, the best ranked first
};

/// A label drawn this frame: its box (icon, halo and gap included) in window pixels.
struct PlacedLabel {
    uint64_t id = 0;
    uint32_t layer = 0, feature = 0;
    glm::dvec2 min{0.0}, max{0.0};
};

struct VectorLabelStats {
    size_t labelled = 0;        ///< features with a label and an anchor
    size_t candidates = 0;      ///< seen this frame (in range, on screen, above the horizon)
    size_t placed = 0;
    size_t hidden = 0;          ///< had room but the terrain hides them
    size_t glyphs = 0;
    bool capped = false;        ///< more candidates than maxCandidates: the rest were left out
    double frameMs = 0.0;       ///< gathering, placement and glyphs together
    double gatherMs = 0.0;      ///< projection, visibility, layout, boxes
    double placementMs = 0.0;   ///< LabelPlacer::place, terrain tests included (a shared board: all layers')
};

class VectorLabels {
public:
    /// Loads the fonts (the error names the font file).
    static Result<VectorLabels> create(const VectorLabelOptions& options = {});

    /// New content or new styles: the labelled features again, their layouts made anew.
    /// `idsByFid`: a label's id comes from its feature's layer and fid, not its index, so that
    /// the placement's hysteresis holds across contents that hold a feature at another index (a
    /// paged source's labelled features, gathered again as pages come and go).
    void setContent(std::shared_ptr<const VectorContent> content, std::shared_ptr<const ContentStyles> styles,
                    std::shared_ptr<const ContentAnchors> anchors, bool idsByFid = false);
    /// This frame's labels and glyphs, placed by this object alone: gather, place, build.
    void update(const scene::FrameContext& frame);
    /// Nothing to draw (labels switched off); last frame's choice is forgotten.
    void clear();

    /// This frame's candidates (and nothing to draw until `build`).
    void gather(const scene::FrameContext& frame);
    /// The glyphs of the candidates chosen (indices into candidates()), and how long the
    /// placement took (for the stats).
    void build(std::span<const uint32_t> chosen, double placementMs, size_t hidden);
    /// True when the terrain hides candidate `index` from the eye of `frame`.
    bool hiddenByGround(uint32_t index, const scene::FrameContext& frame) const;
    /// Added to every label's id (a layer's own, so that ids stay unique on a shared board).
    void setIdBase(uint64_t base);
    /// Where a point drawn as a 3-D marker is shown now (ECEF), by its marker's feature id
    /// (1 + fid: MeshOptions::idsByFid); none: at its anchor. A moving point's label follows
    /// its marker (MarkerMotion) rather than jump ahead of it.
    using MarkerPlace = std::function<std::optional<glm::dvec3>(uint32_t featureId)>;
    void setMarkerPlace(MarkerPlace place) { markerPlace_ = std::move(place); }

    std::span<const shader::LabelGlyph> glyphs() const { return glyphs_; }
    GlyphAtlas& atlas() { return atlas_; }
    /// This frame's candidates (before the terrain test) and the labels drawn: for tests.
    std::span<const LabelCandidate> candidates() const { return candidates_; }
    std::span<const PlacedLabel> placed() const { return placed_; }
    const VectorLabelStats& stats() const { return stats_; }
    const VectorLabelOptions& options() const { return options_; }

private:
    /// One labelled feature, best ranked first.
    struct Entry {
        uint32_t layer = 0, feature = 0;
        int64_t fid = -1;
        uint64_t id = 0;
        double priority = 0.0;
        const LabelAnchor* anchor = nullptr;
        const FeatureStyle* style = nullptr;
        // The anchor in ECEF at the ground's height, for the ground of `groundVersion`.
        glm::dvec3 ecef{0.0}, surface{0.0};   ///< at the ground, and at max(ground, 0)
        double heightM = 0.0;
        uint64_t groundVersion = 0;
        bool located = false;
        TextLayout layout;
        bool laidOut = false;
    };
    /// A candidate's drawing: a layout point q lands at anchorPx + R(angle) (q + offset).
    struct Seen {
        uint32_t entry;
        glm::dvec2 anchorPx, offset;
        double angle;
        double iconPx = 0.0;   ///< a point's icon as seen from the camera's range
        /// A line's label bent along it: bent_[bentFirst, + bentCount) holds each glyph quad's
        /// place (its top left corner, in window pixels) and angle. None: the text is
        /// straight, turned by `angle`.
        uint32_t bentFirst = 0, bentCount = 0;
        glm::dvec3 at{0.0};   ///< where it stands (ECEF): its anchor, or its marker
    };

    struct Projection;

    explicit VectorLabels(GlyphAtlas atlas, const VectorLabelOptions& options)
        : options_(options), atlas_(std::move(atlas)) {}
    /// The candidates of this frame; false when a layout found the atlas full.
    bool gatherOnce(const scene::FrameContext& frame, const glm::dmat4& clipFromEye);
    /// A line's label: along the line, centred on its anchor, each glyph turned with the line
    /// where it bends gently (at most kMaxBendDeg between neighbouring glyphs), else straight
    /// along it; upright; false when the line is shorter on screen than the label.
    bool alongLine(const Entry& e, const TextLayout& layout, const Projection& project, Seen& s);
    std::span<const glm::dvec3> bentOf(const Seen& s) const { return {bent_.data() + s.bentFirst, s.bentCount}; }
    static constexpr double kMaxBendDeg = 25.0;
    /// The label's box for the placer.
    LabelCandidate candidateOf(const Entry& e, const TextLayout& layout, const Seen& s) const;
    void locate(Entry& e, const scene::FrameContext& frame);
    const TextLayout& layoutOf(Entry& e);
    void addGlyphs(const Seen& s);

    VectorLabelOptions options_;
    GlyphAtlas atlas_;
    LabelPlacer placer_;
    std::shared_ptr<const VectorContent> content_;
    std::shared_ptr<const ContentStyles> styles_;
    std::shared_ptr<const ContentAnchors> anchors_;
    std::vector<Entry> entries_;
    std::vector<LabelCandidate> candidates_;
    std::vector<Seen> seen_;
    std::vector<glm::dvec3> bent_;   ///< the bent labels' glyphs (Seen::bentFirst)
    std::vector<PlacedLabel> placed_;
    std::vector<shader::LabelGlyph> glyphs_;
    VectorLabelStats stats_;
    uint64_t idBase_ = 0;
    MarkerPlace markerPlace_;
};

/// True when the ellipsoid hides `point` from `eye` (ECEF): the straight line between them
/// enters the ellipsoid more than `toleranceM` before it reaches the point. A point below the
/// ellipsoid: give it at height 0.
bool hiddenByEllipsoid(const glm::dvec3& eye, const glm::dvec3& point, double toleranceM = 1.0);

/// True when the ground (`ground`: heights above the ellipsoid, nothing where unknown: 0) rises
/// above the straight line from `eye` to `point` (ECEF). The line is sampled at `samples`
/// places over its part below kGroundCeilingM (where the ground can be); its last max(5 m,
/// 0.2 %) is not tested, so that the ground a label stands on does not hide it.
bool hiddenByGround(const glm::dvec3& eye, const glm::dvec3& point, const scene::GroundHeightFn& ground, int samples = 32);
/// The highest ground looked for: Everest (8 849 m) three times exaggerated, and some.
inline constexpr double kGroundCeilingM = 30000.0;

/// The halo for a text colour (sRGB): near black around light text, near white around dark
/// text (by the text's relative luminance), opaque so that overlapping halos stay even.
glm::dvec4 haloColor(const glm::dvec3& textSrgb);

}  // namespace orbis::vector
