#pragma once
// A viewshed painted on the terrain's tiles (a TileImageSource the ground drapes): each tile
// pixel takes the colour of the grid cell under it, seen or hidden; out of range and no data stay
// clear. Immutable: a new viewshed is a new drape. No Vulkan.

#include "globe/TileImageSource.h"
#include "globe/Viewshed.h"

#include <array>
#include <memory>
#include <string>

namespace orbis::layers {

struct ViewshedColors {
    std::array<uint8_t, 4> seen{70, 230, 90, 150};     ///< sRGB, straight alpha
    std::array<uint8_t, 4> hidden{230, 50, 40, 120};
};

class ViewshedDrape : public globe::TileImageSource {
public:
    ViewshedDrape(std::string name, std::shared_ptr<const globe::ViewshedGrid> grid, std::shared_ptr<const globe::Viewshed> viewshed,
                  ViewshedColors colors);

    const std::string& name() const override { return name_; }
    uint32_t maxLevel(int tileSize) const override;
    uint32_t minLevel() const override { return 0; }
    bool covers(const globe::GeoExtent& extent) const override;
    Result<globe::ImageryTile> readTile(const globe::TileImageRequest& request, const jobs::CancelToken* cancel) const override;

    /// The box the drape paints in (longitudes continuous from the grid's centre).
    globe::GeoExtent bounds() const { return bounds_; }

private:
    std::string name_;
    std::shared_ptr<const globe::ViewshedGrid> grid_;
    std::shared_ptr<const globe::Viewshed> viewshed_;
    ViewshedColors colors_;
    globe::ViewshedPlane plane_;
    globe::GeoExtent bounds_;
};

}  // namespace orbis::layers
