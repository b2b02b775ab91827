// Decodes one quantized-mesh tile with @here/quantized-mesh-decoder, a reader independent of
// tincdt, and prints what it read as one JSON object: the header, the vertex count, the decoded
// u, v and height arrays, the decoded triangle indices, the four side lists and the extensions.
// Usage: node decode_tile.mjs NODE_MODULES TILE
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';

const [nodeModules, tilePath] = process.argv.slice(2);
const require = createRequire(join(nodeModules, 'resolve-from-here.js'));
const decode = require('@here/quantized-mesh-decoder').default;

// A fresh ArrayBuffer: the decoder makes typed arrays at file offsets, which must be aligned.
const file = readFileSync(tilePath);
const buffer = file.buffer.slice(file.byteOffset, file.byteOffset + file.byteLength);
const tile = decode(buffer);

const n = tile.vertexData.length / 3;
const list = (typed) => Array.from(typed);
const extensions = tile.extensions;
process.stdout.write(JSON.stringify({
  header: tile.header,
  vertexCount: n,
  u: list(tile.vertexData.subarray(0, n)),
  v: list(tile.vertexData.subarray(n, 2 * n)),
  height: list(tile.vertexData.subarray(2 * n, 3 * n)),
  indices: list(tile.triangleIndices),
  west: list(tile.westIndices),
  south: list(tile.southIndices),
  east: list(tile.eastIndices),
  north: list(tile.northIndices),
  extensions: {
    vertexNormals: extensions.vertexNormals ? list(extensions.vertexNormals) : null,
    metadata: extensions.metadata ?? null,
  },
}) + '\n');
