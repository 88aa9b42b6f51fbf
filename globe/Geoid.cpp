#include "globe/Geoid.h"

#include <ogr_spatialref.h>

#include <memory>

namespace orbis::globe {

GeoidHeightFn egm96Geoid() {
    auto msl = std::make_shared<OGRSpatialReference>();
    auto ellipsoidal = std::make_shared<OGRSpatialReference>();
    if (msl->SetFromUserInput("EPSG:4326+5773") != OGRERR_NONE || ellipsoidal->importFromEPSG(4979) != OGRERR_NONE) return {};
    msl->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    ellipsoidal->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    std::shared_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(msl.get(), ellipsoidal.get()));
    if (!t) return {};
    double x = 9.0, y = 46.0, z = 0.0;
    if (!t->Transform(1, &x, &y, &z) || z == 0.0) return {};   // no grid: PROJ would give 0
    return [t, msl, ellipsoidal](double lon, double lat) {
        double x = lon, y = lat, z = 0.0;
        return t->Transform(1, &x, &y, &z) ? z : 0.0;
    };
}

}  // namespace orbis::globe
