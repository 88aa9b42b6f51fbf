"""The demo server's processes (PyWPS 4.5 on GDAL's Python bindings), over the DEM named by
$ORBIS_WPS_DEM:

  terrain   slope, aspect or hillshade of the DEM in an area (a GeoTIFF by reference)
  viewshed  what an observer sees around a point, gdal_viewshed's algorithm (a GeoTIFF)
  profile   the ground along a path (GeoJSON line) every N metres (a CSV table, inline)
  zonal     statistics of the DEM inside polygons (GeoJSON in, GeoJSON out)
  sleep     a long task that reports its progress (for asynchronous jobs and cancelling)
"""

import json
import math
import os
import time

from osgeo import gdal, ogr, osr
from pywps import (BoundingBoxInput, ComplexInput, ComplexOutput, Format, LiteralInput, LiteralOutput, Process)
from pywps.app.Common import Metadata  # noqa: F401  (kept for processes that add metadata)
from pywps.inout.literaltypes import AllowedValue
from pywps.validator.mode import MODE

gdal.UseExceptions()

GEOTIFF = Format("image/tiff; subtype=geotiff", extension=".tif")
GEOJSON = Format("application/geo+json", extension=".geojson")
CSV = Format("text/csv", extension=".csv")


def dem_path():
    return os.environ["ORBIS_WPS_DEM"]


def fail(message):
    from pywps.app.exceptions import ProcessError
    raise ProcessError(message)


def crop(bbox, workdir, name):
    """The DEM warped into EPSG:4326 over bbox [w, s, e, n]; the path of the crop."""
    w, s, e, n = bbox
    if not (w < e and s < n):
        fail("the area is empty: its west must be less than its east, its south less than its north")
    out = os.path.join(workdir, name)
    try:
        gdal.Warp(out, dem_path(), dstSRS="EPSG:4326", outputBounds=(w, s, e, n), resampleAlg="bilinear",
                  dstNodata=-32768, format="GTiff")
    except RuntimeError as err:
        fail(f"the area cannot be read from the DEM: {err}")
    ds = gdal.Open(out)
    band = ds.GetRasterBand(1)
    stats = band.ComputeRasterMinMax(False) if band.GetNoDataValue() is None else None
    if ds.RasterXSize * ds.RasterYSize == 0 or (stats is not None and math.isnan(stats[0])):
        fail("the area is outside the DEM")
    return out


class Terrain(Process):
    def __init__(self):
        super().__init__(
            self._handler, identifier="terrain", version="1.0", title="Slope, aspect or hillshade of the DEM in an area",
            abstract="gdaldem on the DEM cropped to the area (EPSG:4326); slope in degrees",
            inputs=[BoundingBoxInput("area", "Area", crss=["epsg:4326"], min_occurs=1),
                    LiteralInput("product", "Product", data_type="string", allowed_values=["slope", "aspect", "hillshade"],
                                 default="slope", min_occurs=0),
                    LiteralInput("azimuth", "Sun azimuth for the hillshade (degrees)", data_type="float",
                                 allowed_values=[AllowedValue(minval=0, maxval=360)], default=315, min_occurs=0)],
            outputs=[ComplexOutput("raster", "The product", supported_formats=[GEOTIFF], as_reference=True)],
            store_supported=True, status_supported=True)

    def _handler(self, request, response):
        bbox = [float(v) for v in request.inputs["area"][0].data]
        product = request.inputs["product"][0].data if "product" in request.inputs else "slope"
        azimuth = float(request.inputs["azimuth"][0].data) if "azimuth" in request.inputs else 315.0
        response.update_status("cropping the DEM", 10)
        src = crop(bbox, self.workdir, "crop.tif")
        out = os.path.join(self.workdir, f"{product}.tif")
        # Geographic pixels: metres per degree of latitude as the scale.
        options = {"scale": 111120.0, "computeEdges": True}
        if product == "hillshade":
            options["azimuth"] = azimuth
        response.update_status(f"computing the {product}", 50)
        gdal.DEMProcessing(out, src, product, **options)
        response.outputs["raster"].file = out
        return response


class Viewshed(Process):
    def __init__(self):
        super().__init__(
            self._handler, identifier="viewshed", version="1.0", title="What an observer sees around a point",
            abstract="gdal_viewshed's algorithm on the DEM in a plane centred on the observer (255 seen, 0 hidden)",
            inputs=[LiteralInput("lon", "Observer longitude", data_type="float", allowed_values=[AllowedValue(minval=-180, maxval=180)]),
                    LiteralInput("lat", "Observer latitude", data_type="float", allowed_values=[AllowedValue(minval=-90, maxval=90)]),
                    LiteralInput("height", "Eye above the ground (m)", data_type="float",
                                 allowed_values=[AllowedValue(minval=0, maxval=10000)], default=2, min_occurs=0),
                    LiteralInput("radius", "Radius (m)", data_type="float", allowed_values=[AllowedValue(minval=10, maxval=50000)],
                                 default=2000, min_occurs=0)],
            outputs=[ComplexOutput("visibility", "Visibility", supported_formats=[GEOTIFF], as_reference=True),
                     LiteralOutput("seen", "Share of the ground in range that is seen (%)", data_type="float")],
            store_supported=True, status_supported=True)

    def _handler(self, request, response):
        lon, lat = float(request.inputs["lon"][0].data), float(request.inputs["lat"][0].data)
        height = float(request.inputs["height"][0].data) if "height" in request.inputs else 2.0
        radius = float(request.inputs["radius"][0].data) if "radius" in request.inputs else 2000.0
        plane = osr.SpatialReference()
        plane.ImportFromProj4(f"+proj=aeqd +lat_0={lat} +lon_0={lon} +datum=WGS84 +units=m")
        local = os.path.join(self.workdir, "local.tif")
        response.update_status("warping the DEM around the observer", 20)
        gdal.Warp(local, dem_path(), dstSRS=plane.ExportToWkt(), outputBounds=(-radius, -radius, radius, radius),
                  xRes=max(1.0, radius / 500.0), yRes=max(1.0, radius / 500.0), resampleAlg="bilinear", dstNodata=-32768)
        src = gdal.Open(local)
        band = src.GetRasterBand(1)
        centre = band.ReadAsArray(src.RasterXSize // 2, src.RasterYSize // 2, 1, 1)[0][0]
        if centre == -32768:
            fail("the observer is outside the DEM")
        out = os.path.join(self.workdir, "viewshed.tif")
        response.update_status("computing the viewshed", 60)
        vs = gdal.ViewshedGenerate(band, "GTiff", out, [], 0.0, 0.0, height, 0.0, 255, 0, 1, -1, 0.85714, gdal.GVM_Edge, radius)
        data = vs.GetRasterBand(1).ReadAsArray()
        seen, hidden = int((data == 255).sum()), int((data == 0).sum())
        vs = None
        response.outputs["visibility"].file = out
        response.outputs["seen"].data = 100.0 * seen / max(1, seen + hidden)
        return response


def sample(ds, lon, lat):
    gt = ds.GetGeoTransform()
    px, py = (lon - gt[0]) / gt[1], (lat - gt[3]) / gt[5]
    if px < 0 or py < 0 or px >= ds.RasterXSize or py >= ds.RasterYSize:
        return None
    v = ds.GetRasterBand(1).ReadAsArray(int(px), int(py), 1, 1)[0][0]
    nodata = ds.GetRasterBand(1).GetNoDataValue()
    return None if nodata is not None and v == nodata else float(v)


class Profile(Process):
    def __init__(self):
        super().__init__(
            self._handler, identifier="profile", version="1.0", title="The ground along a path",
            abstract="The DEM every step metres along a GeoJSON line (EPSG:4326): distance, lon, lat, height",
            inputs=[ComplexInput("path", "Path (GeoJSON LineString)", supported_formats=[GEOJSON], mode=MODE.NONE),
                    LiteralInput("step", "Step (m)", data_type="float", allowed_values=[AllowedValue(minval=1, maxval=100000)],
                                 default=100, min_occurs=0)],
            outputs=[ComplexOutput("table", "Profile table", supported_formats=[CSV], as_reference=False)],
            store_supported=True, status_supported=True)

    def _handler(self, request, response):
        try:
            doc = json.loads(request.inputs["path"][0].data)
        except ValueError as err:
            fail(f"the path is not JSON: {err}")
        geom = doc.get("geometry", doc) if isinstance(doc, dict) else None
        if doc.get("type") == "FeatureCollection" and doc.get("features"):
            geom = doc["features"][0].get("geometry")
        if not geom or geom.get("type") != "LineString" or len(geom.get("coordinates", [])) < 2:
            fail("the path must be a GeoJSON LineString of two points at least")
        step = float(request.inputs["step"][0].data) if "step" in request.inputs else 100.0
        ds = gdal.Warp("", dem_path(), format="VRT", dstSRS="EPSG:4326")
        geod = osr.SpatialReference()
        geod.ImportFromEPSG(4326)
        rows, along = ["distance_m,lon,lat,height_m"], 0.0
        pts = geom["coordinates"]
        for (x0, y0, *_), (x1, y1, *_) in zip(pts, pts[1:]):
            # Metres per degree on a sphere: enough for the demo's short paths.
            dx = (x1 - x0) * 111320.0 * math.cos(math.radians((y0 + y1) / 2))
            dy = (y1 - y0) * 110540.0
            length = math.hypot(dx, dy)
            n = max(1, int(math.ceil(length / step)))
            for i in range(n):
                t = i / n
                lon, lat = x0 + t * (x1 - x0), y0 + t * (y1 - y0)
                h = sample(ds, lon, lat)
                rows.append(f"{along + t * length:.1f},{lon:.7f},{lat:.7f},{'' if h is None else f'{h:.2f}'}")
                if len(rows) > 100000:
                    fail("the profile would have more than 100000 samples: use a longer step")
            along += length
        h = sample(ds, pts[-1][0], pts[-1][1])
        rows.append(f"{along:.1f},{pts[-1][0]:.7f},{pts[-1][1]:.7f},{'' if h is None else f'{h:.2f}'}")
        response.outputs["table"].data = "\n".join(rows) + "\n"
        return response


class Zonal(Process):
    def __init__(self):
        super().__init__(
            self._handler, identifier="zonal", version="1.0", title="Statistics of the DEM inside polygons",
            abstract="Each polygon of a GeoJSON collection (EPSG:4326) with the count, minimum, mean and maximum of the DEM inside it",
            inputs=[ComplexInput("zones", "Polygons (GeoJSON)", supported_formats=[GEOJSON], mode=MODE.NONE)],
            outputs=[ComplexOutput("zones", "Polygons with statistics", supported_formats=[GEOJSON], as_reference=True)],
            store_supported=True, status_supported=True)

    def _handler(self, request, response):
        src = os.path.join(self.workdir, "zones.geojson")
        with open(src, "w") as f:
            f.write(request.inputs["zones"][0].data)
        vec = gdal.OpenEx(src, gdal.OF_VECTOR)
        if vec is None or vec.GetLayerCount() == 0:
            fail("the zones are not a GeoJSON collection")
        layer = vec.GetLayer(0)
        dem = gdal.Warp("", dem_path(), format="VRT", dstSRS="EPSG:4326")
        band = dem.GetRasterBand(1)
        nodata = band.GetNoDataValue()
        data = band.ReadAsArray().astype("float64")
        gt = dem.GetGeoTransform()
        out_features = []
        for i, feature in enumerate(layer):
            geom = feature.GetGeometryRef()
            if geom is None:
                continue
            mask_ds = gdal.GetDriverByName("MEM").Create("", dem.RasterXSize, dem.RasterYSize, 1, gdal.GDT_Byte)
            mask_ds.SetGeoTransform(gt)
            mask_ds.SetProjection(dem.GetProjection())
            mem = ogr.GetDriverByName("Memory").CreateDataSource("")
            lyr = mem.CreateLayer("z", srs=layer.GetSpatialRef())
            f = ogr.Feature(lyr.GetLayerDefn())
            f.SetGeometry(geom.Clone())
            lyr.CreateFeature(f)
            gdal.RasterizeLayer(mask_ds, [1], lyr, burn_values=[1])
            inside = mask_ds.GetRasterBand(1).ReadAsArray() == 1
            values = data[inside]
            if nodata is not None:
                values = values[values != nodata]
            props = json.loads(feature.ExportToJson())["properties"] or {}
            props.update({"count": int(values.size),
                          "min": float(values.min()) if values.size else None,
                          "mean": float(values.mean()) if values.size else None,
                          "max": float(values.max()) if values.size else None})
            out_features.append({"type": "Feature", "properties": props, "geometry": json.loads(geom.ExportToJson())})
            response.update_status(f"zone {i + 1}", min(95, 10 + i))
        out = os.path.join(self.workdir, "zones-stats.geojson")
        with open(out, "w") as f:
            json.dump({"type": "FeatureCollection", "features": out_features}, f)
        response.outputs["zones"].file = out
        return response


class Sleep(Process):
    def __init__(self):
        super().__init__(
            self._handler, identifier="sleep", version="1.0", title="A long task",
            abstract="Waits, reporting its progress ten times a second",
            inputs=[LiteralInput("seconds", "Seconds", data_type="float", allowed_values=[AllowedValue(minval=0.1, maxval=600)],
                                 default=5, min_occurs=0)],
            outputs=[LiteralOutput("slept", "Seconds slept", data_type="float")],
            store_supported=True, status_supported=True)

    def _handler(self, request, response):
        seconds = float(request.inputs["seconds"][0].data) if "seconds" in request.inputs else 5.0
        start = time.time()
        while time.time() - start < seconds:
            time.sleep(0.1)
            response.update_status("sleeping", int(100 * (time.time() - start) / seconds))
        response.outputs["slept"].data = time.time() - start
        return response


def all_processes():
    return [Terrain(), Viewshed(), Profile(), Zonal(), Sleep()]
