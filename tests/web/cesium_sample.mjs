// Loads a quantized-mesh pyramid in CesiumJS, in Debian's headless Chromium driven by
// playwright-core, as a web page would: samples the terrain at the points given and takes a
// screenshot of it. Everything comes from two static servers on localhost, on two origins as on
// a real site: the page and CesiumJS (tests/web/node_modules/cesium/Build/Cesium) on one, the
// pyramid on the other, served as docs/web_terrain.md says (Content-Type
// application/vnd.quantized-mesh, Access-Control-Allow-Origin; with --gzip, Content-Encoding:
// gzip), so the browser's CORS checks apply. Every request to any other address is refused and
// reported: no Ion token, no imagery, no geocoder.
//
// Usage: node cesium_sample.mjs --modules NODE_MODULES --terrain DIR [--screenshot OUT.png]
//          [--size WIDTHxHEIGHT] [--gzip] [--chromium PATH] [--options JSON] LON,LAT ...
// --options: the options of CesiumTerrainProvider.fromUrl (default {}, Cesium's own defaults:
// requestMetadata true, requestVertexNormals false).
// Prints one JSON object: "heights" (metres, one a point, null where Cesium found none),
// "levels" (the level Cesium sampled each point at), "tiles" (tile requests served), "gzipped"
// (of them, sent gzipped), "preflights" (CORS preflight requests: none when Cesium's requests
// are simple ones), "blocked" (requests refused: anything not on the two servers), "errors" (the
// page's errors), "metadata" (the provider reads the tiles' metadata extension); with --screenshot also "rendered" (every tile in view loaded) and "low",
// "high" (the heights the colour ramp spans). Exits 1 when the page fails.
import { readFileSync, existsSync, statSync } from 'node:fs';
import { createServer } from 'node:http';
import { createRequire } from 'node:module';
import { extname, join, resolve, sep } from 'node:path';
import { gzipSync } from 'node:zlib';

function parseArguments(argv) {
  const o = { size: '800x600', chromium: '/usr/bin/chromium', gzip: false, options: '{}',
    points: [] };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === '--gzip') o.gzip = true;
    else if (['--modules', '--terrain', '--screenshot', '--size', '--chromium', '--options'].includes(a))
      o[a.slice(2)] = argv[++i];
    else if (/^-?[\d.]+,-?[\d.]+$/.test(a)) o.points.push(a.split(',').map(Number));
    else throw new Error(`unknown argument: ${a}`);
  }
  if (!o.modules || !o.terrain) throw new Error('--modules and --terrain are required');
  const [width, height] = o.size.split('x').map(Number);
  return { ...o, width, height, options: JSON.parse(o.options) };
}

const contentTypes = {
  '.terrain': 'application/vnd.quantized-mesh',
  '.json': 'application/json',
  '.js': 'text/javascript',
  '.css': 'text/css',
  '.html': 'text/html; charset=utf-8',
  '.wasm': 'application/wasm',
  '.png': 'image/png',
  '.jpg': 'image/jpeg',
  '.svg': 'image/svg+xml',
  '.glb': 'model/gltf-binary',
  '.ktx2': 'image/ktx2',
};

// A static server on 127.0.0.1 (a free port) of ROOT's files under PREFIX, and PAGE at /. With
// CORS, it answers any origin, the preflight too; with GZIP, it compresses every file for clients
// that accept it. COUNTS tallies the .terrain requests, those answered gzipped, the preflights.
function staticServer(root, { prefix = '/', cors, gzip, page, counts }) {
  const server = createServer((request, response) => {
    const headers = {};
    if (cors) {
      headers['Access-Control-Allow-Origin'] = '*';
      headers['Access-Control-Allow-Headers'] = '*';
    }
    if (request.method === 'OPTIONS') {
      counts.preflights += 1;
      response.writeHead(204, headers).end();
      return;
    }
    const path = decodeURIComponent(new URL(request.url, 'http://localhost').pathname);
    if (page && path === '/') {
      response.writeHead(200, { ...headers, 'Content-Type': contentTypes['.html'] }).end(page);
      return;
    }
    const file = resolve(root, '.' + path.slice(prefix.length - 1));
    const inside = path.startsWith(prefix) && (file + sep).startsWith(resolve(root) + sep);
    if (!inside || !existsSync(file) || !statSync(file).isFile()) {
      response.writeHead(404, headers).end();
      return;
    }
    let body = readFileSync(file);
    headers['Content-Type'] = contentTypes[extname(file)] ?? 'application/octet-stream';
    const tile = extname(file) === '.terrain';
    if (tile) counts.tiles += 1;
    if (gzip) {
      headers.Vary = 'Accept-Encoding';
      if (/\bgzip\b/.test(request.headers['accept-encoding'] ?? '')) {
        body = gzipSync(body);
        headers['Content-Encoding'] = 'gzip';
        if (tile) counts.gzipped += 1;
      }
    }
    response.writeHead(200, headers).end(body);
  });
  return new Promise((done) =>
    server.listen(0, '127.0.0.1', () =>
      done({ server, origin: `http://127.0.0.1:${server.address().port}` })));
}

const page = `<!DOCTYPE html>
<html><head><meta charset="utf-8">
<link rel="stylesheet" href="/cesium/Widgets/widgets.css">
<style>html, body, #view { margin: 0; width: 100%; height: 100%; overflow: hidden; }</style>
<script>window.CESIUM_BASE_URL = '/cesium/';</script>
<script src="/cesium/Cesium.js"></script>
</head><body><div id="view"></div><div id="credits" style="display: none"></div></body></html>`;

// In the page: the terrain provider and the samples; with RENDER, a widget looking down on the
// data's bounds, tinted by height with a contour every 2 m and lit from the north-west by the
// tiles' normals, drawn until every tile in view has loaded.
async function inPage({ terrainUrl, options, points, bounds, render }) {
  const C = window.Cesium;
  // The globe's material: a colour ramp from LOW to HIGH metres, dark contour lines every 2 m.
  function heightMaterial(C, low, high) {
    const ramp = document.createElement('canvas');
    ramp.width = 256;
    ramp.height = 1;
    const pen = ramp.getContext('2d');
    const gradient = pen.createLinearGradient(0, 0, 256, 0);
    gradient.addColorStop(0, '#2f6b3a');
    gradient.addColorStop(0.5, '#c9b36b');
    gradient.addColorStop(1, '#f2efe6');
    pen.fillStyle = gradient;
    pen.fillRect(0, 0, 256, 1);
    return new C.Material({
      fabric: {
        type: 'TincdtHeights',
        materials: {
          contours: { type: 'ElevationContour', uniforms: { spacing: 2, width: 1,
            color: new C.Color(0.15, 0.12, 0.1, 1) } },
          ramp: { type: 'ElevationRamp', uniforms: { image: ramp, minimumHeight: low,
            maximumHeight: high } },
        },
        components: {
          diffuse: 'contours.alpha == 0.0 ? ramp.diffuse : contours.diffuse',
          alpha: 'max(contours.alpha, ramp.alpha)',
        },
      },
      translucent: false,
    });
  }

  // The heights Cesium draws beyond the data, on a 180 x 180 grid over three times its bounds
  // less the bounds: their range and "step", the largest difference between neighbours on the grid
  // (about 1/60 of the data's width apart), the wall where tiles of two levels meet.
  function heightsBeyond(C, globe, [west, south, east, north]) {
    const n = 180;
    const w = east - west, h = north - south;
    const grid = [];
    for (let i = 0; i < n; ++i) {
      grid.push([]);
      for (let j = 0; j < n; ++j) {
        const lon = west - w + (3 * w * i) / (n - 1), lat = south - h + (3 * h * j) / (n - 1);
        const inside = lon >= west && lon <= east && lat >= south && lat <= north;
        const height = inside ? undefined : globe.getHeight(C.Cartographic.fromDegrees(lon, lat));
        grid[i].push(height);
      }
    }
    let low = Infinity, high = -Infinity, step = 0;
    for (let i = 0; i < n; ++i)
      for (let j = 0; j < n; ++j) {
        const a = grid[i][j];
        if (a === undefined) continue;
        low = Math.min(low, a);
        high = Math.max(high, a);
        for (const b of [grid[i + 1]?.[j], grid[i][j + 1]])
          if (b !== undefined) step = Math.max(step, Math.abs(a - b));
      }
    return { low, high, step };
  }

  const provider = await C.CesiumTerrainProvider.fromUrl(terrainUrl, options);
  const positions = points.map(([lon, lat]) => C.Cartographic.fromDegrees(lon, lat));
  const sampled = await C.sampleTerrainMostDetailed(provider, positions, true);
  const heights = sampled.map((p) => (Number.isFinite(p.height) ? p.height : null));
  // After sampling: with metadataAvailability, Cesium learns the levels from the tiles it loads.
  const levels = positions.map((p) => provider.availability.computeMaximumLevelAtPosition(p));
  const metadata = provider.hasMetadata;
  if (!render) return { heights, levels, metadata };

  const [west, south, east, north] = bounds;
  const grid = [];
  for (let i = 0; i <= 8; ++i)
    for (let j = 0; j <= 8; ++j)
      grid.push(C.Cartographic.fromDegrees(west + ((east - west) * i) / 8,
        south + ((north - south) * j) / 8));
  const gridHeights = (await C.sampleTerrainMostDetailed(provider, grid)).map((p) => p.height);
  const low = Math.min(...gridHeights), high = Math.max(...gridHeights);

  const widget = new C.CesiumWidget('view', {
    baseLayer: false,
    terrainProvider: provider,
    skyBox: false,
    skyAtmosphere: false,
    creditContainer: 'credits',
    msaaSamples: 1,
  });
  const scene = widget.scene;
  scene.backgroundColor = C.Color.fromCssColorString('#1d2a38');
  scene.fog.enabled = false;
  scene.globe.showGroundAtmosphere = false;
  scene.globe.enableLighting = true;
  scene.globe.material = heightMaterial(C, low, high);
  const centre = C.Cartesian3.fromDegrees((west + east) / 2, (south + north) / 2, (low + high) / 2);
  const enu = C.Transforms.eastNorthUpToFixedFrame(centre);
  scene.light = new C.DirectionalLight({
    direction: C.Matrix4.multiplyByPointAsVector(enu, new C.Cartesian3(0.5, -0.5, -0.7),
      new C.Cartesian3()),
  });
  const span = C.Cartesian3.distance(C.Cartesian3.fromDegrees(west, south),
    C.Cartesian3.fromDegrees(east, north));
  widget.camera.lookAt(centre, new C.HeadingPitchRange(0, C.Math.toRadians(-55), span * 0.9));
  widget.camera.lookAtTransform(C.Matrix4.IDENTITY);

  let settled = 0;
  const deadline = performance.now() + 30000;
  while (settled < 3 && performance.now() < deadline) {
    await new Promise((frame) => requestAnimationFrame(frame));
    settled = scene.globe.tilesLoaded ? settled + 1 : 0;
  }
  return { heights, levels, metadata, rendered: settled >= 3, low, high,
    beyond: heightsBeyond(C, scene.globe, bounds) };
}

async function main() {
  const o = parseArguments(process.argv.slice(2));
  const require = createRequire(join(resolve(o.modules), 'resolve-from-here.js'));
  const { chromium } = require('playwright-core');
  const counts = { tiles: 0, gzipped: 0, preflights: 0 };
  const cesiumBuild = join(resolve(o.modules), 'cesium', 'Build', 'Cesium');
  const site = await staticServer(cesiumBuild, { prefix: '/cesium/', page, counts });
  const tiles = await staticServer(o.terrain, { cors: true, gzip: o.gzip, counts });
  const layer = JSON.parse(readFileSync(join(o.terrain, 'layer.json'), 'utf8'));

  // Playwright starts Chromium with a new, empty profile of its own (--user-data-dir).
  const browser = await chromium.launch({
    executablePath: o.chromium,
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--enable-unsafe-swiftshader'],
  });
  const blocked = [];
  const errors = [];
  let result;
  try {
    const context = await browser.newContext({ viewport: { width: o.width, height: o.height } });
    await context.route('**/*', (route) => {
      const url = route.request().url();
      if (url.startsWith(site.origin + '/') || url.startsWith(tiles.origin + '/')) route.continue();
      else {
        blocked.push(url);
        route.abort();
      }
    });
    const tab = await context.newPage();
    tab.on('pageerror', (e) => errors.push(String(e)));
    tab.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
    await tab.goto(`${site.origin}/`);
    result = await tab.evaluate(inPage, {
      terrainUrl: `${tiles.origin}/`,
      options: o.options,
      points: o.points,
      bounds: layer.bounds,
      render: Boolean(o.screenshot),
    });
    if (o.screenshot) await tab.screenshot({ path: o.screenshot });
  } finally {
    await browser.close();
    site.server.close();
    tiles.server.close();
  }
  process.stdout.write(JSON.stringify({ ...result, ...counts, blocked, errors }) + '\n');
}

main().catch((e) => {
  process.stderr.write(`cesium_sample.mjs: ${e.stack ?? e}\n`);
  process.exit(1);
});
