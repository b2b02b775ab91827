// martini (npm @mapbox/martini, the RTIN of Evans et al.) on height grids, one line a grid:
//   MARTINI grid=NAME vertices=V triangles=T border=B max_error=E run_s=S [tile_error=F]
// with B the vertices on the grid's four sides and E the largest difference, over every sample,
// between the grid and the mesh (martini's own measure, checked here rather than trusted). With
// GRID.f32=TILE.terrain, F is the same measure for that quantized-mesh tile (decoded by
// @here/quantized-mesh-decoder) when the grid samples the tile's rectangle, corners on corners.
// Usage: node martini_tiles.mjs NODE_MODULES SIZE MAX_ERROR GRID.f32[=TILE.terrain]...
// NODE_MODULES: the folder holding @mapbox/martini (../shared/bench/node/node_modules);
// GRID.f32: SIZE x SIZE float32, row-major, first row north; SIZE = 2^k + 1.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { basename, join } from 'node:path';

const [nodeModules, sizeText, errorText, ...grids] = process.argv.slice(2);
if (!grids.length) {
  process.stderr.write('usage: node martini_tiles.mjs NODE_MODULES SIZE MAX_ERROR GRID.f32...\n');
  process.exit(2);
}
const require = createRequire(join(nodeModules, 'resolve-from-here.js'));
const Martini = require('@mapbox/martini');
const decode = require('@here/quantized-mesh-decoder').default;
const size = Number(sizeText), maxError = Number(errorText);
const martini = new Martini(size);

// The mesh's height at every sample, linear over its triangles, against the grid's.
function meshError(grid, vertices, triangles) {
  let worst = 0;
  for (let t = 0; t < triangles.length; t += 3) {
    const [ax, ay, bx, by, cx, cy] = [0, 1, 2].flatMap((k) => [vertices[2 * triangles[t + k]],
      vertices[2 * triangles[t + k] + 1]]);
    const za = grid[ay * size + ax], zb = grid[by * size + bx], zc = grid[cy * size + cx];
    const area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    for (let y = Math.min(ay, by, cy); y <= Math.max(ay, by, cy); ++y)
      for (let x = Math.min(ax, bx, cx); x <= Math.max(ax, bx, cx); ++x) {
        const wa = ((bx - x) * (cy - y) - (by - y) * (cx - x)) / area;
        const wb = ((cx - x) * (ay - y) - (cy - y) * (ax - x)) / area;
        const wc = 1 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        worst = Math.max(worst, Math.abs(wa * za + wb * zb + wc * zc - grid[y * size + x]));
      }
  }
  return worst;
}

// The decoded tile's height at every sample, linear in its quantized u, v (0..32767, v north)
// over its triangles, against the grid's: sample (x, y) is at u = x * 32767 / (SIZE - 1),
// v = (SIZE - 1 - y) * 32767 / (SIZE - 1).
function tileError(grid, path) {
  const file = readFileSync(path);
  const tile = decode(file.buffer.slice(file.byteOffset, file.byteOffset + file.byteLength));
  const n = tile.vertexData.length / 3, q = 32767, step = q / (size - 1);
  const { minHeight, maxHeight } = tile.header;
  const d = tile.vertexData, t = tile.triangleIndices;
  const u = (k) => d[k], v = (k) => d[k + n];
  const h = (k) => minHeight + (maxHeight - minHeight) * d[k + 2 * n] / q;
  let worst = 0, covered = 0;
  for (let k = 0; k < t.length; k += 3) {
    const [a, b, c] = [t[k], t[k + 1], t[k + 2]];
    const area = (u(b) - u(a)) * (v(c) - v(a)) - (v(b) - v(a)) * (u(c) - u(a));
    const x0 = Math.ceil(Math.min(u(a), u(b), u(c)) / step);
    const x1 = Math.floor(Math.max(u(a), u(b), u(c)) / step);
    const r0 = Math.ceil(Math.min(v(a), v(b), v(c)) / step);
    const r1 = Math.floor(Math.max(v(a), v(b), v(c)) / step);
    for (let r = r0; r <= r1; ++r)
      for (let x = x0; x <= x1; ++x) {
        const pu = x * step, pv = r * step;
        const wa = ((u(b) - pu) * (v(c) - pv) - (v(b) - pv) * (u(c) - pu)) / area;
        const wb = ((u(c) - pu) * (v(a) - pv) - (v(c) - pv) * (u(a) - pu)) / area;
        const wc = 1 - wa - wb;
        if (wa < -1e-12 || wb < -1e-12 || wc < -1e-12) continue;
        ++covered;
        const z = wa * h(a) + wb * h(b) + wc * h(c);
        worst = Math.max(worst, Math.abs(z - grid[(size - 1 - r) * size + x]));
      }
  }
  if (covered < size * size) process.stderr.write(`${path}: samples in no triangle\n`);
  return worst;
}

for (const arg of grids) {
  const [file, tilePath] = arg.split('=');
  const buf = readFileSync(file);
  if (buf.length !== size * size * 4) {
    process.stderr.write(`${file}: ${buf.length} bytes, want ${size * size * 4}\n`);
    process.exit(1);
  }
  const grid = new Float32Array(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.length));
  const t0 = process.hrtime.bigint();
  const { vertices, triangles } = martini.createTile(grid).getMesh(maxError);
  const s = Number(process.hrtime.bigint() - t0) / 1e9;
  let border = 0;
  for (let i = 0; i < vertices.length; i += 2) {
    const x = vertices[i], y = vertices[i + 1];
    if (x === 0 || y === 0 || x === size - 1 || y === size - 1) ++border;
  }
  const e = meshError(grid, vertices, triangles);
  process.stdout.write(`MARTINI grid=${basename(file, '.f32')} vertices=${vertices.length / 2} ` +
    `triangles=${triangles.length / 3} border=${border} max_error=${e.toFixed(4)} ` +
    `run_s=${s.toFixed(6)}` +
    (tilePath ? ` tile_error=${tileError(grid, tilePath).toFixed(4)}` : '') + '\n');
}
