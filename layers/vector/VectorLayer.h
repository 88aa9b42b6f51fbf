#pragma once
// "vector": features from anything OGR opens (Shapefile, GeoPackage, GeoJSON, KML, GPX, CSV,
// FlatGeobuf, a WFS URL) on the globe, styled by rules on their attributes, shown on the
// scene's clock when they carry times.
//
//   {"type": "vector", "name": "Countries", "path": "countries.gpkg",
//    "layers": ["countries"], "where": "continent = 'Africa'",   or "sql": "SELECT ...",
//    "style": {...},                      (VectorStyle.h: defaults, rules, labels, extrusion)
//    "time": {"begin": "start_date", "end": "end_date"},   fields; default: KML's own times
//    "altitude": "clamped" | "relative" | "absolute", "extrusionScale": 1,
//    "opacity": 1, "maxLevel": 18, "simplifyPx": 0.5, "labels": true,
//    "paging": "auto" | true | false, "pageLevel": 12, "pageBudgetMB": 256,
//    "refresh": {"listen": "channel", "trigger": {"table": "t", "geometry": "geom"},
//                "everySeconds": 0, "glide": "auto" | seconds | false}}
//
// "altitude": "clamped" (the default): lines, points and flat polygons are painted into the
// terrain's tiles (VectorDrape) and lie exactly on the surface drawn, at every zoom. A scene
// needs a terrain layer for them to show. Lines and outlines are about `width` screen pixels
// wide (the tiles are painted for the size they are drawn at, within a factor of sqrt 2 either
// way as the terrain refines), points are disks of `iconSize` pixels or the style's PNG `icon`
// that high (IconCache), lines and outlines may be dashed; when a repaint (a pick, a rule, the
// time) makes a new drape, each tile's old image stays until its new one is in.
//
// Polygons whose style has "extrude" are buildings: walls and a flat roof in the fill colour,
// lit by the scene's sun, their base on the ground (FeatureMesh.h), drawn in the Opaque pass
// (MeshRenderer); "extrusionScale" (live) multiplies every height. "relative" and "absolute"
// put every feature at its own heights (Z above the ground, or above the ellipsoid in the
// terrain's datum): polygons as lit surfaces at their fillOpacity (extruded down to the ground,
// opaque, when the style extrudes them), lines as segments `width` pixels wide, points as disks of `iconSize` or their icon that high, hidden
// by whatever is nearer. The ground under their vertices is sampled and the meshes built on the
// worker pool (MeshGround, FeatureMesh); the renderer and each kind's pipeline are made only
// when there is something of that kind to draw.
//
// Labels: when the style gives a "label", the features' text is drawn over the scene in the
// Overlay pass (VectorLabels: real glyphs from DejaVu Sans with a halo, chosen so that none
// overlap and none flickers as the camera moves, none hidden by the globe or the terrain;
// LabelRenderer draws them). A point's label stands beside its icon, a polygon's at an interior
// point, a line's along the line at its middle, bent with it where it bends gently, where the
// line is long enough on screen
// (LabelAnchors.h). "labels": false (and the live setting "labels") hides them. A style
// without a label builds nothing for labels.
//
// The source is read on the worker pool when the layer is first shown; until then (and when
// reading fails: status() says why) nothing is drawn.
//
// Paging: a large source (more than 100 000 features with "paging": "auto", any with true) is
// not read whole. Its layers' metadata is read first (fields, counts, extent: the style is
// checked against the fields then); then each terrain tile's drape reads the feature tile
// (page) that holds its area, on the terrain's worker, through OGR's spatial filter, and pages
// stay within "pageBudgetMB", the least recently used going first (FeatureTiles). A click reads
// the features under the point. Labels come from the pages in memory: their labelled features,
// each once, gathered on the pool whenever pages come or go (labelledFeatures), with ids by
// fid so that the labels shown stay put. Features in 3-D (extruded, or at their altitude) are
// meshed a level-14 tile (about 1.2 km) at a time, each feature in the tile that holds its
// centre, for the tiles in view within the styles' range, nearest first within the budget.
//
// Live sources ("refresh"; the layer is paged): a PostgreSQL source names a channel to
// "listen" on; a trigger NOTIFYs it on each committed statement with the changed rows' box in
// WGS84 (PgListener: pgNotifyTriggerSql, which Orbis installs on "trigger"'s table when the
// scene asks, else the user runs it). Each box is taken in poll(): the pages in memory that
// it reaches are marked outdated (FeatureTiles::invalidate; the rest stay) and the drape tiles
// near it are painted again at once (drapeChangedSince: each tile's old image drawn until its
// new one is in), their painters reading those pages again; the mesh tiles it reaches are built
// again and the labels gathered again as the pages come in. "everySeconds" (and a change
// "anywhere") reads the pages in memory again on the pool first (FeatureTiles::refresh: any
// source, a file another program writes, a WFS) and paints again only where they changed. The listener runs on
// its own thread with its own connection, made only when the layer is first shown; a lost
// connection is in status() and opened again, then everything in memory is read again (what
// was notified meanwhile was lost). A page that cannot be read again keeps its old features;
// the refresh is tried again a second later. Tiles are read within the source's box read at the
// start; a notified box out of it grows it (a row inserted elsewhere, a vehicle driving out).
//
// Moving points (a vehicles table updated several times a second): drawn as 3-D markers
// ("relative" or "absolute"), each glides from where it is shown to its new place when the mesh
// of its tile comes in (MarkerMotion: "glide" "auto", over the time since that point last moved,
// at most 2 s; or a fixed number of seconds; false: they jump), on the GPU from the markers'
// `from` and the chunk's clock; their labels stand beside the markers as they move. Draped
// ("clamped") points are painted into the terrain's tiles: they move when those are painted
// again, at the feed's rate. Features in 3-D take their labels from the tiles their meshes were
// built from.

#include "base/ThreadPool.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/LayerSetting.h"
#include "engine/scene/SceneDesc.h"
#include "engine/render/RenderContext.h"
#include "layers/vector/FeatureMesh.h"
#include "layers/vector/FeaturePick.h"
#include "layers/vector/FeatureTiles.h"
#include "layers/vector/LabelAnchors.h"
#include "layers/vector/LabelBoard.h"
#include "layers/vector/MarkerMotion.h"
#include "layers/vector/PgListener.h"
#include "layers/vector/VectorContent.h"
#include "layers/vector/VectorDrape.h"
#include "layers/vector/VectorLabels.h"

#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace orbis::layers {

/// Whether a source is read whole or paged (FeatureTiles): "auto" pages a source of more than
/// `pageAbove` features when it is only draped.
enum class Paging { Auto, On, Off };

/// A source that changes while it is shown ("refresh" in the scene): the pages its changes
/// reach are read again and the tiles they paint are painted again; the rest stays.
struct RefreshSettings {
    /// PostgreSQL: the channel a trigger NOTIFYs with the changed box (PgListener); empty: none.
    std::string listen;
    /// Orbis installs its trigger on this table (and geometry column) when the layer starts.
    std::string triggerTable, triggerGeometry = "geom";
    /// Every so many seconds, the pages in memory are read again and those that changed are
    /// replaced (any source: a file written by another program, a WFS); 0: never.
    double everySeconds = 0.0;
    /// Points drawn as 3-D markers glide to their new places (MarkerMotion) over this many
    /// seconds; negative: "auto" (each point's own time between moves, at most 2 s); 0: they jump.
    double glideSeconds = -1.0;
    bool enabled() const { return !listen.empty() || everySeconds > 0.0; }
};

struct VectorLayerSettings {
    std::string name;
    vector::VectorContentOptions content;
    double opacity = 1.0;
    uint32_t maxLevel = 18;   ///< finest terrain tile level painted (~0.6 m pixels at 256)
    double simplifyPx = 0.5;  ///< the drape's simplification (DrapeTileOptions::simplifyPx)
    bool labels = true;       ///< draw the style's labels
    vector::AltitudeMode altitude = vector::AltitudeMode::Clamped;
    double extrusionScale = 1.0;   ///< multiplies extruded heights
    Paging paging = Paging::Auto;
    uint64_t pageAbove = 100'000;  ///< features: "auto" pages a larger source
    uint32_t pageLevel = 12;       ///< FeatureTilesOptions::pageLevel
    uint64_t pageBudgetBytes = 256ull << 20;
    RefreshSettings refresh;
};

class LabelRenderer;
class MeshRenderer;

class VectorLayer : public scene::Layer,
                    public scene::LiveSettings,
                    public scene::DrapedContent,
                    public scene::PickableContent,
                    public scene::LayerStats {
public:
    static scene::LayerType layerType();
    static constexpr scene::SettingRange kOpacityRange{0.0, 1.0};
    static constexpr scene::SettingRange kMaxLevelRange{0.0, 22.0};
    static constexpr scene::SettingRange kExtrusionScaleRange{0.0, 100.0};
    static constexpr scene::SettingRange kSimplifyRange{0.125, 64.0};

    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);

    explicit VectorLayer(VectorLayerSettings settings);
    ~VectorLayer() override;

    std::string_view type() const override { return "vector"; }
    scene::LiveSettings* asLiveSettings() override { return this; }
    const scene::DrapedContent* asDrapedContent() const override { return this; }
    scene::PickableContent* asPickable() override { return this; }
    const scene::LayerStats* asStats() const override { return this; }

    void poll() override;
    void update(const scene::FrameContext& frame) override;
    /// Draped content is drawn by the ground; the labels are the layer's own, in the Overlay
    /// pass, when there are any to draw.
    bool drawsIn(scene::Pass pass) const override;
    void recordTransfers(const render::RecordContext& context) override;
    void record(scene::Pass pass, const render::RecordContext& context) override;
    bool busy() const override {
        return loading_ || meshPending() || tileMeshesPending_ > 0 || tileMeshesChanged_ || refreshing_ || refreshQueued() ||
               !deferredRepaints_.empty() || (motion_ && motion_->moving(glideClock()));
    }
    std::string status() const override;

    // DrapedContent
    /// None when every feature is a mesh and no label is drawn: the terrain then paints nothing.
    std::shared_ptr<const globe::TileImageSource> drapeSource() const override { return drape_; }
    uint64_t drapeVersion() const override { return version_; }
    double drapeOpacity() const override { return settings_.opacity; }
    std::optional<std::vector<globe::GeoExtent>> drapeChangedSince(uint64_t version) const override;
    double drapeReach() const override;

    // PickableContent: the feature under a ground point, highlighted (painted again).
    std::optional<scene::PickedAttributes> pickAt(double lonDeg, double latDeg, double metresPerPixel) override;
    void clearPick() override;

    // LiveSettings: "opacity", "labels" (when the style gives a label), "extrusionScale" (when
    // there are meshes), "rule<i>" (a style rule on or off), and the drape's quality knobs
    // "maxLevel" and "simplifyPx" (`orbis bench --sweep`: error against run time).
    std::vector<scene::LayerSetting> liveSettings() const override;
    bool setParameter(std::string_view name, double value) override;

    // LayerStats
    uint64_t gpuBytes() const override;
    /// The features read, and the meshes (kept on the CPU after their upload).
    uint64_t cacheBytes() const override;
    uint64_t itemsDrawn() const override { return content_ ? content_->featureCount : pagedFeatures_; }

    /// What was read; null while loading, after an error, or when the source is paged.
    const vector::VectorContent* content() const { return content_.get(); }
    /// The pages of a paged source; null when it is read whole.
    const vector::FeatureTiles* pages() const { return pages_.get(); }
    const std::string& error() const { return error_; }
    /// A live source's listener (null unless the scene names a channel, before prepare).
    const vector::PgListener* listener() const { return listener_.get(); }
    /// Whether the scene names a channel to listen on (the listener is made when it is shown).
    bool hasListener() const { return !settings_.refresh.listen.empty(); }
    /// What it reads: a path, a URL, a connection string.
    const std::string& source() const { return settings_.content.read.source; }
    /// Changes applied so far (a refresh of the pages they reached, and their tiles painted again).
    uint64_t refreshesApplied() const { return refreshesApplied_; }
    /// The labels on the CPU (the last frame's candidates and placed boxes, timings); null when
    /// the style gives no label, before prepare, or when the fonts could not be read.
    const vector::VectorLabels* labels() const { return labels_ ? &*labels_ : nullptr; }
    /// Whether the label pipelines were made (only for a style that gives a label).
    bool hasLabelRenderer() const { return labelRenderer_ != nullptr; }
    /// The meshes drawn (extruded buildings, polygons at altitude); null before the first one.
    const vector::FeatureMesh* mesh() const { return mesh_.get(); }
    /// Whether the mesh pipeline was made (only when there is a mesh to draw).
    bool hasMeshRenderer() const { return meshRenderer_ != nullptr; }
    /// A live layer's moving points (null unless live, paged with meshes, and gliding).
    const vector::MarkerMotion* motion() const { return motion_.get(); }

private:
    /// What the worker reads: the content, and each feature's label anchor when labels are drawn.
    struct Loaded {
        std::shared_ptr<vector::VectorContent> content;
        std::shared_ptr<const vector::ContentAnchors> anchors;
        // Or a paged source: its pages, extent and feature count.
        std::shared_ptr<vector::FeatureTiles> pages;
        std::optional<vector::LonLatBounds> bounds;
        uint64_t features = 0;
    };
    /// A paged source's pager, when the settings and the source's size ask for one (the read's
    /// first step, on the pool); null: read it whole.
    static Result<Loaded> openPaged(const VectorLayerSettings& settings);
    /// Paged: the features near a ground point (for a click).
    std::optional<scene::PickedAttributes> pickPaged(const vector::PickQuery& query);

    void onPrepare(const render::RenderServices& services) override;
    /// A new drape for the current content, styles and time (and new meshes).
    void republish();
    /// The features drawn as meshes changed (new content or styles): build them again, on
    /// ground sampled again.
    void restartMeshes();
    /// Starts a mesh build when one is needed (the ground changed, the time, the scale).
    void updateMeshes(const scene::FrameContext& frame);
    /// Takes a finished build.
    void pollMeshes();
    bool meshPending() const { return meshLoading_ || meshStale_; }
    /// Gathers this frame's labels and submits them to the scene's shared board.
    void updateLabels(const scene::FrameContext& frame);
    bool drawingLabels() const { return labels_ && settings_.labels && (content_ || pages_); }
    /// The layer's name, or its source's when it has none (drapes, picked features).
    const std::string& displayName() const { return settings_.name.empty() ? settings_.content.read.source : settings_.name; }
    /// Paged: gathers the labelled features of the pages in memory again when they changed.
    void updatePagedLabels();
    void pollPagedLabels();
    /// Live sources: takes the changes received (and the polling clock's), reads again the
    /// pages they reach on the pool, and when that is done, paints again where they changed.
    void pollRefresh();
    bool refreshQueued() const { return refreshAnywhere_ || !refreshBoxes_.empty(); }
    /// The drape changed within `regions` only: a new version whose tiles there are painted again.
    void drapeChangedIn(std::vector<globe::GeoExtent> regions);
    /// A change applied: the drape's tiles and the mesh tiles the regions reach made again.
    void applyChanges(std::vector<globe::GeoExtent> regions);
    /// A change's box out of the source's box (pagedBounds_) grows it; true when it grew.
    bool growBounds(const vector::LonLatBounds& box);

    VectorLayerSettings settings_;
    jobs::Job<Result<Loaded>> job_;
    bool loading_ = false;
    std::string error_;
    std::shared_ptr<vector::VectorContent> content_;
    std::shared_ptr<const vector::ContentStyles> styles_;
    std::shared_ptr<const vector::VectorDrape> drape_;
    std::shared_ptr<vector::IconCache> icons_;   ///< the points' icons, read by the drape's painters
    uint64_t version_ = 0;
    TimeNs time_ = 0;
    uint64_t shownSignature_ = 0;
    std::optional<vector::DrapeFeature> highlight_;   ///< the picked feature
    std::shared_ptr<vector::FeatureTiles> pages_;
    // Paged meshes (a paged source with features in 3-D): the tiles of kMeshLevel near the view,
    // each read (its features whole) and meshed on the pool, kept within the budget nearest
    // first, drawn together; a generation for the settings they were built with.
    static constexpr uint32_t kMeshLevel = 14;
    /// Meshes up to this size are gathered and uploaded again as each tile comes in.
    static constexpr uint64_t kComposeAtOnceBytes = 1u << 20;
    struct TileMesh {
        std::shared_ptr<vector::FeatureMesh> mesh;
        uint64_t generation = 0;
        uint64_t lastWanted = 0;
        bool arrived = false;   ///< drawn once: its markers' glides are set (motion_)
        /// The features it was built from: the labels of features drawn in 3-D come from these.
        std::shared_ptr<const vector::FeatureTile> page;
    };
    struct TileMeshBuild {
        globe::TileKey key;
        uint64_t generation = 0;
        std::shared_ptr<vector::FeatureMesh> mesh;
        std::shared_ptr<const vector::FeatureTile> page;
        bool drapes = false;   ///< the tile has a feature to paint on the terrain
        uint64_t refreshes = 0;   ///< refreshesApplied_ when it started
    };
    void updatePagedMeshes(const scene::FrameContext& frame);
    void pollPagedMeshes();
    /// The tiles of kMeshLevel the view wants meshes of, nearest first.
    std::vector<globe::TileKey> wantedMeshTiles(const scene::FrameContext& frame) const;
    bool pagedMeshes_ = false;
    std::map<globe::TileKey, TileMesh> tileMeshes_;
    std::vector<jobs::Job<TileMeshBuild>> tileJobs_;
    std::vector<globe::TileKey> tileJobKeys_;
    uint64_t tileMeshGeneration_ = 1, meshFrame_ = 0;
    /// Tiles whose build failed, with the generation it was for: not tried again for it.
    std::map<globe::TileKey, uint64_t> failedTiles_;
    /// The tiles of the mesh drawn now, in the order gathered.
    std::vector<globe::TileKey> composedTiles_;
    size_t tileMeshesPending_ = 0;   ///< wanted tiles without a mesh of this generation
    bool tileMeshesChanged_ = false;
    /// Paged with meshes: whether a feature to paint on the terrain was met. Until then no
    /// drape is published (an empty drape still makes the terrain refine to its finest level).
    bool pagedDrapes_ = false;
    /// Live and paged with meshes: the moving points' glides (none with "glide": 0).
    std::unique_ptr<vector::MarkerMotion> motion_;
    /// Now on the glides' clock (steady_clock, seconds).
    static double glideClock();
    // Paged labels: the gathering on the pool, the pages' changes it saw, a restyle to redo.
    jobs::Job<Loaded> pagedLabelJob_;
    bool pagedLabelLoading_ = false, pagedLabelsStale_ = false;
    uint64_t pagedLabelChanges_ = ~0ull;
    /// Counts the meshes composed (their pages hold the labels of features in 3-D), and the
    /// count the labels were last gathered at.
    uint64_t meshesComposed_ = 0, pagedLabelComposed_ = ~0ull;
    std::optional<vector::LonLatBounds> pagedBounds_;
    uint64_t pagedFeatures_ = 0;
    // Live sources (RefreshSettings): the listener, the changes not yet applied, the refresh
    // running on the pool, where each drape version changed (nothing: anywhere; the last few).
    std::unique_ptr<vector::PgListener> listener_;
    std::vector<vector::LonLatBounds> refreshBoxes_;
    bool refreshAnywhere_ = false, refreshing_ = false;
    std::vector<vector::LonLatBounds> refreshingBoxes_;
    jobs::Job<vector::PageRefresh> refreshJob_;
    std::chrono::steady_clock::time_point nextPoll_{};
    /// A refresh whose reads failed is tried again at this time, for these boxes (none: anywhere).
    std::optional<std::chrono::steady_clock::time_point> retryRefreshAt_;
    std::vector<vector::LonLatBounds> retryBoxes_;
    /// Pages that invalidate left outdated a while (slow to read): painted again then.
    std::vector<vector::DeferredRead> deferredRepaints_;
    uint64_t refreshesApplied_ = 0;
    std::string refreshError_;
    std::deque<std::pair<uint64_t, std::optional<std::vector<globe::GeoExtent>>>> drapeChanges_;
    /// Mesh tiles a change reached (the refresh count then): a build started before is redone.
    std::map<globe::TileKey, uint64_t> meshTileChanged_;
    std::shared_ptr<const vector::ContentAnchors> anchors_;
    std::optional<vector::VectorLabels> labels_;
    std::unique_ptr<LabelRenderer> labelRenderer_;
    /// This layer's board, and the one its labels are placed on this frame: the board of the
    /// first visible vector layer with labels (the frame's drapes list them in scene order).
    std::shared_ptr<vector::LabelBoard> ownBoard_, board_;
    std::string labelError_;

    // Meshes: the features drawn as meshes, the ground under their vertices (sampled on the
    // pool by the first build, kept until the ground or the features change), the build, the
    // renderer.
    struct MeshBuild {
        std::shared_ptr<const vector::MeshGround> ground;
        std::shared_ptr<const vector::FeatureMesh> mesh;
        uint64_t generation = 0;   ///< the features and ground it was built for
    };
    render::RenderServices services_;
    size_t meshFeatures_ = 0;
    uint64_t meshGeneration_ = 0;   ///< counts changes of the mesh features or their ground
    std::shared_ptr<const vector::MeshGround> ground_;
    /// styles_ with the features drawn as meshes hidden: what the drape paints.
    std::shared_ptr<const vector::ContentStyles> drapeStyles_;
    bool drapesSomething_ = true;
    uint64_t groundVersion_ = 0;
    bool meshStale_ = false;     ///< a build is needed
    bool meshLoading_ = false;
    jobs::Job<MeshBuild> meshJob_;
    std::shared_ptr<const vector::FeatureMesh> mesh_;
    std::unique_ptr<MeshRenderer> meshRenderer_;
};

}  // namespace orbis::layers
