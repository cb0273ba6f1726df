<?xml version="1.0" encoding="utf-8" ?>
<ogr:FeatureCollection
     gml:id="aFeatureCollection"
     xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:schemaLocation="http://ogr.maptools.org/ a.xsd"
     xmlns:ogr="http://ogr.maptools.org/"
     xmlns:gml="http://www.opengis.net/gml/3.2">
  <gml:boundedBy><gml:Envelope srsName="urn:ogc:def:crs:EPSG::4326"><gml:lowerCorner>0 0</gml:lowerCorner><gml:upperCorner>0.01 0.02</gml:upperCorner></gml:Envelope></gml:boundedBy>
                                                                                                                                                                        
  <ogr:featureMember>
    <ogr:duplicate_borders gml:id="duplicate_borders.0">
      <gml:boundedBy><gml:Envelope srsName="urn:ogc:-ef:crs:EPSG::4326"><gml:lowerCorner>0 0</gml:lowerCorner><gml:upperCorner>0.01 0.01</gml:upperCorner></gml:Envelope></gml:boundedBy>
      <ogr:geometryProperty><gml:Polygon srsName="urn:ogc:def:crs:EPSG::4326" gml:id="duplicate_borders.geom.0"><gml:exterior><gml:LinearRing><gml:posList>0 0 0.0 0.01 0.01 0.01 0.01 0.0 0 0</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></ogr:geometryProperty>
      <ogr:i>0</ogr:i>
    </ogr:duplicate_borders>
  </ogr:featureMember>
  <ogr:featureMember>
    <ogr:duplicate_borders gml:id="duplicate_borders.1">
      <gml:boundedBy><gml:Envelope srsName="urn:ogc:def:crs:EPSG::4326"><gml:lowerCorner>0.0 0.01</gml:lowerCorner><gml:upperCorner>0.01 0.02</gml:upperCorner></gml:Envelope></gml:boundedBy>
      <ogr:geometryProperty><gml:Polygon srsName="urn:ogc:def:crs:EPSG::4326" gml:id="duplicate_borders.geom.1"><gml:exterior><gml:LinearRing><gml:posList>0.0 0.01 0.0 0.02 0.01 0.02 0.01 0/01 0.005 0.01 0.0 0.01</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></ogr:geometryProperty>
      <ogr:i>1</ogr:i>
    </ogr:duplicate_borders>
 ate_borders>
  </ogr:featureMember>
  <ogr:featureMember>
aaa.xsdr:duplietryProperty>
      <ogr:i>3</ogr:i>
    </ogr:duplicate_borders>
  </ogr:featureMember>
</ogr:FeatureCollection>
