#pragma once
// GDAL's side of the viewshed: its own algorithm (GDALViewshedGenerate, what gdal_viewshed
// runs) on a viewshed grid, to compare against, and GeoTIFF files of a grid and of a viewshed in
// the grid's plane (an azimuthal equidistant CRS centred on the grid: within a cell of the
// tangent plane for the radii a viewshed uses), so that the gdal_viewshed program can be run on
// exactly the heights Orbis used.

#include "base/Result.h"
#include "globe/Viewshed.h"

#include <string>

namespace orbis::globe {

/// GDALViewshedGenerate on `grid` (in memory, "edge" cell mode, the options' curvature and
/// radius); NaN heights are not supported by GDAL and are refused. `seconds`: the time GDAL took.
Result<Viewshed> viewshedGdal(const ViewshedGrid& grid, const ViewshedOptions& options, double* seconds = nullptr);

/// The PROJ string of the grid's plane.
std::string viewshedGridProj(const ViewshedGrid& grid);

/// The heights as a Float32 GeoTIFF (NaN: the nodata value).
Result<void> writeViewshedGridTiff(const ViewshedGrid& grid, const std::string& path);
/// The viewshed as a Byte GeoTIFF: 255 seen, 0 hidden, 1 out of range, 2 no data (the nodata value).
Result<void> writeViewshedTiff(const ViewshedGrid& grid, const Viewshed& viewshed, const std::string& path);

}  // namespace orbis::globe
