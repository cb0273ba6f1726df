// geo-tz's own lookup on the points bench/run-geotz.sh drew: the peer of
// hpfc's batch location on the same map.
//   node bench/geotz_find.js NODE_MODULES POINTS.f64 ANSWERS.jsonl
// POINTS.f64: n longitudes then n latitudes, native doubles. Loads the
// whole map first (preCache, geo-tz's fastest mode), answers every point
// once to warm up, then times a second pass; writes each point's zones
// (a JSON array a line) and prints the per-point time and the resident
// memory as JSON.
const fs = require('fs');
const path = require('path');
const [nodeModules, pointsPath, answersPath] = process.argv.slice(2);
const geoTz = require(path.join(nodeModules, 'geo-tz', 'dist', 'find-now.js'));
const buf = fs.readFileSync(pointsPath);
const xy = new Float64Array(buf.buffer, buf.byteOffset, buf.length / 8);
const n = xy.length / 2;
let t0 = process.hrtime.bigint();
geoTz.preCache();
const loadSeconds = Number(process.hrtime.bigint() - t0) / 1e9;
const answers = new Array(n);
for (let i = 0; i < n; i++)
  answers[i] = geoTz.find(xy[n + i], xy[i]);
t0 = process.hrtime.bigint();
let count = 0;
for (let i = 0; i < n; i++)
  count += geoTz.find(xy[n + i], xy[i]).length;
const seconds = Number(process.hrtime.bigint() - t0) / 1e9;
fs.writeFileSync(answersPath, answers.map((a) => JSON.stringify(a)).join('\n') + '\n');
console.log(JSON.stringify({points: n, load_seconds: loadSeconds, seconds,
  us_per_point: seconds / n * 1e6, rss_mib: process.memoryUsage().rss / 1048576, zones: count}));
