D<?xml version="1.0" encoding="utf-8" ?>
<ogr:FeatureCollection xmlns:ogr="http://ogr.maptools.org/" xmlns:gml="http://www.opengis.net/gml">
<gml:featureMember><ogr:roads><ogr:geometryProperty><gml:LineString srsName="EPSG:4326"><gml:coordinates>46,9 46.1,9.1</gml:coordinates></gml:LineString></ogr:geometryProperty><ogr:name>A</ogr:name></ogr:roads></gml:featureMember>
</ogr:FeatureCollection>
