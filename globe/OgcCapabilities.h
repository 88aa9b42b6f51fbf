#pragma once
// What an OGC server offers, from its GetCapabilities documents (WMS 1.1.1/1.3.0, WMTS 1.0, WFS
// 1.1/2.0): each layer or feature type with its title, styles, CRSs, extent in WGS84 and time
// dimension (WMTS: also its formats and tile matrix sets),
// as JSON for `orbis info URL`. The XML is parsed with GDAL's CPLParseXMLString, namespaces
// stripped; an OGC exception report is an error that quotes it. No Vulkan.

#include "base/Result.h"

#include <string>
#include <string_view>

namespace orbis::globe {

enum class OgcService { Wms, Wmts, Wfs };

/// The JSON (text) of one capabilities document: {"service", "version", "title", "layers": [{
/// "name", "title", "styles", "crs", "wgs84Bounds": [w, s, e, n], "time"; WMTS also "formats" and
/// "tileMatrixSets"}]}. Errors: not XML,
/// an exception report (its text), not a capabilities document of `service`. `source` names it
/// in messages (the URL, without secrets).
Result<std::string> parseOgcCapabilities(std::string_view xml, OgcService service, const std::string& source);

/// Fetches and parses the three services' capabilities at `url` ("http(s)://host/path?", with or
/// without "WMS:"/"WMTS:"/"WFS:" before it; a SERVICE= in it keeps to that service), through GDAL's HTTP
/// (its timeouts, GDAL_HTTP_AUTH / GDAL_HTTP_USERPWD / GDAL_HTTP_HEADERS from the environment).
/// JSON: {"kind": "ogc-services", "url", "wms": {...} or "wmsError", "wmts": ... or "wmtsError",
/// "wfs": ... or "wfsError"}.
/// An error when neither answers.
Result<std::string> describeOgcServices(const std::string& url);

}  // namespace orbis::globe
