#include "layers/analysis/ViewshedDrape.h"

#include "base/ThreadPool.h"

#include <cmath>

namespace orbis::layers {

ViewshedDrape::ViewshedDrape(std::string name, std::shared_ptr<const globe::ViewshedGrid> grid, std::shared_ptr<const globe::Viewshed> viewshed,
                             ViewshedColors colors)
    : name_(std::move(name)), grid_(std::move(grid)), viewshed_(std::move(viewshed)), colors_(colors), plane_(*grid_) {
    const globe::GeoExtentLonLat b = plane_.bounds(*grid_);
    bounds_ = {b.west, b.south, b.east, b.north};
}

uint32_t ViewshedDrape::maxLevel(int tileSize) const {
    // Finest level whose pixels are still about as large as a cell (at the grid's latitude).
    const double metresPerDeg = 111320.0 * std::max(0.05, std::cos(grid_->centre.y * M_PI / 180.0));
    uint32_t level = 0;
    while (level < 22 && 180.0 / double(1u << level) / tileSize * metresPerDeg > 0.5 * grid_->cellM) ++level;
    return level;
}

bool ViewshedDrape::covers(const globe::GeoExtent& extent) const { return bounds_.meetsWithTurns(extent); }

Result<globe::ImageryTile> ViewshedDrape::readTile(const globe::TileImageRequest& request, const jobs::CancelToken* cancel) const {
    globe::ImageryTile tile;
    const int n = std::max(1, request.size);
    tile.size = n;
    tile.rgba.assign(size_t(n) * size_t(n) * 4, 0);
    if (!covers(request.extent)) return tile;
    const double dx = request.extent.width() / n, dy = request.extent.height() / n;
    for (int row = 0; row < n; ++row) {
        if (cancel && (row & 15) == 0 && cancel->cancelled()) return makeError("cancelled");
        const double lat = request.extent.north - (row + 0.5) * dy;
        for (int col = 0; col < n; ++col) {
            const auto cell = plane_.cellOf(request.extent.west + (col + 0.5) * dx, lat);
            if (!cell) continue;
            const globe::Sight s = viewshed_->at(cell->first, cell->second);
            if (s != globe::Sight::Visible && s != globe::Sight::Hidden) continue;
            const auto& c = s == globe::Sight::Visible ? colors_.seen : colors_.hidden;
            std::copy(c.begin(), c.end(), tile.rgba.begin() + (ptrdiff_t(row) * n + col) * 4);
            tile.anyValid = true;
        }
    }
    return tile;
}

}  // namespace orbis::layers
