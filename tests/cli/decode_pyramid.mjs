// Decodes every tile of a quantized-mesh pyramid with @here/quantized-mesh-decoder, a reader
// independent of tincdt, and prints one line a tile: "Z/X/Y VERTICES TRIANGLES WEST SOUTH EAST
// NORTH NORMALS METADATA_BYTES", the counts it read (side lists, octvertexnormals entries, the
// metadata's JSON length). Exits 1 on a tile it cannot read or whose indices are out of range.
// Usage: node decode_pyramid.mjs NODE_MODULES DIR
import { readFileSync, readdirSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join, relative } from 'node:path';

const [nodeModules, dir] = process.argv.slice(2);
const require = createRequire(join(nodeModules, 'resolve-from-here.js'));
const decode = require('@here/quantized-mesh-decoder').default;

function tiles(folder) {
  const out = [];
  for (const entry of readdirSync(folder, { withFileTypes: true })) {
    const path = join(folder, entry.name);
    if (entry.isDirectory()) out.push(...tiles(path));
    else if (entry.name.endsWith('.terrain')) out.push(path);
  }
  return out;
}

let failed = false;
for (const path of tiles(dir).sort()) {
  const file = readFileSync(path);
  const buffer = file.buffer.slice(file.byteOffset, file.byteOffset + file.byteLength);
  const tile = decode(buffer);
  const n = tile.vertexData.length / 3;
  const inRange = (list) => Array.from(list).every((i) => i < n);
  const quantized = Array.from(tile.vertexData).every((q) => q <= 32767);
  if (!inRange(tile.triangleIndices) || !quantized) {
    process.stderr.write(`${path}: index or quantized value out of range\n`);
    failed = true;
  }
  const ext = tile.extensions;
  const metadata = ext.metadata ? JSON.stringify(ext.metadata).length : 0;
  process.stdout.write([relative(dir, path).replace(/\.terrain$/, ''), n,
    tile.triangleIndices.length / 3, tile.westIndices.length, tile.southIndices.length,
    tile.eastIndices.length, tile.northIndices.length,
    ext.vertexNormals ? ext.vertexNormals.length / 2 : 0, metadata].join(' ') + '\n');
}
process.exit(failed ? 1 : 0);
