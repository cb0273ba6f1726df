// Decodes geo-tz's quadtree tiles into one GeoJSON layer: one feature per
// polygon, property tzid; covered cells become rectangles.
const fs = require('fs');
const path = require('path');
const Pbf = require('pbf').default || require('pbf');
const geobuf = require('geobuf');
const dir = process.argv[2], out = process.argv[3];
const index = JSON.parse(fs.readFileSync(path.join(dir, 'timezones-now.geojson.index.json')));
const dat = fs.readFileSync(path.join(dir, 'timezones-now.geojson.geo.dat'));
const w = fs.createWriteStream(out);
w.write('{"type":"FeatureCollection","features":[\n');
let first = true, n = 0;
function emit(tzid, geometry) {
  w.write((first ? '' : ',\n') + JSON.stringify({type: 'Feature', properties: {tzid}, geometry}));
  first = false; n++;
}
function walk(node, q) {
  for (const key of ['a', 'b', 'c', 'd']) {
    const c = node[key];
    if (!c) continue;
    const b = {...q};
    if (key === 'a') { b.bottom = q.midLat; b.left = q.midLon; }
    else if (key === 'b') { b.bottom = q.midLat; b.right = q.midLon; }
    else if (key === 'c') { b.top = q.midLat; b.right = q.midLon; }
    else { b.top = q.midLat; b.left = q.midLon; }
    if (c.pos >= 0 && c.len) {
      const gj = geobuf.decode(new Pbf(dat.subarray(c.pos, c.pos + c.len)));
      for (const f of gj.features)
        emit(f.properties.tzid, f.geometry);
    } else if (Array.isArray(c)) {
      for (const i of c) emit(index.timezones[i], {type: 'Polygon', coordinates: [[[b.left, b.bottom],
        [b.right, b.bottom], [b.right, b.top], [b.left, b.top], [b.left, b.bottom]]]});
    } else if (typeof c === 'object') {
      walk(c, {...b, midLat: (b.top + b.bottom) / 2, midLon: (b.left + b.right) / 2});
    }
  }
}
walk(index.lookup, {top: 89.9999, bottom: -89.9999, left: -179.9999, right: 179.9999, midLat: 0, midLon: 0});
w.write('\n]}\n');
w.end(() => console.error(`${n} features`));
